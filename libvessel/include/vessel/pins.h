#pragma once

#include "vessel/mesh.h"

#include <vector>

namespace vessel {

//! A vertex held at a given (u, v) position during a parameterization.
struct Pin
{
    VertexHandle vertex;
    Eigen::Vector2d uv;
};

using Pins = std::vector<Pin>;

}  // namespace vessel
