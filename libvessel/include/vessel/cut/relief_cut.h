#pragma once

#include "vessel/cut/boundary.h"
#include "vessel/cut/cut_plan.h"

#include <optional>
#include <vector>

namespace vessel {

//! \file Relief cuts: extra slits that let a bulging region open in the plane.
//!
//! The paper's cuts run along the vessels, from every outlet to the tree. A region that bulges
//! away from the vessels, e.g. the sac of an aneurysm, is then a cap that the map must squeeze
//! into a disk: its middle shrinks and its rim stretches (a lateral aneurysm: mean |log area
//! ratio| 0.31, the sac's centre at a third of its area). Following Gu, Gortler and Hoppe
//! ("Geometry images", 2002), a relief cut runs from the point the map compresses most along
//! the shortest path to the seam; the cap then opens like a flower. It is a dead-end slit: the
//! cut mesh stays a disk, and the layout ignores it.

//! When and how relief cuts are added (FlattenOptions::relief).
struct ReliefCutOptions
{
    //! Relief cuts are added while the map's area-weighted mean |log area ratio| is above this
    //! (FlatQuality::mean_abs_log_area_normalized: blind to the map's overall scale, as the
    //! issue's check is).
    //! The default is the core issue's acceptance bound; every map below it is left as the
    //! paper's cuts make it.
    double target_mean_abs_log_area = 0.15;
    //! At most this many relief cuts; 0 = never (the paper's cuts only).
    int max_cuts = 2;
    //! Passes of one-ring averaging of the per-vertex log area ratio before the most compressed
    //! vertex is picked, so that a single squeezed sliver does not decide where to cut.
    int smoothing_passes = 3;
    //! A relief cut starts at least this many edges (rings) away from the seam and the loops,
    //! so that it opens a region instead of nicking the seam.
    int min_rings = 5;
    //! \throw InvalidInputError naming the bad field.
    void validate() const;
};

//! \brief Per-vertex log area ratio of a map, on the uncut mesh: every face of the cut mesh gives
//! log(A_2D / A_3D) to the original vertices of its corners (area-weighted mean), then
//! \p smoothing_passes rounds of one-ring averaging over the uncut mesh.
//! \param uncut The mesh before the cut (vertex ids = `prop::origin` values of \p cut).
//! \param cut The cut mesh with the `prop::origin` vertex property. \param uv |V_cut| x 2.
//! \return one value per vertex of \p uncut (0 where no face has positive area in both).
Eigen::VectorXd vertex_log_area_ratio(const Mesh& uncut, const Mesh& cut,
                                      const Eigen::MatrixX2d& uv, int smoothing_passes);

//! \brief Plan one relief cut on the uncut mesh: from the vertex with the lowest \p log_area at
//! least \p min_rings edges away from the seam of \p plan (cuts and earlier relief cuts) and the
//! boundary loops, the shortest path (edge length) to the nearest vertex of that seam that is
//! not on a loop (a loop opened twice would no longer be one strip end); loops are not crossed.
//! \return the path, `outlet = -1`, `parent` = the cut it ends on (-1 on a relief cut);
//! std::nullopt when no vertex is that far from the seam.
std::optional<CutPath> plan_relief_cut(const Mesh& uncut, const std::vector<BoundaryLoop>& loops,
                                       const CutPlan& plan, const Eigen::VectorXd& log_area,
                                       int min_rings);

}  // namespace vessel
