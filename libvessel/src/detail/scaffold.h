#pragma once

#include <Eigen/Core>

#include <array>
#include <vector>

namespace vessel::detail {

//! The scaffold: triangles over the map's boundary vertices, the box corners and new free
//! (Steiner) vertices placed in the free space so that no scaffold triangle is a sliver.
struct ScaffoldMesh
{
    std::vector<Eigen::Vector2d> steiner;          //!< positions of the Steiner vertices
    std::vector<std::array<int, 3>> triangles;     //!< counter-clockwise, indices into x; Steiner
                                                   //!< vertex j is `first_steiner + j`
};

//! The area polish's scaffold shape bound (area_polish()), CGAL's default: sin^2 of the
//! smallest angle, 20.7 degrees, the largest bound for which Delaunay refinement is known to
//! end (Shewchuk 2002, "Delaunay refinement algorithms for triangular mesh generation"). The
//! polish's scaffold is made once and its Newton steps end where a scaffold triangle would
//! flip, so slivers shorten them.
constexpr double kPolishScaffoldShape = 0.125;
//! SLIM's scaffold shape bound (injective_refine()): sin^2 of 10 degrees. Its steps are
//! line-searched up to the first flip, and a step that a scaffold triangle stopped goes on over
//! a new triangulation, so the triangles need only bound the step; a coarser bound means fewer
//! Steiner vertices, and each new triangulation and the symbolic analysis of the system it
//! changes cost less (docs/benchmarks.md "The scaffold's angle bound").
constexpr double kSlimScaffoldShape = 0.030153689607045803;

//! \brief Triangulates the free space between a map's boundary polygon and a box around it
//! (the scaffold of Jiang et al. 2017, "Simplicial complex augmentation framework for bijective
//! maps"): a constrained Delaunay triangulation whose constraints are the boundary edges and the
//! box's sides, refined in the free space (CGAL's Delaunay mesher, boundary edges never split)
//! until no triangle has an angle below the one \p shape_bound gives, keeping the triangles
//! between the two.
//! \param x positions [u_0, v_0, u_1, v_1, ...] of every vertex, the box corners included.
//! \param boundary the map's boundary polygon (vertex indices into x, in order).
//! \param box the four box corners' vertex indices, counter-clockwise.
//! \param inside a point strictly inside the map (e.g. a face's centroid).
//! \param first_steiner index given to the first Steiner vertex.
//! \param shape_bound CGAL's shape bound, sin^2 of the smallest angle kept, in (0,
//! kPolishScaffoldShape]: kSlimScaffoldShape for SLIM, kPolishScaffoldShape for the area
//! polish.
//! \throw InvalidInputError if \p shape_bound is outside that range.
//! \throw SolverError if the boundary crosses itself (the scaffold needs a simple polygon).
ScaffoldMesh scaffold_triangles(const Eigen::VectorXd& x, const std::vector<int>& boundary,
                                const std::array<int, 4>& box, const Eigen::Vector2d& inside,
                                int first_steiner, double shape_bound);

//! \brief Makes \p triangles (a scaffold over the vertices of \p x, counter-clockwise) the
//! constrained Delaunay triangulation of the region they cover by edge flips (Lawson 1977,
//! "Software for C1 surface interpolation"): an edge between two triangles that is not locally
//! Delaunay, and whose quadrilateral is strictly convex, is replaced by the other diagonal until
//! none is left. The map's boundary edges (consecutive vertices of \p boundary) and the box's
//! sides are never flipped. Triangles that are not positively oriented at \p x stay unless a
//! flip removes them. The vertices and the region stay the same, so the scaffold needs no new
//! vertex, only a new pattern where an edge flipped.
//! \return the number of flips made.
int flip_to_delaunay(const Eigen::VectorXd& x, const std::vector<int>& boundary,
                     const std::array<int, 4>& box, std::vector<std::array<int, 3>>& triangles);

}  // namespace vessel::detail
