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

//! \brief Triangulates the free space between a map's boundary polygon and a box around it
//! (the scaffold of Jiang et al. 2017, "Simplicial complex augmentation framework for bijective
//! maps"): a constrained Delaunay triangulation whose constraints are the boundary edges and the
//! box's sides, refined in the free space (CGAL's Delaunay mesher, boundary edges never split)
//! until no triangle has an angle below ~20 degrees, keeping the triangles between the two.
//! \param x positions [u_0, v_0, u_1, v_1, ...] of every vertex, the box corners included.
//! \param boundary the map's boundary polygon (vertex indices into x, in order).
//! \param box the four box corners' vertex indices, counter-clockwise.
//! \param inside a point strictly inside the map (e.g. a face's centroid).
//! \param first_steiner index given to the first Steiner vertex.
//! \throw SolverError if the boundary crosses itself (the scaffold needs a simple polygon).
ScaffoldMesh scaffold_triangles(const Eigen::VectorXd& x, const std::vector<int>& boundary,
                                const std::array<int, 4>& box, const Eigen::Vector2d& inside,
                                int first_steiner);

}  // namespace vessel::detail
