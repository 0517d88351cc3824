#pragma once

#include "vessel/cut/boundary.h"
#include "vessel/cut/cut_plan.h"
#include "vessel/solve/ordering.h"

#include <memory>

namespace vessel {

//! How well cuts follow the vessel: the project's own measure (../shared/tools/flatcheck.py
//! gives a second opinion with another reference field).
struct SeamAlignmentOptions
{
    //! Half-width, in path edges, of the chord that stands for the cut's local direction. A
    //! path along mesh edges zig-zags around any smooth curve; its chord over 2 * window edges
    //! does not. 1 = per edge pair.
    int window = 3;
    //! \throw InvalidInputError naming the bad field.
    void validate() const;
};

//! Alignment of one cut with a reference direction field.
struct PathAlignment
{
    double mean = 0.0;   //!< length-weighted mean |cos(chord, reference)|: 1 = along the field
    double low_fraction = 0.0;  //!< fraction of the cut's length where |cos| < 0.5
    double length = 0.0;        //!< 3D length of the cut
};

//! \brief Windowed alignment of \p path with \p reference: at every path vertex the chord from
//! `window` edges before it to `window` edges after it (clamped at the ends) is compared with
//! the reference direction there, weighted by the length of the vertex's half edges.
//! \param reference |V| x 3 directions, row `v.idx()` (e.g. geodesic_descent()); zero rows
//! (no direction) are skipped. A field of the uncut mesh also serves its cut copy: the cut
//! only appends vertices.
//! \throw InvalidInputError if \p reference has no row for a vertex of the path, or options
//! are invalid.
PathAlignment path_alignment(const Mesh& mesh, const CutPath& path,
                             const Eigen::MatrixX3d& reference,
                             const SeamAlignmentOptions& options = {});

//! \brief Harmonic longitudinal coordinate of a vessel tree (as in vessel mapping, e.g. Antiga
//! and Steinman 2004): Laplace's equation with 0 on the inlet (loops[0]) and, on each outlet,
//! the mean of \p geodesic over that loop. Its descent_direction() runs along every vessel
//! and, unlike the geodesic distance, is smooth across junctions and sacs; it is the reference
//! field of the report's seam alignment. One sparse Cholesky factorization (CHOLMOD).
//! \param loops boundary_loops(mesh). \param geodesic |V| distances from the inlet.
//! \return |V| values, `v.idx()`.
//! \throw InvalidInputError if there are fewer than two loops or sizes disagree;
//! SolverError if the factorization fails (e.g. a component without a loop).
Eigen::VectorXd harmonic_longitudinal(const Mesh& mesh, const std::vector<BoundaryLoop>& loops,
                                      const Eigen::VectorXd& geodesic);

//! harmonic_longitudinal() in two steps: the factorization, which needs only the loops, and the
//! solve, which needs the geodesic distance; so the factorization can run beside the
//! distance's own (the pipeline does). solve() gives the same values as harmonic_longitudinal().
class HarmonicLongitudinal
{
public:
    //! \param loops boundary_loops(mesh); loops[0] is the inlet. Reads \p mesh only.
    //! \param ordering Elimination order of the factorization, a VertexOrdering of \p mesh
    //! (e.g. shared with the heat method's, as the pipeline does); null (the default) = CHOLMOD
    //! orders it.
    //! \throw InvalidInputError if there are fewer than two loops or \p ordering is not one of
    //! the mesh; SolverError as harmonic_longitudinal().
    HarmonicLongitudinal(const Mesh& mesh, const std::vector<BoundaryLoop>& loops,
                         const VertexOrdering* ordering = nullptr);
    ~HarmonicLongitudinal();
    HarmonicLongitudinal(HarmonicLongitudinal&&) noexcept;
    HarmonicLongitudinal& operator=(HarmonicLongitudinal&&) noexcept;

    //! \param geodesic |V| distances from the inlet. \return |V| values, `v.idx()`.
    //! \throw InvalidInputError if the size disagrees.
    Eigen::VectorXd solve(const Eigen::VectorXd& geodesic) const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

//! \brief How far cut \p index of \p plan runs beside the cuts made before it: over its edges
//! whose two ends both lie within \p distance (edge-path distance d over the surface) of a vertex
//! of an earlier cut (plan.paths[0 .. index-1]), the sum of max(0, edge length - drop of d along
//! the edge). An edge heading straight for the tree adds ~0, an edge at a constant offset its
//! length; so a cut that meets the tree head-on scores ~0 whatever \p distance, and one that runs
//! down the parent vessel next to an earlier cut scores the length of that run (a sliver in the
//! map). Only counting the edges within \p distance missed runs at a larger offset (the
//! SimVascular demo's 8 mm run lies 1.2-1.8 mm = 2.4-3.6 outlet radii from the trunk cut) and
//! gave head-on joins about \p distance. 0 for the first cut.
//! \throw InvalidInputError if \p index is out of range or \p distance is negative.
double beside_length(const Mesh& mesh, const CutPlan& plan, std::size_t index, double distance);

//! \brief beside_length() of every cut, cut i within \p distance[i]: the same figures, from
//! one distance field grown cut by cut instead of one field per cut.
//! \throw InvalidInputError if \p distance has not one entry per cut or one is negative.
std::vector<double> beside_lengths(const Mesh& mesh, const CutPlan& plan,
                                   const std::vector<double>& distance);

//! \brief The fraction of the cuts' length (plan.paths, not the relief cuts) on the far side of
//! their vessels from \p viewpoint: an edge is on the far side where the surface faces away
//! from the viewpoint, i.e. where the normal n of its faces (outward, summed, area-weighted)
//! has n . (viewpoint - midpoint) < 0. 0 for a plan without cuts. The plan's halfedges must
//! index \p mesh (the uncut mesh of plan_cuts(), or FlattenResult::mesh with its plan).
//! \throw InvalidInputError if \p viewpoint is not finite.
double far_side_fraction(const Mesh& mesh, const CutPlan& plan, const Eigen::Vector3d& viewpoint);

//! Length-weighted mean of per-cut path_alignment() results (all zero when there are none).
PathAlignment seam_alignment(const std::vector<PathAlignment>& paths);

}  // namespace vessel
