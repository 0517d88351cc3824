#include "solve/paired_symbolic.h"
#include "solve/cholmod_common.h"
#include "solve/paired_cholmod.h"
#include "solve/paired_system.h"
#include "support/meshes.h"

#include <doctest/doctest.h>
#include <Eigen/CholmodSupport>
#include <Eigen/Sparse>

#include <array>
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

using vessel::detail::CholmodCommon;
using vessel::detail::vertex_graph;
using vessel::detail::VertexGraph;

namespace {

// detail::paired_laplacian_system() of a real vessel mesh with each vertex's (u, v) entry
// stored too (an explicit zero), so that every pair's block is whole, as in SLIM's and the
// area polish's systems.
Eigen::SparseMatrix<double> whole_block_system(const char* relative)
{
    const Eigen::SparseMatrix<double> A =
        vessel::detail::paired_laplacian_system(vessel::test::shared_tree_mesh(relative));
    std::vector<Eigen::Triplet<double>> entries;
    for (int j = 0; j < A.outerSize(); ++j)
        for (Eigen::SparseMatrix<double>::InnerIterator it(A, j); it; ++it)
            entries.emplace_back(static_cast<int>(it.row()), j, it.value());
    for (Eigen::Index i = 0; i < A.rows() / 2; ++i)
        entries.emplace_back(static_cast<int>(2 * i), static_cast<int>(2 * i + 1), 0.0);
    Eigen::SparseMatrix<double> whole(A.rows(), A.cols());
    whole.setFromTriplets(entries.begin(), entries.end());
    whole.makeCompressed();
    return whole;
}

template <class T>
std::vector<T> array_of(const void* data, std::size_t size)
{
    const auto* begin = static_cast<const T*>(data);
    return std::vector<T>(begin, begin + size);
}

// Every field of \p expected (CHOLMOD's analysis) that a factorization or solve reads.
void check_same_factor(const cholmod_factor& got, const cholmod_factor& expected)
{
    REQUIRE(got.n == expected.n);
    REQUIRE(got.is_super == expected.is_super);
    REQUIRE(got.nsuper == expected.nsuper);
    CHECK(got.is_ll == expected.is_ll);
    CHECK(got.xtype == expected.xtype);
    CHECK(got.ordering == expected.ordering);
    CHECK(got.ssize == expected.ssize);
    CHECK(got.xsize == expected.xsize);
    CHECK(got.maxcsize == expected.maxcsize);
    CHECK(got.maxesize == expected.maxesize);
    const std::size_t n = expected.n, nsuper = expected.nsuper;
    CHECK(array_of<int>(got.Perm, n) == array_of<int>(expected.Perm, n));
    CHECK(array_of<int>(got.ColCount, n) == array_of<int>(expected.ColCount, n));
    CHECK(array_of<int>(got.super, nsuper + 1) == array_of<int>(expected.super, nsuper + 1));
    CHECK(array_of<int>(got.pi, nsuper + 1) == array_of<int>(expected.pi, nsuper + 1));
    CHECK(array_of<int>(got.px, nsuper + 1) == array_of<int>(expected.px, nsuper + 1));
    CHECK(array_of<int>(got.s, expected.ssize) == array_of<int>(expected.s, expected.ssize));
}

}  // namespace

TEST_CASE(
    "paired symbolic: the vertex graph's analysis is CHOLMOD's analysis of the paired "
    "matrix, field for field, under its relaxation and postorder settings")
{
    struct Relaxation
    {
        std::array<std::size_t, 3> nrelax;
        std::array<double, 3> zrelax;
    };
    const Relaxation defaults{{4, 16, 48}, {0.8, 0.1, 0.05}};
    const Relaxation wide{{8, 32, 96}, {0.5, 0.3, 0.2}};
    const Relaxation none{{0, 0, 0}, {0.0, 0.0, 0.0}};
    for (const char* mesh : {"x-ray-angio-data/coronary-phantom-tri3-coarse.ply",
                             "vampy/artery-coarse.ply", "svfsi-tests/pulmonary-glenn-wall.ply"})
    {
        const Eigen::SparseMatrix<double> A = whole_block_system(mesh);
        VertexGraph graph = vertex_graph(A);
        REQUIRE(graph.whole_blocks);
        cholmod_sparse pattern = graph.view();
        const int n = static_cast<int>(A.cols()) / 2;
        for (const Relaxation& relaxation : {defaults, wide, none})
            for (const int postorder : {1, 0})
            {
                CAPTURE(mesh);
                CAPTURE(relaxation.nrelax[1]);
                CAPTURE(postorder);
                CholmodCommon common;
                common.c.supernodal = CHOLMOD_SUPERNODAL;
                common.c.postorder = postorder;
                for (int k = 0; k < 3; ++k)
                {
                    common.c.nrelax[k] = relaxation.nrelax[k];
                    common.c.zrelax[k] = relaxation.zrelax[k];
                }
                std::vector<int> order(static_cast<std::size_t>(n));
                REQUIRE(cholmod_amd(&pattern, nullptr, 0, order.data(), &common.c));
                std::vector<int> paired(2 * order.size());
                for (std::size_t k = 0; k < order.size(); ++k)
                {
                    paired[2 * k] = 2 * order[k];
                    paired[2 * k + 1] = 2 * order[k] + 1;
                }
                cholmod_sparse view = Eigen::viewAsCholmod(A.selfadjointView<Eigen::Upper>());
                cholmod_factor* expected =
                    vessel::detail::analyze_in_order(view, &paired, common.c);
                cholmod_factor* got = vessel::detail::paired_symbolic(pattern, order, common.c);
                REQUIRE(expected != nullptr);
                REQUIRE(got != nullptr);
                check_same_factor(*got, *expected);
                cholmod_free_factor(&expected, &common.c);
                cholmod_free_factor(&got, &common.c);
            }
    }
}

TEST_CASE(
    "paired symbolic: PairedCholmod solves with the same bits as with CHOLMOD's analysis "
    "of the paired order, and keeps CHOLMOD's analysis where a pair's block is not whole")
{
    const Eigen::SparseMatrix<double> whole =
        whole_block_system("x-ray-angio-data/coronary-phantom-tri3-coarse.ply");
    Eigen::VectorXd b(whole.rows());
    for (Eigen::Index i = 0; i < b.size(); ++i)
        b[i] = std::sin(0.07 * static_cast<double>(i)) + 0.5;

    vessel::detail::PairedCholmod paired;
    paired.analyze_pairs(whole);
    REQUIRE(paired.info() == Eigen::Success);
    paired.factorize(whole);
    REQUIRE(paired.info() == Eigen::Success);
    const Eigen::VectorXd x = paired.solve(b);

    // The same AMD order of the vertex graph, analysed by CHOLMOD on the whole matrix.
    VertexGraph graph = vertex_graph(whole);
    CHECK(graph.whole_blocks);
    cholmod_sparse pattern = graph.view();
    CholmodCommon common;
    std::vector<int> order(static_cast<std::size_t>(whole.cols() / 2));
    REQUIRE(cholmod_amd(&pattern, nullptr, 0, order.data(), &common.c));
    std::vector<int> pairs(2 * order.size());
    for (std::size_t k = 0; k < order.size(); ++k)
    {
        pairs[2 * k] = 2 * order[k];
        pairs[2 * k + 1] = 2 * order[k] + 1;
    }
    vessel::detail::OrderedCholmod<Eigen::Upper> cholmod;
    cholmod.analyze_given(whole, pairs);
    REQUIRE(cholmod.info() == Eigen::Success);
    cholmod.factorize(whole);
    REQUIRE(cholmod.info() == Eigen::Success);
    CHECK(cholmod.solve(b) == x);
    const Eigen::SparseMatrix<double> full = whole.selfadjointView<Eigen::Upper>();
    CHECK((full * x - b).norm() <= 1e-10 * b.norm());

    // Without the (u, v) entries on the diagonal (LSCM's pattern) the pairs' blocks are not
    // whole, and the vertex graph's factor would hold entries CHOLMOD's does not: CHOLMOD
    // analyses the paired order itself, to the same bits.
    const Eigen::SparseMatrix<double> partial = vessel::detail::paired_laplacian_system(
        vessel::test::shared_tree_mesh("x-ray-angio-data/coronary-phantom-tri3-coarse.ply"));
    vessel::detail::PairedCholmod lscm_like;
    lscm_like.analyze_pairs(partial);
    REQUIRE(lscm_like.info() == Eigen::Success);
    lscm_like.factorize(partial);
    REQUIRE(lscm_like.info() == Eigen::Success);
    VertexGraph partial_graph = vertex_graph(partial);
    CHECK_FALSE(partial_graph.whole_blocks);
    cholmod_sparse partial_pattern = partial_graph.view();
    REQUIRE(cholmod_amd(&partial_pattern, nullptr, 0, order.data(), &common.c));
    for (std::size_t k = 0; k < order.size(); ++k)
    {
        pairs[2 * k] = 2 * order[k];
        pairs[2 * k + 1] = 2 * order[k] + 1;
    }
    vessel::detail::OrderedCholmod<Eigen::Upper> partial_cholmod;
    partial_cholmod.analyze_given(partial, pairs);
    partial_cholmod.factorize(partial);
    REQUIRE(partial_cholmod.info() == Eigen::Success);
    const Eigen::VectorXd y = lscm_like.solve(b);
    CHECK(partial_cholmod.solve(b) == y);
    const Eigen::SparseMatrix<double> partial_full = partial.selfadjointView<Eigen::Upper>();
    CHECK((partial_full * y - b).norm() <= 1e-10 * b.norm());
}
