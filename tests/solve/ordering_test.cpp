#include "vessel/map/arap.h"
#include "vessel/cut/boundary.h"
#include "vessel/cut/cut_metrics.h"
#include "vessel/core/errors.h"
#include "vessel/direction/geodesic.h"
#include "vessel/map/lscm.h"
#include "vessel/solve/ordering.h"

#include "support/meshes.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <numeric>

using namespace vessel;

namespace {

bool is_permutation_of_vertices(const VertexOrdering& ordering, const Mesh& mesh)
{
    std::vector<int> sorted = ordering.vertices;
    std::sort(sorted.begin(), sorted.end());
    std::vector<int> all(mesh.n_vertices());
    std::iota(all.begin(), all.end(), 0);
    return sorted == all;
}

// Cut cylinder with both rims pinned (the top rim stretched), as LSCM and ARAP get it.
struct PinnedCylinder
{
    static constexpr int n_around = 24, n_along = 12;
    Mesh mesh = test::cut_cylinder(1.0, 2.5, n_around, n_along);
    Pins rims, bottom;
    PinnedCylinder()
    {
        for (int i = 0; i <= n_around; ++i)
        {
            const double u = 2.0 * M_PI * i / n_around;
            rims.push_back({VertexHandle(i), {u, 0.0}});
            bottom.push_back(rims.back());
            rims.push_back(
                {VertexHandle(n_along * (n_around + 1) + i), {1.2 * u - 0.2 * M_PI, 2.0}});
        }
    }
};

}  // namespace

TEST_CASE("ordering: AMD orders every vertex once and a system's unknowns follow it")
{
    const Mesh mesh = test::bumped_grid(2.0, 30, 0.4);
    const VertexOrdering ordering = laplacian_ordering(mesh);
    CHECK(is_permutation_of_vertices(ordering, mesh));

    // Unknowns of every other vertex, numbered backwards: they come in the vertices' order.
    const int n = static_cast<int>(mesh.n_vertices());
    std::vector<int> unknown_of(n, -1);
    int n_unknowns = 0;
    for (int v = n - 1; v >= 0; v -= 2)
        unknown_of[v] = n_unknowns++;
    const std::vector<int> order = unknown_order(ordering, unknown_of, n_unknowns);
    REQUIRE(static_cast<int>(order.size()) == n_unknowns);
    std::vector<int> expected;
    for (const int v : ordering.vertices)
        if (unknown_of[v] >= 0)
            expected.push_back(unknown_of[v]);
    CHECK(order == expected);

    // Another mesh's ordering, a missing or a repeated unknown are refused.
    CHECK_THROWS_AS(unknown_order(ordering, std::vector<int>(n + 1, -1), 0), InvalidInputError);
    CHECK_THROWS_AS(unknown_order(ordering, unknown_of, n_unknowns + 1), InvalidInputError);
    std::vector<int> repeated = unknown_of;
    repeated[n - 2] = repeated[n - 1];
    CHECK_THROWS_AS(unknown_order(ordering, repeated, n_unknowns), InvalidInputError);
}

TEST_CASE("ordering: LSCM and ARAP solve the same maps in a given ordering")
{
    const PinnedCylinder cylinder;
    const Mesh& mesh = cylinder.mesh;
    const VertexOrdering ordering = laplacian_ordering(mesh);
    const Eigen::MatrixX2d own = lscm(mesh, cylinder.rims);
    const Eigen::MatrixX2d given = lscm(mesh, cylinder.rims, &ordering);
    CHECK((own - given).cwiseAbs().maxCoeff() < 1e-10);

    ArapOptions options;
    options.max_iterations = 30;
    Eigen::MatrixX2d refined_own = own, refined_given = own;
    const ArapSummary a = arap(mesh, refined_own, cylinder.bottom, options);
    options.prefactored = arap_prefactor(mesh, cylinder.bottom, &ordering);
    const ArapSummary b = arap(mesh, refined_given, cylinder.bottom, options);
    CHECK(b.iterations == a.iterations);
    CHECK(b.final_energy == doctest::Approx(a.final_energy).epsilon(1e-10));
    CHECK((refined_own - refined_given).cwiseAbs().maxCoeff() < 1e-9);

    const VertexOrdering other = laplacian_ordering(test::bumped_grid(1.0, 5, 0.1));
    CHECK_THROWS_AS(lscm(mesh, cylinder.rims, &other), InvalidInputError);
    CHECK_THROWS_AS(arap_prefactor(mesh, cylinder.bottom, &other), InvalidInputError);
}

TEST_CASE("ordering: the heat method and the harmonic coordinate share one ordering")
{
    const Mesh mesh = test::test_tree_phantom(2);
    const std::vector<BoundaryLoop> loops = boundary_loops(mesh);
    REQUIRE(loops.size() == 3);
    const auto ordering = std::make_shared<const VertexOrdering>(laplacian_ordering(mesh));
    REQUIRE(is_permutation_of_vertices(*ordering, mesh));

    HeatGeodesicsOptions given;
    given.ordering = ordering;
    const Eigen::VectorXd G = HeatGeodesics(mesh).distance(loops[0].vertices);
    const Eigen::VectorXd G_given = HeatGeodesics(mesh, given).distance(loops[0].vertices);
    CHECK((G - G_given).cwiseAbs().maxCoeff() < 1e-9 * G.maxCoeff());

    const Eigen::VectorXd H = HarmonicLongitudinal(mesh, loops).solve(G);
    const Eigen::VectorXd H_given = HarmonicLongitudinal(mesh, loops, ordering.get()).solve(G);
    CHECK((H - H_given).cwiseAbs().maxCoeff() < 1e-9 * H.cwiseAbs().maxCoeff());

    HeatGeodesicsOptions wrong;
    wrong.ordering = std::make_shared<const VertexOrdering>(
        laplacian_ordering(test::bumped_grid(1.0, 5, 0.1)));
    CHECK_THROWS_AS(HeatGeodesics(mesh, wrong), InvalidInputError);
}
