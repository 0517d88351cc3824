#pragma once

#include "vessel/core/mesh.h"
#include "vessel/core/operators.h"

#include <Eigen/Sparse>

#include <vector>

namespace vessel::detail {

//! A system of the kind the flattening factors (LSCM, SLIM, the area polish), made from a mesh
//! alone, for the factorization's tests and vessel-factor-bench: per vertex a (u, v) pair, the
//! cotangent Laplacian on both with \p shift added to the diagonal (definite, as the pipeline's
//! pins make its systems), and the u-v couplings of neighbours that LSCM's conformal term has,
//! stored as explicit zeros. Upper triangle, compressed.
inline Eigen::SparseMatrix<double> paired_laplacian_system(const Mesh& mesh, double shift = 1e-3)
{
    Eigen::SparseMatrix<double> L = cotan_laplacian(mesh);
    if (L.coeff(0, 0) < 0.0)
        L = -L;
    std::vector<Eigen::Triplet<double>> t;
    for (int k = 0; k < L.outerSize(); ++k)
        for (Eigen::SparseMatrix<double>::InnerIterator it(L, k); it; ++it)
        {
            const int i = static_cast<int>(it.row()), j = static_cast<int>(it.col());
            if (i > j)
                continue;
            const double value = it.value() + (i == j ? shift : 0.0);
            t.emplace_back(2 * i, 2 * j, value);
            t.emplace_back(2 * i + 1, 2 * j + 1, value);
            if (i != j)
            {
                t.emplace_back(2 * i, 2 * j + 1, 0.0);
                t.emplace_back(2 * i + 1, 2 * j, 0.0);
            }
        }
    Eigen::SparseMatrix<double> A(2 * L.rows(), 2 * L.rows());
    A.setFromTriplets(t.begin(), t.end());
    A.makeCompressed();
    return A;
}

}  // namespace vessel::detail
