#pragma once

#include "vessel/solve/ordering.h"
#include "vessel/layout/pins.h"

#include <Eigen/Sparse>

namespace vessel {

//! \brief Least squares conformal map \cite levy_2002_least with the given vertices pinned.
//! \param mesh Disk-topology triangle mesh (not modified).
//! \param pins At least two vertices with distinct target positions.
//! \return |V| x 2 matrix of (u, v), row `v.idx()`; pinned rows equal their targets. Vertices
//! without incident faces get (0, 0).
//! \throw InvalidInputError if fewer than two pins or a pin handle is invalid.
//! If CHOLMOD's factorization fails (the system is numerically singular, e.g. a region the pins
//! do not hold), the system is solved regularised instead (shift 1e-10 x its largest diagonal
//! entry, refined against the unshifted system), so a run does not end here: the solution is
//! unchanged wherever the pins determine it, and an unpinned part collapses toward the origin.
//! \param ordering Elimination order of the factorization: a VertexOrdering of \p mesh (e.g.
//! laplacian_ordering() of the cut mesh, shared with ARAP as the pipeline does); null (the
//! default) = AMD here.
//! \throw SolverError if even the regularised factorization or solve fails.
//! \throw InvalidInputError if \p ordering is not an ordering of the mesh's vertices.
Eigen::MatrixX2d lscm(const Mesh& mesh, const Pins& pins,
                      const VertexOrdering* ordering = nullptr);

//! \brief The LSCM conformal energy as a quadratic form \cite mullen_2008_spectral:
//! E_C(x) = 1/2 x^T L_C x = E_D(x) - A(x), Dirichlet energy minus signed image area.
//! \return 2|V| x 2|V| symmetric positive semi-definite matrix; row/column `v.idx()` is the u of
//! vertex v and row/column `|V| + v.idx()` its v (block ordering x = [u; v]).
Eigen::SparseMatrix<double> lscm_energy_matrix(const Mesh& mesh);

//! \brief The conformal energy of a map, summed per triangle:
//! E_C = sum_t area_t * ((J_00 - J_11)^2 + (J_01 + J_10)^2) / 2 with J_t the 2x2 Jacobian of the
//! map on face t; equals 1/2 x^T lscm_energy_matrix(mesh) x. Zero exactly for similarities.
//! \param uv |V| x 2, row `v.idx()`.
//! \throw InvalidInputError if `uv` does not have |V| rows.
double conformal_energy(const Mesh& mesh, const Eigen::MatrixX2d& uv);

}  // namespace vessel
