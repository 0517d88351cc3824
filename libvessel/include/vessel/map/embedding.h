#pragma once

#include "vessel/core/mesh.h"

namespace vessel {

//! \brief First pair of non-adjacent boundary edges of a disk map that cross or touch, if any.
//! A map without flipped triangles whose boundary is a simple polygon is one-to-one (no part of
//! the map lies over another), so this is the global-overlap test for flip-free maps.
//! \param uv |V| x 2, row `v.idx()`.
//! \return the two boundary halfedges' indices, or {-1, -1} when the boundary is simple.
//! Near-linear: edges are bucketed in a uniform grid.
std::pair<int, int> boundary_self_intersection(const Mesh& mesh, const Eigen::MatrixX2d& uv);

}  // namespace vessel
