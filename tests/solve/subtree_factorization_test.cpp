#include "solve/subtree_factorization.h"
#include "solve/cholmod_common.h"
#include "solve/paired_cholmod.h"
#include "solve/paired_system.h"
#include "support/meshes.h"
#include "vessel/core/errors.h"

#include <Eigen/CholmodSupport>
#include <Eigen/Sparse>
#include <doctest/doctest.h>

#include <cmath>
#include <string>
#include <vector>

using vessel::detail::CholmodCommon;
using vessel::detail::SubtreeFactorization;

namespace {

// detail::paired_laplacian_system() of a real vessel mesh.
Eigen::SparseMatrix<double> paired_system(const char* relative)
{
    return vessel::detail::paired_laplacian_system(vessel::test::shared_tree_mesh(relative));
}

// CHOLMOD's view of the symmetric matrix whose upper triangle \p A holds (stype 1).
cholmod_sparse upper_view(const Eigen::SparseMatrix<double>& A)
{
    return Eigen::viewAsCholmod(A.selfadjointView<Eigen::Upper>());
}

// A supernodal symbolic factor of the upper triangle \p A (CHOLMOD's own ordering).
cholmod_factor* analyze(const Eigen::SparseMatrix<double>& A, CholmodCommon& common)
{
    common.c.supernodal = CHOLMOD_SUPERNODAL;
    cholmod_sparse view = upper_view(A);
    cholmod_factor* L = cholmod_analyze(&view, &common.c);
    REQUIRE(L != nullptr);
    REQUIRE(L->is_super);
    return L;
}

Eigen::VectorXd solve(cholmod_factor* L, const Eigen::VectorXd& b, CholmodCommon& common)
{
    Eigen::VectorXd rhs = b;
    cholmod_dense view = Eigen::viewAsCholmod(rhs);
    cholmod_dense* x = cholmod_solve(CHOLMOD_A, L, &view, &common.c);
    REQUIRE(x != nullptr);
    Eigen::VectorXd out = Eigen::Map<Eigen::VectorXd>(static_cast<double*>(x->x), b.size());
    cholmod_free_dense(&x, &common.c);
    return out;
}

}  // namespace

TEST_CASE("subtree factorization: a real mesh's paired system, as CHOLMOD factors it, on one "
          "and two threads with the same bits")
{
    Eigen::SparseMatrix<double> A = paired_system("vmtk-test-data/aorta-surface-open-ends.ply");
    cholmod_sparse view = upper_view(A);
    CholmodCommon common;
    cholmod_factor* ours[2] = {analyze(A, common), analyze(A, common)};
    cholmod_factor* theirs = analyze(A, common);
    SubtreeFactorization factorization(view, *ours[0]);
    // The tree splits into two sets that both carry work (else two threads would not run).
    CHECK(factorization.set_share(0) > 0.2);
    CHECK(factorization.set_share(1) > 0.2);
    for (int threads : {1, 2})
        REQUIRE(factorization.factorize(view, *ours[threads - 1], common.c, threads));
    REQUIRE(cholmod_factorize(&view, theirs, &common.c));
    REQUIRE(ours[0]->xsize == theirs->xsize);
    const auto* one = static_cast<const double*>(ours[0]->x);
    const auto* two = static_cast<const double*>(ours[1]->x);
    const auto* reference = static_cast<const double*>(theirs->x);
    bool same_bits = true;
    double largest_difference = 0.0, largest = 0.0;
    for (std::size_t k = 0; k < ours[0]->xsize; ++k)
    {
        same_bits = same_bits && one[k] == two[k];
        largest_difference = std::max(largest_difference, std::abs(one[k] - reference[k]));
        largest = std::max(largest, std::abs(reference[k]));
    }
    CHECK(same_bits);
    CHECK(ours[0]->minor == ours[0]->n);
    // The same factor as CHOLMOD's up to the order in which updates are summed.
    CHECK(largest_difference <= 1e-12 * largest);

    Eigen::VectorXd b(A.rows());
    for (Eigen::Index i = 0; i < b.size(); ++i)
        b[i] = std::sin(0.37 * static_cast<double>(i)) + 0.5;
    const Eigen::SparseMatrix<double> full = A.selfadjointView<Eigen::Upper>();
    const Eigen::VectorXd x = solve(ours[1], b, common);
    CHECK((full * x - b).norm() <= 1e-10 * b.norm());
    CHECK((x - solve(theirs, b, common)).norm() <= 1e-10 * x.norm());

    // New values of the same pattern: factorize() again into the same factor.
    const Eigen::SparseMatrix<double> scaled = 2.0 * A;
    cholmod_sparse scaled_view = upper_view(scaled);
    REQUIRE(factorization.factorize(scaled_view, *ours[1], common.c, 2));
    CHECK((full * solve(ours[1], b, common) - 0.5 * b).norm() <= 1e-10 * b.norm());

    for (cholmod_factor* L : {ours[0], ours[1], theirs})
        cholmod_free_factor(&L, &common.c);
}

TEST_CASE("subtree factorization: an indefinite matrix is reported at CHOLMOD's column, another "
          "pattern refused")
{
    Eigen::SparseMatrix<double> A = paired_system("vmtk-test-data/aorta-surface-open-ends.ply");
    A.coeffRef(4000, 4000) = -1.0;  // one negative pivot
    cholmod_sparse view = upper_view(A);
    CholmodCommon common;
    common.c.print = 0;
    cholmod_factor* ours = analyze(A, common);
    cholmod_factor* theirs = analyze(A, common);
    SubtreeFactorization factorization(view, *ours);
    for (int threads : {1, 2})
        CHECK_FALSE(factorization.factorize(view, *ours, common.c, threads));
    cholmod_factorize(&view, theirs, &common.c);
    CHECK(theirs->minor < theirs->n);
    CHECK(ours->minor == theirs->minor);

    Eigen::SparseMatrix<double> other = paired_system("vampy/artery-coarse.ply");
    cholmod_sparse other_view = upper_view(other);
    CHECK_THROWS_AS(factorization.factorize(other_view, *ours, common.c, 2), vessel::SolverError);
    for (cholmod_factor* L : {ours, theirs})
        cholmod_free_factor(&L, &common.c);
}

TEST_CASE("subtree factorization: PairedCholmod factors with it and solves, on one and two "
          "threads alike")
{
    const Eigen::SparseMatrix<double> A =
        paired_system("x-ray-angio-data/coronary-phantom-tri3-coarse.ply");
    const Eigen::SparseMatrix<double> full = A.selfadjointView<Eigen::Upper>();
    Eigen::VectorXd b(A.rows());
    for (Eigen::Index i = 0; i < b.size(); ++i)
        b[i] = std::cos(0.11 * static_cast<double>(i));
    Eigen::VectorXd x[2];
    for (int threads : {1, 2})
    {
        vessel::detail::PairedCholmod solver;
        solver.set_threads(threads);
        solver.analyze_pairs(A);
        REQUIRE(solver.info() == Eigen::Success);
        solver.factorize(A);
        REQUIRE(solver.info() == Eigen::Success);
        x[threads - 1] = solver.solve(b);
        CHECK((full * x[threads - 1] - b).norm() <= 1e-10 * b.norm());
    }
    CHECK(x[0] == x[1]);

    Eigen::SparseMatrix<double> indefinite = A;
    indefinite.coeffRef(10, 10) = -5.0;
    vessel::detail::PairedCholmod solver;
    solver.analyze_pairs(indefinite);
    solver.factorize(indefinite);
    CHECK(solver.info() == Eigen::NumericalIssue);
}

TEST_CASE(
    "subtree factorization: PairedCholmod solves the factorized matrix with a low-rank "
    "term added, through the factor's halves")
{
    // (A + U diag(c) U^T) x = b, as the look pulls' Gauss-Newton terms add to SLIM's and the
    // polish's systems: a few sparse columns over a real mesh's paired system.
    const Eigen::SparseMatrix<double> A =
        paired_system("x-ray-angio-data/coronary-phantom-tri3-coarse.ply");
    const Eigen::SparseMatrix<double> full = A.selfadjointView<Eigen::Upper>();
    const Eigen::Index n = A.rows();
    Eigen::MatrixXd dense = Eigen::MatrixXd::Zero(n, 4);
    for (Eigen::Index j = 0; j < dense.cols(); ++j)
        for (Eigen::Index i = 0; i < 30; ++i)
            dense((j * 997 + 13 * i) % n, j) = std::cos(0.3 * static_cast<double>(i + j));
    const Eigen::SparseMatrix<double> U = dense.sparseView();
    Eigen::VectorXd c(4), b(n);
    c << 300.0, 1.0, 0.05, 1e4;
    for (Eigen::Index i = 0; i < n; ++i)
        b[i] = std::sin(0.07 * static_cast<double>(i)) + 0.5;
    vessel::detail::PairedCholmod solver;
    solver.analyze_pairs(A);
    solver.factorize(A);
    REQUIRE(solver.info() == Eigen::Success);
    const Eigen::VectorXd x = solver.solve_with_low_rank(b, U, c);
    REQUIRE(solver.info() == Eigen::Success);
    const Eigen::VectorXd residual = full * x + U * (c.asDiagonal() * (U.transpose() * x)) - b;
    CHECK(residual.norm() <= 1e-9 * b.norm());
    // The term moves the solution: the pulls are not lost in the update.
    const Eigen::VectorXd plain = solver.solve(b);
    CHECK((plain - x).norm() > 1e-3 * plain.norm());
}

TEST_CASE(
    "subtree factorization: the low-rank solve has the same bits on one thread as with "
    "the low-rank columns' reach beside the right-hand side's forward solve")
{
    const Eigen::SparseMatrix<double> A =
        paired_system("vmtk-old-website/aneurisk-id1-lateral-aneurysm.ply");
    const Eigen::Index n = A.rows();
    REQUIRE(n >= 20000);  // large enough for the second thread (kBesideUnknowns)
    Eigen::MatrixXd dense = Eigen::MatrixXd::Zero(n, 3);
    for (Eigen::Index j = 0; j < dense.cols(); ++j)
        for (Eigen::Index i = 0; i < 40; ++i)
            dense((j * 4001 + 17 * i) % n, j) = 1.0 + 0.5 * std::sin(0.2 * static_cast<double>(i));
    const Eigen::SparseMatrix<double> U = dense.sparseView();
    Eigen::VectorXd c(3), b(n);
    c << 50.0, 2.0, 700.0;
    for (Eigen::Index i = 0; i < n; ++i)
        b[i] = std::cos(0.05 * static_cast<double>(i));
    Eigen::VectorXd x[2];
    for (const int threads : {1, 2})
    {
        vessel::detail::PairedCholmod solver;
        solver.set_threads(threads);
        solver.analyze_pairs(A);
        solver.factorize(A);
        REQUIRE(solver.info() == Eigen::Success);
        x[threads - 1] = solver.solve_with_low_rank(b, U, c);
        REQUIRE(solver.info() == Eigen::Success);
    }
    CHECK(x[0] == x[1]);
    const Eigen::SparseMatrix<double> full = A.selfadjointView<Eigen::Upper>();
    const Eigen::VectorXd residual =
        full * x[1] + U * (c.asDiagonal() * (U.transpose() * x[1])) - b;
    CHECK(residual.norm() <= 1e-9 * b.norm());
}

TEST_CASE("subtree factorization: a PairedCholmod re-analyses one pattern after another, in a "
          "given order or CHOLMOD's, and solves each system as a new solver does")
{
    // SLIM's scaffold re-analyses a new pattern at almost every iteration with one solver; an
    // analysis in a given order must leave CHOLMOD's own ordering methods to a later one.
    const Eigen::SparseMatrix<double> small = paired_system("vampy/artery-coarse.ply");
    const Eigen::SparseMatrix<double> large =
        paired_system("x-ray-angio-data/coronary-phantom-tri3-coarse.ply");
    const auto rhs = [](Eigen::Index n) {
        Eigen::VectorXd b(n);
        for (Eigen::Index i = 0; i < n; ++i)
            b[i] = std::sin(0.07 * static_cast<double>(i)) + 0.5;
        return b;
    };
    const auto fresh_solution = [&](const Eigen::SparseMatrix<double>& A) {
        vessel::detail::PairedCholmod fresh;
        fresh.analyze_pairs(A);
        fresh.factorize(A);
        REQUIRE(fresh.info() == Eigen::Success);
        return Eigen::VectorXd(fresh.solve(rhs(A.rows())));
    };
    vessel::detail::PairedCholmod solver;
    int step = 0;
    for (const Eigen::SparseMatrix<double>* A : {&small, &large, &small, &large, &small})
    {
        CAPTURE(step);
        if (step == 3)
            solver.analyzePattern(*A);  // Eigen's analysis (CHOLMOD's ordering)
        else
            solver.analyze_pairs(*A);
        REQUIRE(solver.info() == Eigen::Success);
        const Eigen::VectorXd b = rhs(A->rows());
        const Eigen::SparseMatrix<double> full = A->selfadjointView<Eigen::Upper>();
        // The same elimination order as a new solver's: the same bits.
        const Eigen::VectorXd expected = step == 3 ? Eigen::VectorXd() : fresh_solution(*A);
        for (int repeat = 0; repeat < 2; ++repeat)  // refactorized in place
        {
            solver.factorize(*A);
            REQUIRE(solver.info() == Eigen::Success);
            const Eigen::VectorXd x = solver.solve(b);
            CHECK((full * x - b).norm() <= 1e-10 * b.norm());
            if (step != 3)
                CHECK(x == expected);
        }
        ++step;
    }
}
