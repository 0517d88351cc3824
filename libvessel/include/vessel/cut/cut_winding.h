#pragma once

#include "vessel/cut/cut_graph.h"
#include "vessel/cut/cut_plan.h"

#include <limits>
#include <memory>
#include <vector>

namespace vessel {

//! How a cut's winding around its vessel is measured (WindingMeter).
struct WindingOptions
{
    //! Half-width of a ring, in mean edge lengths: the ring through a vertex p is the connected
    //! band of vertices whose longitudinal value lies within band x mean edge of p's. 0.5 (as
    //! the shared yardstick seamwinding.py) holds one vertex per column on a regular tube.
    double band = 0.5;
    //! Fewer vertices than this and the band is no ring (the end of a loop, a thin strip).
    int min_ring_vertices = 8;
    //! A band counts as a ring only if the spread (std / mean) of its vertices' distances to
    //! the local axis is below this; junctions and aneurysm sacs are not round and are skipped.
    double max_spread = 0.25;
    //! ... and only if the cut's vertex lies at least this fraction of the mean radius off the
    //! axis (an angle is ill-defined near the axis).
    double min_offset = 0.5;
    //! \throw InvalidInputError naming the bad field.
    void validate() const;
};

//! How far one cut winds around its vessel.
struct PathWinding
{
    //! Signed angle (degrees) gained around the vessel from the cut's first to its last
    //! measured vertex, in a rotation-minimizing frame: 0 for a cut that keeps to one side
    //! (a line of minimal curvature on a canal surface), 360 for one full turn.
    double winding_deg = 0.0;
    double span_deg = 0.0;  //!< largest minus smallest cumulative angle along the cut
    int measured = 0;       //!< path vertices that lie on a clean ring (the others add 0)
    int vertices = 0;       //!< vertices of the path
    double length = 0.0;    //!< 3D length of the path
};

//! \brief The part of a cut's winding read where the wall does not close round one axis
//! (WindingMeter::measure()'s `open`).
//!
//! The ring test (WindingOptions::max_spread) skips a band that is not round, as at most
//! junctions, but a band can be round enough and still not close round the vessel: its
//! vertices leave an arc of the circle round its axis empty. So it is at the neck of a sac,
//! where the harmonic coordinate's level runs out over the sac, and where a coarse or
//! irregular mesh breaks the band (an edge longer than the band is wide carries it across
//! no vertex). There the angle round the vessel is not defined by the wall, yet measure()
//! reads one from the open band's centroid, which lies off the vessel's axis.
struct OpenStretch
{
    double length = 0.0;    //!< 3D length of the cut's edges with an end on an open band
    double turn_deg = 0.0;  //!< sum of |angle| that measure() adds at vertices on open bands
};

//! \brief Ring-based winding of cuts (the library's version of the yardstick seamwinding.py).
//!
//! At every vertex p of a cut: the ring through p (WindingOptions::band) of the harmonic
//! longitudinal coordinate u; its centroid and the mean gradient of u over it give the local
//! vessel axis; the angle of p around that axis is measured against a reference direction that
//! is parallel-transported from ring to ring by the minimal rotation between consecutive axes
//! (a discrete rotation-minimizing frame). Where the band is no clean ring the frame restarts
//! and that stretch adds nothing. O(ring size) per cut vertex, once per vertex (a vertex that
//! another measured path passed reuses its ring); the meter keeps three |V| scratch arrays
//! (marks, cached gradients, ring slots), so measure many cuts with one meter.
class WindingMeter
{
public:
    //! \param mesh the uncut surface (cut copies keep the first |V| vertices, but rings must
    //! close around the vessel). \param longitudinal |V| values, e.g. harmonic_longitudinal().
    //! \throw InvalidInputError if sizes disagree or options are invalid.
    WindingMeter(const Mesh& mesh, const Eigen::VectorXd& longitudinal,
                 const WindingOptions& options = {});

    //! \brief The same meter (the same figures), walking its rings over the arcs of \p graph
    //! (the mesh's edges, in the order vv_range() visits them) instead of OpenMesh's
    //! circulators. For a meter inside plan_cuts(), which has both at hand.
    //! \param mean_edge mean_edge_length(graph.mesh()), which the caller already computed.
    //! \throw InvalidInputError as above, or if \p mean_edge is negative or not finite.
    WindingMeter(const CutGraph& graph, const Eigen::VectorXd& longitudinal, double mean_edge,
                 const WindingOptions& options = {});

    //! \brief The graph meter with each vertex's direction of increasing u given instead of
    //! computed at the first ring that reaches it (rings along a cut reach most of its vessel:
    //! on the 300k carotid phantom these gradients were half of the default cut stage).
    //! plan_cuts() passes minus its stream field, descent_direction(mesh, u), which the cut
    //! route computes anyway; the figures then agree with the other constructors' to rounding
    //! (the same area-weighted gradient of u, summed per face instead of per corner).
    //! \param axis_direction |V| x 3 rows `v.idx()`: the unit direction in which u increases
    //! at each vertex (zero where u has no gradient).
    //! \throw InvalidInputError as above, or if \p axis_direction has not |V| rows.
    WindingMeter(const CutGraph& graph, const Eigen::VectorXd& longitudinal, double mean_edge,
                 const Eigen::MatrixX3d& axis_direction, const WindingOptions& options = {});

    //! \brief How far \p path winds round its vessel.
    //! \param open if set, also where that reading comes from bands that do not close round
    //! their axis (OpenStretch), in the same walk over the path's rings: a measured vertex's
    //! band is open when the largest angle between consecutive band vertices round the band's
    //! axis exceeds both 60 degrees and four times their mean angle (360 / band vertices). On
    //! a closed tube the largest is about twice the mean, and a band of a few vertices round a
    //! thin vessel still closes. For the report; the planner does not ask for it.
    //! \throw InvalidInputError if the path leaves the mesh's vertex range.
    PathWinding measure(const CutPath& path, OpenStretch* open = nullptr) const;

    //! The same for a path given as its vertices, in order.
    PathWinding measure(const std::vector<VertexHandle>& path, OpenStretch* open = nullptr) const;

    //! \brief The signed angle (radians) measure() adds when a path reaches \p w with \p last
    //! the path's last measured vertex: the angle around w's ring axis from last's offset,
    //! carried to w's ring by the minimal rotation between the two axes, to w's offset.
    //! NaN when w is not measured (no clean ring, or too near the axis): the path's frame
    //! then waits at \p last. 0 when \p last is invalid (the path's first measured vertex), or
    //! when \p gap (the path passed unmeasured vertices since \p last) and \p last lies farther
    //! from w than \p bridge radii of its ring (the frame restarts). measure() restarts after
    //! every vertex it does not measure (\p bridge 0, as the yardstick seamwinding.py), so it is
    //! the sum of these steps; a search that carries `last` along bounds a path's winding as the
    //! meter reads it (winding_bounded_path()). With \p bridge > 0 the turn across a short gap
    //! (a band that fails the spread test by discretization noise) counts too, so that a search
    //! cannot turn there unseen; across a junction or a sac, longer than a radius, the frame
    //! still restarts.
    double step(VertexHandle last, VertexHandle w, bool gap, double bridge = 0.0) const;

    //! \brief The angle around the vessel (radians) this meter reads per unit displacement at
    //! \p v: (a x d) / |d|^2 with a the axis of v's ring and d the offset of v from it, so that
    //! a step s from v turns by about angular_rate(v) . s (to first order, ignoring the turn
    //! of the frame between rings). Zero where measure() adds nothing: v's band is no ring (a
    //! junction, a sac, an end) or v lies too near the axis. Cached like the rings.
    Eigen::Vector3d angular_rate(VertexHandle v) const;

    //! The band of u through a vertex as the meter fits it (cached like the rings).
    struct Band
    {
        bool ring = false;    //!< a clean ring: measure() measures the band's vertices
        double radius = 0.0;  //!< mean distance of its vertices from the fitted axis
        //! |mean| of its vertices' unit gradients of u: about 1 where the band closes round
        //! one axis (a tube), low where they point apart (a sac's wall, where the band runs
        //! round the bulge); NaN for a band of fewer than WindingOptions::min_ring_vertices.
        double coherence = 0.0;
    };
    //! \brief The band through \p v: what the ring test saw there, for a caller that must
    //! tell where "around the vessel" is undefined (route_aligned.cpp, the passage across a sac).
    Band band(VertexHandle v) const;

    //! \brief Rings fitted ahead on a second thread while one search asks this meter for its
    //! steps (winding_bounded_path()'s `settled`): hint(v) for each vertex the search settles
    //! queues the vertices within two edges of v, whose rings the search asks for next. The
    //! figures are the same bits as without it (a ring does not depend on the thread that
    //! fits it, and the meter keeps the rings in the order they are asked for); only the time
    //! changes (docs/benchmarks.md, "The cut stages alone"). Does nothing for a
    //! meter whose axis directions were not given (the fourth constructor: the others fit
    //! them lazily). While it lives the meter must be used by the calling thread alone.
    class Prefetch
    {
    public:
        explicit Prefetch(const WindingMeter& meter);
        ~Prefetch();
        Prefetch(const Prefetch&) = delete;
        Prefetch& operator=(const Prefetch&) = delete;
        //! The search settled \p v.
        void hint(VertexHandle v);

    private:
        friend class WindingMeter;
        struct State;
        std::unique_ptr<State> state_;
    };

private:
    struct Ring;
    // Checks the options and the field's size, and sizes the scratch; the public constructors
    // then set the band's half width.
    WindingMeter(const Mesh& mesh, const CutGraph* graph, const Eigen::VectorXd& longitudinal,
                 const WindingOptions& options);
    //! The ring through p into \p ring, the band's search marked in \p stamp with \p round
    //! (a thread's own marks: Prefetch fits rings on another thread).
    bool ring_at(VertexHandle p, Ring& ring, int* stamp, int round) const;
    //! Whether \p ring (a clean ring: ring_at() true) leaves an arc round its axis empty
    //! (measure()'s \p open).
    bool ring_open(const Ring& ring) const;
    //! The vertices of \p path, its start first.
    std::vector<VertexHandle> path_vertices(const CutPath& path) const;
    struct RingFit;
    //! ring_fit() with RingFit::open set, the ring fitted again only where a fit made without
    //! that test kept no vertices.
    const RingFit& open_tested_fit(VertexHandle p) const;
    //! ring_at()'s answer for p as kept per vertex (\p ring holds the ring's vertices).
    RingFit fit_ring(VertexHandle p, Ring& ring, int* stamp, int round) const;
    //! The unit offset \p d of p from its ring's axis, and the ring; false where measure()
    //! does not measure p.
    bool offset(VertexHandle p, Eigen::Vector3d& d, const RingFit*& fit) const;

    const Mesh& mesh_;
    const CutGraph* graph_ = nullptr;
    //! Each vertex's neighbours in voh_range() order (compressed rows), which the rings walk:
    //! a quarter of the memory of the graph's arcs (head, halfedge, weight), and no circulator.
    std::vector<int> neighbour_start_, neighbours_;
    Eigen::VectorXd u_;  // a copy: the meter may outlive the caller's field
    WindingOptions options_;
    double half_width_ = 0.0;
    mutable std::vector<int> stamp_;  // BFS marks, by vertex
    mutable int round_ = 0;
    //! Unit gradient of u per vertex, computed when a ring first reaches the vertex (NaN
    //! until then; or all given at construction): consecutive rings of a cut share most of
    //! their vertices.
    mutable std::vector<Eigen::Vector3d> direction_;
    //! ring_at()'s answer per vertex once asked (plan_cuts() measures two candidate cuts from
    //! one start, which share part of their vertices): index into fits_, -1 until then.
    struct RingFit
    {
        Eigen::Vector3d centre, axis;
        double radius = 0.0;
        double coherence = std::numeric_limits<double>::quiet_NaN();  //!< Band::coherence
        bool ok = false;
        signed char open = -1;  //!< ring_open() once asked (open_tested_fit()), else -1
    };
    //! \p scratch: the ring, made with it the first time p is asked.
    const RingFit& ring_fit(VertexHandle p, Ring& scratch) const;
    mutable std::vector<int> fit_of_;
    //! angular_rate()'s ring per vertex: its own, or that of the first ring whose inner half
    //! (u within half the band's half width) held it (index into fits_, -1 until asked).
    mutable std::vector<int> rate_of_;
    mutable std::vector<RingFit> fits_;
    bool directions_given_ = false;  // all of direction_ set at construction (graph_ set too)
    mutable Prefetch::State* ahead_ = nullptr;  // the live Prefetch's, if any
};

//! Seam-level figures over cuts.
struct SeamWinding
{
    double mean_abs_deg = 0.0;  //!< length-weighted mean of |winding_deg|
    double max_abs_deg = 0.0;   //!< largest |winding_deg|
};

//! Length-weighted mean and max of per-cut |winding| (all zero when there are none).
SeamWinding seam_winding(const std::vector<PathWinding>& paths);

}  // namespace vessel
