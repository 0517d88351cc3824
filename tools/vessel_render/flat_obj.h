#pragma once

#include "vessel/cut/boundary.h"
#include "vessel/core/mesh.h"

#include <string>
#include <vector>

namespace vessel::cli {

//! A flattened mesh read back from the seam-form OBJ that vessel-flatten writes.
struct FlatObj
{
    //! Cut mesh: one vertex per `vt` line (row i of uv = vertex i), positions from the `v`
    //! line of its corners; `int` vertex property prop::input_index = that `v` index (0-based).
    Mesh mesh;
    Eigen::MatrixX2d uv;  //!< |vt| x 2
    //! The openings: runs of the map's boundary whose edge is on the boundary once only (a seam
    //! edge appears twice, once per side), longest first as boundary_loops() orders them.
    std::vector<BoundaryLoop> loops;
};

//! \brief Read `v`, `vt` and `f v/vt ...` lines (triangles only).
//! \throw IoError if the file cannot be read; InvalidInputError if it is not in seam form.
FlatObj read_flat_obj(const std::string& path);

}  // namespace vessel::cli
