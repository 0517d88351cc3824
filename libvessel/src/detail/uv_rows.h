#pragma once

#include "vessel/core/errors.h"
#include "vessel/core/mesh.h"

#include <string>

namespace vessel::detail {

//! \throw InvalidInputError "<caller>: uv has R rows for V vertices" unless \p uv has one row
//! per vertex of \p mesh.
inline void require_uv_rows(const Mesh& mesh, const Eigen::MatrixX2d& uv, const char* caller)
{
    if (static_cast<std::size_t>(uv.rows()) != mesh.n_vertices())
        throw InvalidInputError(std::string(caller) + ": uv has " + std::to_string(uv.rows()) +
                                " rows for " + std::to_string(mesh.n_vertices()) + " vertices");
}

}  // namespace vessel::detail
