#pragma once

#include "vessel/core/mesh.h"

#include <string>
#include <vector>

namespace vessel {

//! Distortion of a map (u, v) of a triangle mesh, measured against its 3D triangles.
struct FlatQuality
{
    int flipped_triangles = 0;     //!< faces with non-positive signed area in the map
    double area_ratio = 0.0;       //!< total 2D area / total 3D area
    double mean_abs_log_area = 0.0;  //!< area-weighted mean |log(A_2D / A_3D)| over faces
    //! The same with each area divided by its total over the non-flipped faces,
    //! |log((A_2D / sum A_2D) / (A_3D / sum A_3D))|: blind to a uniform scale of the map
    //! (../shared/tools/flatcheck.py's area.mean_abs_log_ratio). The relief-cut target acts on it.
    double mean_abs_log_area_normalized = 0.0;
    double mean_conformal = 0.0;   //!< area-weighted mean sigma_max / sigma_min (1 = conformal)
    double max_conformal = 0.0;    //!< worst sigma_max / sigma_min over non-flipped faces
    //! Faces whose interior overlaps another face's in the map (find_overlaps(), exact).
    int overlapping_triangles = 0;
    double overlap_area = 0.0;      //!< sum of pairwise intersection areas (find_overlaps())
    double overlap_fraction = 0.0;  //!< overlap_area / total |2D area|
    //! The overlapping faces themselves, sorted (find_overlaps().triangles), so that a report
    //! can list them without a second search.
    std::vector<int> overlapping_faces;
};

//! \brief Measure the distortion and the overlaps (find_overlaps()) of \p uv (|V| x 2, row `v.idx()`) on \p mesh.
//! \throw InvalidInputError if \p uv does not have one row per vertex.
FlatQuality flat_quality(const Mesh& mesh, const Eigen::MatrixX2d& uv);

//! Signed area of face \p f in the map (positive = counter-clockwise).
double signed_uv_area(const Mesh& mesh, const Eigen::MatrixX2d& uv, FaceHandle f);

//! Sum of the signed face areas of \p uv (positive for a counter-clockwise map).
double signed_map_area(const Mesh& mesh, const Eigen::MatrixX2d& uv);

//! \brief Scale \p uv about the origin so that its signed area equals the surface's 3D area
//! (a start map of the right size for a distortion energy). Left as it is if its signed area
//! is not positive.
void scale_to_surface_area(const Mesh& mesh, Eigen::MatrixX2d& uv);

//! Above this FlatQuality::mean_abs_log_area a map is of little use: its triangles' areas are
//! off by a factor e = 2.7 on average. The maps of the real trees stay far below it
//! (docs/results.md); maps above it come from inputs such as holes in the wall
//! (docs/bad-input.md).
inline constexpr double kMaxUsefulMeanAbsLogArea = 1.0;

//! One line saying that \p quality is above kMaxUsefulMeanAbsLogArea and what to check, or an
//! empty string if it is not.
std::string distortion_warning(const FlatQuality& quality);

}  // namespace vessel
