#pragma once

#include "vessel/cut/boundary.h"
#include "vessel/cut/cut_graph.h"
#include "vessel/cut/endpoints.h"

#include <memory>
#include <optional>
#include <vector>

namespace vessel {

class CutRoutePolicy;  // cut_route.h
class CutJoinPolicy;   // cut_join.h

//! How a cut runs from its outlet to its end: the built-in route policies (cut_route.h).
enum class CutRoute
{
    ShortestPath,  //!< the paper's rule: the cheapest path in the cut graph
    //! Trace a streamline of a vessel direction field from the start of the cheapest path
    //! toward the root, then take the cheapest path inside a narrow band around it; the cut
    //! then cannot drift from an exactly aligned curve by more than the band. Cuts whose
    //! streamline does not arrive (a sink, a cycle, another loop) keep the cheapest path.
    Streamline,
    //! Per cut, both of the above, keeping the one that winds less around the vessel
    //! (WindingMeter of cut_winding.h, when plan_cuts() gets the longitudinal coordinate;
    //! CutPlanOptions::winding_min_gain_deg, winding_max_alignment_loss), or else the one
    //! better aligned with the stream field (path_alignment() of cut_metrics.h, windowed |cos|
    //! against the field); ties keep the cheapest path. A rule per cut, not per mesh: the
    //! cheapest path where it already follows the vessel, the traced one where it drifts or
    //! winds (docs/design.md, "Per-cut route choice"). With StreamField::Harmonic and the
    //! vessel direction z given to plan_cuts(), a natural cut whose angle spans more than twice
    //! winding_target_deg is also offered the streamline of z, kept if it is natural, winds no
    //! more (or within the target), spans less by winding_min_gain_deg and is as aligned
    //! within winding_max_alignment_loss: the discrete harmonic descent drifts round a long
    //! coarse tube, z does not.
    Aligned,
};

//! The field CutRoute::Streamline traces (flatten() computes it).
enum class StreamField
{
    Direction,  //!< the vessel direction z of the travel cost (DirectionOptions)
    Harmonic,   //!< descent of harmonic_longitudinal() (cut_metrics.h): smooth across junctions
};

//! Where a later cut (every outlet but the largest) ends on the cuts made before it
//! (docs/design.md, "Where later cuts join"): the built-in join policies (cut_join.h).
enum class CutJoin
{
    //! On whichever cut vertex the cheapest path reaches first (the paper's rule, read
    //! literally). With the vessel direction's cost a lateral step spread along the parent is
    //! almost free, so a branch's cut can run down the parent beside an earlier cut and join it
    //! far from its bifurcation; the map then shows a sliver of the parent's wall.
    Cheapest,
    //! The paper's wording: on a cut vertex closest to the outlet, i.e. within (1 + join_slack)
    //! x the edge-path distance of the closest one plus the outlet's perimeter; the cheapest
    //! path to those. A wide outlet's perimeter still lets its cut run beside the tree.
    Closest,
    //! The cheapest path, cut back where it starts to run beside the cut tree (default): at its
    //! first vertex within join_reach outlet radii of the tree (edge-path distance) from which
    //! the path still runs more than join_excess outlet radii further than that distance, and
    //! joined to the tree there over the shortest bridge. The branch part of the path is the
    //! cheapest path's own.
    Approach,
};

struct CutPlanOptions
{
    //! How each cut runs (default CutRoute::Aligned: no valid real mesh's seam less aligned
    //! than with either route alone; docs/design.md, "Per-cut route choice").
    CutRoute route = CutRoute::Aligned;
    //! A researcher's own cut route (cut_route.h); when set it replaces `route`.
    std::shared_ptr<const CutRoutePolicy> router;
    //! CutRoute::Streamline and Aligned: the field traced (the harmonic descent measured best).
    StreamField stream_field = StreamField::Harmonic;
    //! CutRoute::Streamline: half-width, in edge rings (>= 0), of the band around the faces the
    //! streamline crosses in which the cut is taken (0 = those faces' corners only, measured
    //! best; wider bands let the cut wander further from the line).
    int band_rings = 0;
    //! CutRoute::Streamline: a later cut's streamline stops once it comes within this many
    //! edge rings (>= 0) of an earlier cut, or else is cut back to where it first comes within
    //! this many mean edge lengths of its nearest approach to the cut tree; the cut joins there,
    //! over the shortest bridge, instead of running beside the earlier cut.
    int join_rings = 3;
    //! Where the cheapest path of a later cut ends (CutStep::cheapest(): the route of
    //! CutRoute::ShortestPath, the cheapest candidate of CutRoute::Aligned, the fallback of
    //! CutRoute::Streamline); a traced cut joins by join_rings.
    CutJoin join = CutJoin::Approach;
    //! A researcher's own join policy (cut_join.h); when set it replaces `join`.
    std::shared_ptr<const CutJoinPolicy> joiner;
    //! CutJoin::Closest: the later cut may end on any cut vertex whose edge-path distance from
    //! the outlet is within (1 + join_slack) x the closest one's plus the outlet's perimeter
    //! (>= 0); the cheapest path among them is taken.
    double join_slack = 0.25;
    //! CutJoin::Approach: the cut-back vertex lies within this many outlet radii (perimeter /
    //! 2 pi; >= 0) of the cut tree. 4 reaches the runs beside the tree seen on the real meshes
    //! and the carotid phantoms (0.5-3.6 radii from it; docs/design.md, "Reach 4, excess 8").
    double join_reach = 4.0;
    //! CutJoin::Approach: a cut is cut back only where its remaining length exceeds its
    //! distance to the tree by more than this many outlet radii (>= 0), so a head-on join or a
    //! short run is kept. Fitted, not derived: 8 lies below the runs it should stop and above
    //! the tails of the Glenn tree's later cuts (docs/design.md, "Reach 4, excess 8").
    double join_excess = 8.0;
    //! CutJoin::Approach, for a path held to one side of its vessel (a winding-bounded route of
    //! natural_cuts; CutJoiner::finish_held()): join_excess for such a path (outlet radii,
    //! >= 0). It cannot turn toward the tree where it comes near it on another side of the
    //! vessel, so a run beside the tree is all it has left there, and one shorter than
    //! join_excess is cut back too. Fitted on the real trees: no later cut runs beside an
    //! earlier one on the vmtk aorta and the SimVascular demo (docs/design.md, "Natural
    //! cuts").
    double join_held_excess = 2.0;
    //! CutRoute::Aligned: the traced path replaces the cheapest one only if its alignment is
    //! higher by more than this (|cos| units, >= 0). Fitted, not derived: it separates the
    //! small gains of cuts that already follow their vessel from those of drifting cuts
    //! (docs/results.md, "Per-cut route choice").
    double aligned_min_gain = 0.015;
    //! CutRoute::Aligned with a longitudinal coordinate: the traced path replaces the cheapest
    //! one if it winds less by more than this many degrees (WindingMeter, end to end) ...
    double winding_min_gain_deg = 15.0;
    //! ... and its alignment with the stream field is at most this much lower (|cos| units).
    //! Both fitted on the real trees: a looser pair switches cuts whose change moves later
    //! cuts and raises the largest winding (docs/results.md, "Winding of the cuts").
    double winding_max_alignment_loss = 0.05;
    //! CutRoute::Aligned with a longitudinal coordinate: a cut that winds more than this many
    //! degrees around its vessel end to end (WindingMeter) is searched again with its signed
    //! winding priced into the arc weights (PathQuery::steer_rate, a Lagrangian relaxation of
    //! "winds at most this much"); the steered path replaces it if it winds less by more than
    //! winding_min_gain_deg and loses at most winding_max_alignment_loss of alignment. With
    //! natural_cuts also the bound of winding_bounded_path(), and a natural route within this
    //! target (as aligned) replaces a natural cut above it whatever it gains. 0 = no
    //! steering. Not with CutJoin::Closest.
    double winding_target_deg = 15.0;
    //! CutRoute::Aligned with a longitudinal coordinate: the bound on a natural cut's winding,
    //! in degrees. Without natural_cuts a cut taken along a streamline (CutPath::traced) is
    //! searched again only if it winds more than this: it cannot drift from an aligned curve
    //! by more than its band (CutRoute::Streamline), so what it winds below this is the
    //! vessel's and the field's, not the graph's; a steered search may move it to another side
    //! of the vessel, where later cuts then join it instead and the branch layout changes with
    //! them. With natural_cuts it is searched again as any cut above winding_target_deg.
    double winding_limit_deg = 45.0;
    //! CutRoute::Aligned with a longitudinal coordinate: hold every cut to winding_limit_deg, end
    //! to end and in span (which bounds each piece between two joins, what the shared yardstick
    //! seamwinding.py measures). A cut that is not natural after the multiplier takes
    //! winding_bounded_path()'s route within +-winding_target_deg (or half the limit) whatever its
    //! alignment (of two natural candidates, the one that winds less); a bounded route that comes
    //! near the tree on another side of the vessel is joined to it with join_held_excess. What it
    //! costs: where a bounded route crosses a junction or a sac (the angle is undefined there) the
    //! seam aligns a little less with the vessel, and the routes change where later cuts join, with
    //! them the branch layout (docs/results.md, "Winding of the cuts", has the figures per real
    //! tree and phantom). CLI `--no-natural-cuts` turns it off.
    bool natural_cuts = true;
    //! Where on its loop each cut starts and the first cut ends (endpoints.h); null =
    //! ImaginaryNodeEndpoints, the paper's cheapest point of the loop.
    std::shared_ptr<const EndpointPolicy> endpoints;
    //! Per-step slack, as a fraction of the mean halfedge weight (>= 0), within which two
    //! routes count as equally cheap; among those the one that winds least around the vessel
    //! is taken. 0 = the plain shortest path, which drifts around the vessel where costs
    //! (nearly) tie (docs/design.md, "Winding-aware tie breaking in Dijkstra").
    double tie_tolerance = 0.1;
    //! \throw InvalidInputError naming the bad field.
    void validate() const;
};

//! One cut, from an outlet loop toward the inlet or an earlier cut.
struct CutPath
{
    int outlet = -1;  //!< index into the loops passed to plan_cuts() (1 = largest outlet)
    int parent = -1;  //!< earlier cut it ends on, or -1 when it ends on the inlet (loop 0)
    std::vector<HalfedgeHandle> halfedges;  //!< outlet -> end, head to tail
    VertexHandle start;                     //!< vertex on the outlet loop
    VertexHandle end;                       //!< vertex on the inlet or on the parent cut
    double cost = 0.0;
    bool traced = false;  //!< taken in the band of a streamline (CutRoute::Streamline)
};

struct CutPlan
{
    std::vector<CutPath> paths;  //!< in the order they were made
    //! Relief cuts (relief_cut.h): dead-end slits from a bulging region to the seam, made after
    //! `paths`; `outlet` is -1. Layouts place `paths` only.
    std::vector<CutPath> relief;
    //! Edges of all paths and relief cuts, each once.
    std::vector<EdgeHandle> seam_edges(const Mesh& mesh) const;
};

//! \brief Angle around the vessel gained per unit displacement: k_max(v) * (n_v x z_v), the
//! lateral direction scaled by the local inverse radius.
//! \param direction |V| x 3 unit vessel direction z. \param k_max |V| max curvature magnitudes.
//! \return |V| x 3, row `v.idx()`.
Eigen::MatrixX3d winding_rate(const Mesh& mesh, const Eigen::MatrixX3d& direction,
                              const Eigen::VectorXd& k_max);

//! \brief Plan the cuts of the method (step 4): the largest outlet to the inlet first, then every
//! other outlet, largest to smallest, to an interior vertex already on a cut; each cut's route
//! from the route policy (CutPlanOptions::route or ::router), where it joins from the join
//! policy (::join or ::joiner). Paths never pass through other boundary loops and never cross
//! earlier cuts, so every loop is opened at exactly one vertex. Where the endpoint policy fixes
//! the inlet's end to one vertex (a viewpoint's far side) and, with CutPlanOptions::natural_cuts
//! and \p longitudinal, a cut then winds or spans more than CutPlanOptions::winding_limit_deg
//! (a vessel turning round the view between the two fixed ends), the plan is made again with
//! the inlet's end free, and the one whose widest cut turns less is returned.
//! \param loops boundary_loops(mesh): loops[0] is the inlet.
//! \param weights evaluate_cost() of the chosen travel cost.
//! \param winding_rate winding_rate(), or an empty matrix to disable drift control.
//! \param stream_field |V| x 3 field toward the root traced by CutRoute::Streamline (see
//! StreamField; with StreamField::Harmonic, descent_direction(mesh, \p longitudinal), whose
//! negation the winding meter then reads as its axes); unused (may be empty) with
//! CutRoute::ShortestPath.
//! \param longitudinal |V| harmonic_longitudinal() values: CutRoute::Aligned then chooses by
//! winding (WindingMeter); empty = by alignment only.
//! \param direction |V| x 3 vessel direction z toward the root (the field of the travel cost):
//! CutRoute::Aligned's second trace where the harmonic one spans wide (see CutRoute::Aligned);
//! empty = none.
//! \throw InvalidInputError if fewer than two loops or options are invalid; if an outlet cannot
//! reach the cut tree; if the route needs a stream field (CutRoutePolicy::needs_stream_field())
//! and \p stream_field has not |V| rows; if \p direction is neither empty nor |V| rows; if a
//! policy returns a path or end that breaks its contract (the message names the policy).
CutPlan plan_cuts(const Mesh& mesh, const std::vector<BoundaryLoop>& loops,
                  const HalfedgeWeights& weights, const Eigen::MatrixX3d& winding_rate,
                  const CutPlanOptions& options = {},
                  const Eigen::MatrixX3d& stream_field = Eigen::MatrixX3d(),
                  const Eigen::VectorXd& longitudinal = Eigen::VectorXd(),
                  const Eigen::MatrixX3d& direction = Eigen::MatrixX3d());

//! plan_cuts() on a cut graph already built (flatten() builds it in stage GC); the same plan.
CutPlan plan_cuts(CutGraph& graph, const std::vector<BoundaryLoop>& loops,
                  const Eigen::MatrixX3d& winding_rate, const CutPlanOptions& options = {},
                  const Eigen::MatrixX3d& stream_field = Eigen::MatrixX3d(),
                  const Eigen::VectorXd& longitudinal = Eigen::VectorXd(),
                  const Eigen::MatrixX3d& direction = Eigen::MatrixX3d());

}  // namespace vessel
