#pragma once
// Flat caps: the planar patches that close a vessel model's ends (make_tree_surface(),
// TreeSurfaceOptions::remove_flat_caps).

#include <Eigen/Core>

#include <array>
#include <vector>

namespace vessel::detail {

//! One flat cap found by find_flat_caps().
struct FlatCap
{
    std::vector<int> triangles;  //!< indices into the triangles given, ascending
    double area = 0.0;
    double mean_rim_angle_deg = 0.0;  //!< mean dihedral angle between the cap and the wall
};

//! make_tree_surface()'s criteria (TreeSurfaceOptions::remove_flat_caps). A cap's face normals
//! lie within kFlatCapCoplanarDeg of one another's: a capping tool's caps are planar to the
//! rounding of their coordinates, which in a file of floats (STL) turns the normals of a cap's
//! smallest faces by a few degrees. Its rim turns by at least kFlatCapMinRimDeg everywhere and
//! kFlatCapMeanRimDeg on average (find_flat_caps() says why), and has more edges than a
//! vertex's star, as a vessel end must (TreeSurfaceOptions::hole_max_edges).
inline constexpr double kFlatCapCoplanarDeg = 5.0;
inline constexpr double kFlatCapMinRimDeg = 30.0;
inline constexpr double kFlatCapMeanRimDeg = 60.0;
inline constexpr int kFlatCapMinRimEdges = 7;

//! \brief The flat caps of a consistently oriented, edge-manifold triangle surface.
//!
//! A cap is a maximal patch of faces joined across edges whose normals lie within
//! \p coplanar_deg of the first face's (the patch is planar, to the rounding of small faces'
//! normals), that is a topological disk (one rim loop; V - E + F = 1), lies wholly inside the
//! surface (no edge of it on the surface's boundary, which is an open vessel end already), and
//! meets the wall along its rim at a crease:
//! the dihedral angle across every rim edge at least \p min_rim_deg and on average at least
//! \p mean_rim_deg. Capping tools (SimVascular's, vmtksurfacecapper with its flat caps, a
//! segmentation closed by planes) leave the cap about perpendicular to the wall, 90 degrees
//! all round an end cut square and 45-135 degrees round one cut obliquely; the wall itself turns
//! by about 360 / n degrees between faces on a vessel n faces round (45 on a coarse tube of 8),
//! and a flat stretch of the wall joins the wall around it smoothly, so it is no cap.
//! The rim also has at least \p min_rim_edges edges: a sliver in a crease between two walls
//! can be a planar disk with a sharp rim of three.
//! \param triangles corner indices into \p points, wound alike (normals on one side).
std::vector<FlatCap> find_flat_caps(const std::vector<Eigen::Vector3d>& points,
                                    const std::vector<std::array<int, 3>>& triangles,
                                    double coplanar_deg, double min_rim_deg, double mean_rim_deg,
                                    int min_rim_edges);

}  // namespace vessel::detail
