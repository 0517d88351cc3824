#pragma once

#include "vessel/core/mesh.h"

#include <string>
#include <vector>

namespace vessel {

//! A vertex held at a given (u, v) position during a parameterization.
struct Pin
{
    VertexHandle vertex;
    Eigen::Vector2d uv;
};

using Pins = std::vector<Pin>;

//! \brief Check \p pins against \p mesh and index them by vertex.
//! \param caller function name that prefixes the error messages.
//! \return |V| entries, `v.idx()`: the index in \p pins of the pin on v, or -1.
//! \throw InvalidInputError if a pin has an invalid handle or a non-finite target, or a vertex
//! is pinned twice.
std::vector<int> pin_index(const Mesh& mesh, const Pins& pins, const std::string& caller);

}  // namespace vessel
