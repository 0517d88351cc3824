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

//! \brief Unit direction of steepest descent of a scalar field \p f per vertex: -grad f / |grad f|
//! from the area-weighted face gradients (vertex_gradient()). With f = G (distance from the
//! inlet) or a harmonic longitudinal coordinate it points along the vessel toward the root.
//! It is not the cut direction of the method: tried as E_c's z, the geodesic descent leans to
//! the inner side of bends, and the cut wound 405 degrees around a 1.5-turn helical tube
//! (the minimal curvature direction: under 20; docs/results.md).
//! \param f |V| values indexed by `v.idx()`.
//! \return |V| x 3; rows where the gradient vanishes or is undefined (e.g. infinite distances)
//! are zero.
//! \throw InvalidInputError if \p f does not have |V| entries.
Eigen::MatrixX3d descent_direction(const Mesh& mesh, const Eigen::VectorXd& f);

}  // namespace vessel
