#include "solve/cholmod_common.h"
#include "solve/subtree_solver.h"

#include <Eigen/CholmodSupport>
#include <Eigen/Sparse>
#include <doctest/doctest.h>

#include <vector>

using vessel::detail::CholmodCommon;
using vessel::detail::SubtreeSolver;

namespace {

// The 5-point Laplacian of an nx x ny grid plus `shift` on the diagonal (lower triangle).
Eigen::SparseMatrix<double> grid_laplacian(int nx, int ny, double shift)
{
    std::vector<Eigen::Triplet<double>> t;
    const auto id = [nx](int x, int y) { return y * nx + x; };
    for (int y = 0; y < ny; ++y)
        for (int x = 0; x < nx; ++x)
        {
            t.emplace_back(id(x, y), id(x, y), 4.0 + shift);
            if (x + 1 < nx)
                t.emplace_back(id(x + 1, y), id(x, y), -1.0);
            if (y + 1 < ny)
                t.emplace_back(id(x, y + 1), id(x, y), -1.0);
        }
    Eigen::SparseMatrix<double> A(nx * ny, nx * ny);
    A.setFromTriplets(t.begin(), t.end());
    return A;
}

// A's LL' factor, supernodal (as ArapFactor makes it) or simplicial, copied into a SubtreeSolver.
SubtreeSolver factor(const Eigen::SparseMatrix<double>& lower, bool supernodal = true)
{
    CholmodCommon common;
    common.c.supernodal = supernodal ? CHOLMOD_SUPERNODAL : CHOLMOD_SIMPLICIAL;
    common.c.final_asis = 0;
    common.c.final_ll = 1;
    cholmod_sparse view = Eigen::viewAsCholmod(lower.selfadjointView<Eigen::Lower>());
    cholmod_factor* L = cholmod_analyze(&view, &common.c);
    REQUIRE(L != nullptr);
    REQUIRE(cholmod_factorize(&view, L, &common.c));
    REQUIRE(L->minor == L->n);
    SubtreeSolver solver(*L);
    cholmod_free_factor(&L, &common.c);
    return solver;
}

void check_solves(const Eigen::SparseMatrix<double>& lower, const SubtreeSolver& solver)
{
    const Eigen::Index n = lower.rows();
    REQUIRE(solver.size() == n);
    Eigen::MatrixX2d b(n, 2);
    for (Eigen::Index i = 0; i < n; ++i)
        b.row(i) << std::sin(0.37 * static_cast<double>(i)), 1.0 + 0.01 * static_cast<double>(i % 17);
    SubtreeSolver::Workspace work;
    Eigen::MatrixX2d one, two;
    solver.solve(b, one, 1, work);
    solver.solve(b, two, 2, work);
    CHECK(one == two);  // the same bits on one thread as on two
    const Eigen::SparseMatrix<double> full = lower.selfadjointView<Eigen::Lower>();
    for (int k = 0; k < 2; ++k)
        CHECK((full * one.col(k) - b.col(k)).norm() < 1e-10 * b.col(k).norm());
}

}  // namespace

TEST_CASE("subtree solver: a grid Laplacian splits into two halves and solves exactly")
{
    const Eigen::SparseMatrix<double> A = grid_laplacian(120, 90, 1e-3);
    const SubtreeSolver solver = factor(A);
    // Two sets of nearly equal nonzeros, the columns above them a small remainder.
    CHECK(solver.set_share(0) > 0.35);
    CHECK(solver.set_share(1) > 0.35);
    CHECK(solver.set_share(1) > 0.9 * solver.set_share(0));
    CHECK(solver.set_share(0) > 0.9 * solver.set_share(1));
    check_solves(A, solver);
    // A simplicial factor is copied as supernodes of one column each: no padding zeros, so
    // no more entries than the supernodal copy, and the same solutions.
    const SubtreeSolver simplicial = factor(A, false);
    CHECK(simplicial.stored_entries() <= solver.stored_entries());
    check_solves(A, simplicial);
}

TEST_CASE("subtree solver: two separate blocks go to one set each")
{
    const Eigen::SparseMatrix<double> block = grid_laplacian(40, 40, 0.5);
    const Eigen::Index n = block.rows();
    Eigen::SparseMatrix<double> A(2 * n, 2 * n);
    std::vector<Eigen::Triplet<double>> t;
    for (int copy = 0; copy < 2; ++copy)
        for (int c = 0; c < block.outerSize(); ++c)
            for (Eigen::SparseMatrix<double>::InnerIterator it(block, c); it; ++it)
                t.emplace_back(copy * n + it.row(), copy * n + c, it.value());
    A.setFromTriplets(t.begin(), t.end());
    const SubtreeSolver solver = factor(A);
    CHECK(solver.set_share(0) == doctest::Approx(0.5));
    CHECK(solver.set_share(1) == doctest::Approx(0.5));
    check_solves(A, solver);
}

TEST_CASE("subtree solver: a chain, whose tree does not split evenly, still solves on two threads")
{
    const Eigen::SparseMatrix<double> A = grid_laplacian(2000, 1, 0.1);
    const SubtreeSolver solver = factor(A);
    CHECK(solver.set_share(0) + solver.set_share(1) <= 1.0);
    check_solves(A, solver);
}

TEST_CASE("subtree solver: dense blocks of every width modulo the panel width solve exactly")
{
    // A dense SPD matrix is one supernode; widths 2..9 cover full panels and each remainder
    // (from 2: the checks' first right-hand side starts with sin 0 = 0).
    for (int n = 2; n <= 9; ++n)
    {
        std::vector<Eigen::Triplet<double>> t;
        for (int j = 0; j < n; ++j)
            for (int i = j; i < n; ++i)
                t.emplace_back(i, j, i == j ? n + 1.0 : 1.0 / (1.0 + i + j));
        Eigen::SparseMatrix<double> A(n, n);
        A.setFromTriplets(t.begin(), t.end());
        CAPTURE(n);
        check_solves(A, factor(A));
    }
    // Grid strips of several widths: supernodes with rows below them, in both sets and the top.
    for (int width : {3, 5, 6, 7})
    {
        CAPTURE(width);
        const Eigen::SparseMatrix<double> A = grid_laplacian(width, 300, 0.05);
        check_solves(A, factor(A));
    }
}
