#pragma once

#include "vessel/core/mesh.h"

#include <array>
#include <utility>
#include <vector>

namespace vessel {

//! A triangle in the plane, corners in any order (either orientation).
using Triangle2 = std::array<Eigen::Vector2d, 3>;

//! \brief Whether the interiors of two planar triangles intersect, decided exactly.
//!
//! Uses exact orientation predicates (CGAL's `Exact_predicates_inexact_constructions_kernel`):
//! the interiors are disjoint exactly when the line through one edge of either triangle has the
//! whole other triangle on its outer closed side (separating axis theorem in 2D). Triangles that
//! only share an edge or a corner, or touch along a boundary, do not intersect. A triangle with
//! zero area has no interior and intersects nothing.
bool interiors_intersect(const Triangle2& a, const Triangle2& b);

//! Area of the intersection of two planar triangles (convex polygon clipping in double
//! precision; 0 when interiors_intersect() is false).
double intersection_area(const Triangle2& a, const Triangle2& b);

//! Overlaps of a planar triangle map with itself.
struct OverlapReport
{
    //! Pairs (f, g), f < g, of face indices whose interiors intersect in the map, sorted.
    //! Neighbours that do not fold over each other are never reported: their shared edge (or
    //! corner) separates them exactly.
    std::vector<std::pair<int, int>> pairs;
    std::vector<int> triangles;    //!< every face in some pair, sorted, each once
    //! Sum over `pairs` of the intersection area (a region covered k times counts
    //! k (k - 1) / 2 times; for the usual two-layer overlap this is the doubly covered area).
    double overlap_area = 0.0;
    double map_area = 0.0;          //!< sum of |signed area| of all faces
    double overlap_fraction = 0.0;  //!< overlap_area / map_area (0 for an empty map)
    int overlapping_triangles() const { return static_cast<int>(triangles.size()); }
};

//! \brief All pairs of faces of \p mesh whose interiors intersect in the map \p uv.
//!
//! A map whose faces all turn the same way (none degenerate) and whose boundary is one loop
//! mapped to a simple polygon is one-to-one (Lipman 2014, "Bijective mappings of meshes with
//! boundary and the degree in mesh processing"): that is decided first, exactly and in time
//! linear in the faces plus near-linear in the boundary, and then no pair is tested. Otherwise
//! candidate pairs come from a uniform grid whose cell is the mean face bounding-box size, so the
//! cost is near-linear in the number of faces for a map without large overlaps; each candidate is
//! decided exactly with interiors_intersect(). Flipped faces are tested with their own corners
//! (a fold over its neighbours is reported as overlapping them).
//! \param uv |V| x 2, row `v.idx()`.
//! \throw InvalidInputError if \p uv does not have one row per vertex or has a non-finite entry.
OverlapReport find_overlaps(const Mesh& mesh, const Eigen::MatrixX2d& uv);

//! \brief Same for a triangle soup: \p triangles[i] is face i.
//! \throw InvalidInputError if a corner is not finite.
OverlapReport find_overlaps(const std::vector<Triangle2>& triangles);

}  // namespace vessel
