#pragma once

#include "vessel/core/mesh.h"

#include <vector>

namespace vessel {

//! \file A vector field on the flattened map sampled at evenly spaced points, for drawing it as
//! arrows over a scalar field (render_map_image() with MapImageInput::vectors), e.g. the
//! direction of the wall shear stress on the unrolled wall.

//! One sample: where on the map (uv) and the map vector there.
struct MapArrow
{
    Eigen::Vector2d at;
    Eigen::Vector2d vector;
};

//! \brief \p vectors (one map vector per cut-mesh vertex, row `v.idx()`; e.g. a 3D wall field
//! pushed through vertex_map_jacobians()) sampled at the points of a square grid of step
//! \p spacing (map units) centred on the map's bounding box, each linearly interpolated over the
//! face that holds it (barycentric), in row-major order from the lowest (u, v). Points outside
//! every face (in the gaps between branches) get no sample. Where faces overlap, the first face in
//! index order that holds the point is used; a flip-free map has none.
//! \throw InvalidInputError if \p uv or \p vectors does not have one row per vertex, an entry is
//! not finite, or \p spacing is not positive or leaves more than 10^7 grid cells.
std::vector<MapArrow> sample_map_arrows(const Mesh& mesh, const Eigen::MatrixX2d& uv,
                                        const Eigen::MatrixX2d& vectors, double spacing);

}  // namespace vessel
