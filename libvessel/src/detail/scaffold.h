#pragma once

#include <Eigen/Core>

#include <array>
#include <vector>

namespace vessel::detail {

//! \brief Triangulates the free space between a map's boundary polygon and a box around it
//! (the scaffold of Jiang et al. 2017, "Simplicial complex augmentation framework for bijective
//! maps"): a constrained Delaunay triangulation whose constraints are the boundary edges and the
//! box's sides, keeping the triangles between the two.
//! \param x positions [u_0, v_0, u_1, v_1, ...] of every vertex, the box corners included.
//! \param boundary the map's boundary polygon (vertex indices into x, in order).
//! \param box the four box corners' vertex indices, counter-clockwise.
//! \return counter-clockwise triangles (vertex indices into x).
//! \throw SolverError if the boundary crosses itself (the scaffold needs a simple polygon).
std::vector<std::array<int, 3>> scaffold_triangles(const Eigen::VectorXd& x,
                                                   const std::vector<int>& boundary,
                                                   const std::array<int, 4>& box);

}  // namespace vessel::detail
