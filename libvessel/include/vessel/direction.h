#pragma once

#include "vessel/mesh.h"

namespace vessel {

//! \brief Orient each minimal principal direction toward the root: z = c if <c, grad G> < 0,
//! else -c (step 3 of the method).
//! \param min_direction |V| x 3 unit directions (sign arbitrary), row `v.idx()`.
//! \param geodesic |V| distances from the inlet, indexed by `v.idx()`.
//! \return |V| x 3 unit directions pointing toward decreasing geodesic distance; where the
//! gradient of \p geodesic is undefined (e.g. infinite distances) the row of \p min_direction is
//! returned unchanged.
//! \throw InvalidInputError if the array sizes do not match the mesh.
Eigen::MatrixX3d align_to_root(const Mesh& mesh, const Eigen::MatrixX3d& min_direction,
                               const Eigen::VectorXd& geodesic);

}  // namespace vessel
