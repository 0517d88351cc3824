#include "solve/reach_solve.h"
#include "solve/cholmod_common.h"
#include "solve/paired_system.h"
#include "support/meshes.h"

#include <doctest/doctest.h>
#include <Eigen/CholmodSupport>
#include <Eigen/Sparse>

#include <cmath>
#include <string>
#include <vector>

TEST_CASE(
    "reach solve: a few sparse columns forward-solved on the rows they reach equal the "
    "dense solve, which is zero on every other row")
{
    const Eigen::SparseMatrix<double> A = vessel::detail::paired_laplacian_system(
        vessel::test::shared_tree_mesh("x-ray-angio-data/coronary-phantom-tri3-coarse.ply"));
    const Eigen::Index n = A.rows();
    vessel::detail::CholmodCommon common;
    common.c.supernodal = CHOLMOD_SUPERNODAL;
    cholmod_sparse view = Eigen::viewAsCholmod(A.selfadjointView<Eigen::Upper>());
    cholmod_factor* L = cholmod_analyze(&view, &common.c);
    REQUIRE(L != nullptr);
    REQUIRE(cholmod_factorize(&view, L, &common.c));
    REQUIRE(L->is_super);

    // Columns like the look pulls': each over a run of consecutive vertices' unknowns.
    std::vector<Eigen::Triplet<double>> entries;
    const int columns = 5;
    for (int j = 0; j < columns; ++j)
        for (int i = 0; i < 24; ++i)
            entries.emplace_back((j * 2003 + i) % n, j, std::cos(0.4 * (i + j)) + 1.5);
    Eigen::SparseMatrix<double> U(n, columns);
    U.setFromTriplets(entries.begin(), entries.end());

    const vessel::detail::ReachSolve reach = vessel::detail::reach_forward_solve(*L, U);
    REQUIRE(reach.Y.rows() == static_cast<Eigen::Index>(reach.rows.size()));
    REQUIRE(reach.Y.cols() == columns);

    Eigen::MatrixXd dense = U;
    for (const int system : {CHOLMOD_P, CHOLMOD_L})
    {
        cholmod_dense in = Eigen::viewAsCholmod(dense);
        cholmod_dense* out = cholmod_solve(system, L, &in, &common.c);
        REQUIRE(out != nullptr);
        dense = Eigen::Map<Eigen::MatrixXd>(static_cast<double*>(out->x), n, columns);
        cholmod_free_dense(&out, &common.c);
    }
    std::vector<char> in_reach(static_cast<std::size_t>(n), 0);
    double largest_difference = 0.0;
    for (std::size_t r = 0; r < reach.rows.size(); ++r)
    {
        in_reach[static_cast<std::size_t>(reach.rows[r])] = 1;
        largest_difference =
            std::max(largest_difference,
                     (dense.row(reach.rows[r]) - reach.Y.row(static_cast<Eigen::Index>(r)))
                         .cwiseAbs()
                         .maxCoeff());
    }
    CHECK(largest_difference <= 1e-12 * dense.cwiseAbs().maxCoeff());
    double outside = 0.0;
    for (Eigen::Index i = 0; i < n; ++i)
        if (!in_reach[static_cast<std::size_t>(i)])
            outside = std::max(outside, dense.row(i).cwiseAbs().maxCoeff());
    CHECK(outside == 0.0);
    // Sparse columns reach part of the factor, not all of it.
    CHECK(reach.rows.size() < static_cast<std::size_t>(n) / 2);
    cholmod_free_factor(&L, &common.c);
}
