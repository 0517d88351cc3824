#pragma once

#include "vessel/pins.h"

namespace vessel {

//! \brief Least squares conformal map \cite levy_2002_least with the given vertices pinned.
//! \param mesh Disk-topology triangle mesh (not modified).
//! \param pins At least two vertices with distinct target positions.
//! \return |V| x 2 matrix of (u, v), row `v.idx()`; pinned rows equal their targets.
//! \throw InvalidInputError if fewer than two pins or a pin handle is invalid.
//! \throw SolverError if the sparse factorization fails.
Eigen::MatrixX2d lscm(const Mesh& mesh, const Pins& pins);

}  // namespace vessel
