#pragma once

#include "vessel/core/mesh.h"

#include <string>
#include <vector>

namespace vessel {

//! \brief Write a flattened mesh as OBJ in seam form: `v` lines are \p input_points (the input
//! file's vertices, in input order, unchanged), `vt` lines the (u, v) of every cut-mesh vertex,
//! faces in mesh order as `f v/vt v/vt v/vt`. Blender, MeshLab and ParaView read this, and any
//! per-vertex field of the input maps straight across.
//! \param mesh the cut mesh; needs the `int` vertex property `prop::input_index`.
//! \param uv |V| x 2 (u, v), row `v.idx()` of \p mesh.
//! \throw InvalidInputError if sizes disagree or the property is missing.
//! \throw IoError if the file cannot be written. The file is written to a temporary name and
//! renamed, so a failed run never leaves a partial file.
void write_flat_obj(const std::string& path, const std::vector<Eigen::Vector3d>& input_points,
                    const Mesh& mesh, const Eigen::MatrixX2d& uv);

}  // namespace vessel
