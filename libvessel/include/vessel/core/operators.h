#pragma once

#include "vessel/core/mesh.h"

#include <Eigen/Sparse>

namespace vessel {

//! \brief Cotangent Laplacian (positive semi-definite convention: L = -Δ).
//! \return |V| x |V| symmetric matrix, entries indexed by `v.idx()`; rows sum to zero.
Eigen::SparseMatrix<double> cotan_laplacian(const Mesh& mesh);

//! \brief Lumped (barycentric) mass matrix: one third of the incident face areas per vertex.
//! \return |V| diagonal entries indexed by `v.idx()`.
Eigen::VectorXd lumped_mass(const Mesh& mesh);

//! \brief Per-face gradient of a piecewise-linear function.
//! \param f |V| values indexed by `v.idx()`.
//! \return |F| x 3 matrix, row `f.idx()` is the (constant) gradient on that face; zero on faces
//! with collinear corners.
//! \throw InvalidInputError if \p f does not have |V| entries.
Eigen::MatrixX3d face_gradient(const Mesh& mesh, const Eigen::VectorXd& f);

//! \brief Area-weighted average of the face gradients around each vertex.
//! \return |V| x 3 matrix, row `v.idx()`; zero at isolated vertices.
//! \throw InvalidInputError if \p f does not have |V| entries.
Eigen::MatrixX3d vertex_gradient(const Mesh& mesh, const Eigen::VectorXd& f);

}  // namespace vessel
