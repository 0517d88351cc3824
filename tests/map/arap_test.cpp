#include "vessel/map/arap.h"
#include "vessel/core/errors.h"
#include "vessel/map/lscm.h"

#include "support/meshes.h"

#include <doctest/doctest.h>

#include <cmath>

using namespace vessel;

namespace {

constexpr int n_around = 24, n_along = 10;

// Cut cylinder plus a deliberately distorted LSCM start: both rims pinned with the top rim
// stretched by 20% about its middle and the length squeezed by 20%, so the start is neither
// isometric nor a similarity.
struct DistortedCylinder
{
    Mesh mesh = test::cut_cylinder(1.0, 2.5, n_around, n_along);
    Eigen::MatrixX2d uv;
    DistortedCylinder()
    {
        Pins rims;
        for (int i = 0; i <= n_around; ++i)
        {
            const double u = 2.0 * M_PI * i / n_around;
            rims.push_back({VertexHandle(i), {u, 0.0}});
            rims.push_back(
                {VertexHandle(n_along * (n_around + 1) + i), {1.2 * u - 0.2 * M_PI, 2.0}});
        }
        uv = lscm(mesh, rims);
    }
};

double area_ratio(const Mesh& mesh, const Eigen::MatrixX2d& uv)
{
    return test::uv_signed_areas(mesh, uv).sum() / face_areas(mesh).sum();
}

ArapOptions tight(ArapSolver solver)
{
    ArapOptions options;
    options.solver = solver;
    options.max_iterations = 1000;
    options.tolerance = 1e-12;
    return options;
}

// A bumped 70 x 70 grid (9800 triangles: from 8192 on, the local step, the right-hand side's
// gather and the u and v solves may run on two threads), its LSCM map and two pins for ARAP.
struct BumpedGridStart
{
    Mesh mesh = test::bumped_grid(2.0, 70, 0.6);
    Eigen::MatrixX2d start;
    Pins pins = {{VertexHandle(0), {0.0, 0.0}}, {VertexHandle(1), {0.02, 0.0}}};
    BumpedGridStart()
    {
        start = lscm(mesh, {{VertexHandle(0), {0.0, 0.0}}, {VertexHandle(70), {1.5, 0.3}}});
    }
};

}  // namespace

TEST_CASE("arap: energy is zero for rigid maps and 2 (s - 1)^2 area for scalings")
{
    const Mesh mesh = test::posed_grid(2.0, 6, Eigen::Isometry3d::Identity());
    const int n = static_cast<int>(mesh.n_vertices());
    Eigen::MatrixX2d flat(n, 2);
    for (auto v : mesh.vertices())
        flat.row(v.idx()) << mesh.point(v)[0], mesh.point(v)[1];
    const Eigen::Matrix2d R = Eigen::Rotation2Dd(0.7).toRotationMatrix();
    const Eigen::MatrixX2d rigid = (flat * R.transpose()).rowwise() + Eigen::RowVector2d(3, -1);
    CHECK(arap_energy(mesh, rigid) < 1e-24);
    const double s = 1.3, area = 4.0;
    CHECK(arap_energy(mesh, s * rigid) == doctest::Approx(2.0 * (s - 1) * (s - 1) * area));
    // A mirror image is far from every rotation.
    Eigen::MatrixX2d mirrored = flat;
    mirrored.col(0) *= -1.0;
    CHECK(arap_energy(mesh, mirrored) == doctest::Approx(4.0 * area));
}

TEST_CASE("arap: both solvers turn a distorted map of a cut cylinder into an isometry")
{
    for (ArapSolver solver : {ArapSolver::LocalGlobal, ArapSolver::Ceres})
    {
        CAPTURE(static_cast<int>(solver));
        DistortedCylinder c;
        REQUIRE(test::count_flips(c.mesh, c.uv) == 0);
        REQUIRE(test::max_edge_length_error(c.mesh, c.uv) > 0.05);
        const Pins pin = {{VertexHandle(0), c.uv.row(0).transpose()}};
        const Eigen::RowVector2d pinned_at = c.uv.row(0);

        const ArapSummary summary = arap(c.mesh, c.uv, pin, tight(solver));
        INFO(summary.report);
        CHECK(summary.iterations >= 1);
        CHECK(summary.final_energy < 1e-3 * summary.initial_energy);
        CHECK(summary.final_energy == doctest::Approx(arap_energy(c.mesh, c.uv)));
        CHECK(test::max_edge_length_error(c.mesh, c.uv) < 1e-3);
        CHECK(area_ratio(c.mesh, c.uv) == doctest::Approx(1.0).epsilon(1e-3));
        CHECK(test::count_flips(c.mesh, c.uv) == 0);
        CHECK(c.uv.row(0) == pinned_at);
    }
}

TEST_CASE("arap: on a non-developable disk both solvers decrease the energy to the same value")
{
    const Mesh mesh = test::bumped_grid(2.0, 12, 0.6);
    const int corner = 12;  // vertex (12, 0)
    const Pins lscm_pins = {{VertexHandle(0), {0.0, 0.0}}, {VertexHandle(corner), {1.5, 0.3}}};
    const Eigen::MatrixX2d start = lscm(mesh, lscm_pins);
    const Pins pin = {{VertexHandle(0), {0.0, 0.0}}};

    Eigen::MatrixX2d uv_lg = start, uv_ceres = start;
    const ArapSummary lg = arap(mesh, uv_lg, pin, tight(ArapSolver::LocalGlobal));
    const ArapSummary ce = arap(mesh, uv_ceres, pin, tight(ArapSolver::Ceres));
    INFO(lg.report);
    INFO(ce.report);
    CHECK(lg.initial_energy == doctest::Approx(ce.initial_energy).epsilon(1e-12));
    CHECK(lg.final_energy < lg.initial_energy);
    CHECK(ce.final_energy < ce.initial_energy);
    CHECK(lg.final_energy > 1e-4);  // the bump cannot be flattened isometrically
    CHECK(ce.final_energy == doctest::Approx(lg.final_energy).epsilon(1e-4));
    CHECK(test::count_flips(mesh, uv_lg) == 0);
    CHECK(test::count_flips(mesh, uv_ceres) == 0);

    // Each local/global sweep cannot increase the energy.
    Eigen::MatrixX2d uv = start;
    double previous = arap_energy(mesh, uv);
    for (int i = 0; i < 5; ++i)
    {
        ArapOptions one = tight(ArapSolver::LocalGlobal);
        one.max_iterations = 1;
        const ArapSummary s = arap(mesh, uv, pin, one);
        CHECK(s.final_energy <= previous * (1 + 1e-12));
        previous = s.final_energy;
    }
}

TEST_CASE("arap: on_iteration sees every iteration's energy and can stop the solver")
{
    const Mesh mesh = test::bumped_grid(2.0, 12, 0.6);
    const Pins lscm_pins = {{VertexHandle(0), {0.0, 0.0}}, {VertexHandle(12), {1.5, 0.3}}};
    const Eigen::MatrixX2d start = lscm(mesh, lscm_pins);
    const Pins pin = {{VertexHandle(0), {0.0, 0.0}}};
    for (ArapSolver solver : {ArapSolver::LocalGlobal, ArapSolver::Ceres})
    {
        CAPTURE(static_cast<int>(solver));
        std::vector<std::pair<int, double>> seen;
        ArapOptions options = tight(solver);
        options.on_iteration = [&](int it, double energy) {
            seen.emplace_back(it, energy);
            return true;
        };
        Eigen::MatrixX2d uv = start;
        const ArapSummary full = arap(mesh, uv, pin, options);
        INFO(full.report);
        REQUIRE(static_cast<int>(seen.size()) == full.iterations);
        for (std::size_t i = 0; i < seen.size(); ++i)
            CHECK(seen[i].first == static_cast<int>(i) + 1);
        // The reported energy is arap_energy() of the map after that iteration.
        CHECK(seen.back().second == doctest::Approx(full.final_energy).epsilon(1e-9));
        CHECK(seen.back().second == doctest::Approx(arap_energy(mesh, uv)).epsilon(1e-9));
        CHECK(seen.front().second < full.initial_energy);

        // Returning false after the second iteration stops there, not converged.
        seen.clear();
        options.on_iteration = [&](int it, double energy) {
            seen.emplace_back(it, energy);
            return it < 2;
        };
        uv = start;
        const ArapSummary stopped = arap(mesh, uv, pin, options);
        CHECK(stopped.iterations == 2);
        CHECK_FALSE(stopped.converged);
        CHECK(seen.size() == 2);
        CHECK(stopped.final_energy == doctest::Approx(seen.back().second).epsilon(1e-9));
        CHECK(stopped.final_energy > full.final_energy);
    }
}

TEST_CASE("arap: a factorization made ahead gives the same map and one for other pins is refused")
{
    const BumpedGridStart grid;
    const Mesh& mesh = grid.mesh;
    const Eigen::MatrixX2d& start = grid.start;
    const Pins& pins = grid.pins;
    ArapOptions options;
    options.max_iterations = 20;
    Eigen::MatrixX2d own = start;
    const ArapSummary a = arap(mesh, own, pins, options);

    // The factor depends on which vertices are pinned, not on their targets.
    Pins moved = pins;
    moved[1].uv = {5.0, 5.0};
    options.prefactored = arap_prefactor(mesh, moved);
    Eigen::MatrixX2d ahead = start;
    const ArapSummary b = arap(mesh, ahead, pins, options);
    CHECK(b.iterations == a.iterations);
    CHECK(b.final_energy == a.final_energy);
    CHECK(ahead == own);  // the same bits
    CHECK(a.final_energy < a.initial_energy);
    CHECK(test::count_flips(mesh, own) == 0);

    // Reusable: a second call with the same factor gives the same map again.
    Eigen::MatrixX2d again = start;
    arap(mesh, again, pins, options);
    CHECK(again == own);

    Eigen::MatrixX2d other = start;
    const Pins fewer = {pins[0]};
    CHECK_THROWS_AS(arap(mesh, other, fewer, options), InvalidInputError);
    CHECK(other == start);
    CHECK_THROWS_AS(arap_prefactor(mesh, {}), InvalidInputError);
}

TEST_CASE("arap: the local/global solver gives the same bits on one thread as on two")
{
    const BumpedGridStart grid;
    ArapOptions options;
    options.max_iterations = 20;
    Eigen::MatrixX2d two = grid.start, one = grid.start;
    const ArapSummary a = arap(grid.mesh, two, grid.pins, options);
    options.threads = 1;
    const ArapSummary b = arap(grid.mesh, one, grid.pins, options);
    CHECK(a.iterations == 20);
    CHECK(b.iterations == a.iterations);
    CHECK(b.final_energy == a.final_energy);
    CHECK(one == two);
    CHECK(a.final_energy < 0.5 * a.initial_energy);
    CHECK(test::count_flips(grid.mesh, two) == 0);
}

TEST_CASE("arap: invalid input is rejected")
{
    DistortedCylinder c;
    const Pins pin = {{VertexHandle(0), {0.0, 0.0}}};
    for (ArapSolver solver : {ArapSolver::LocalGlobal, ArapSolver::Ceres})
    {
        ArapOptions options;
        options.solver = solver;
        Eigen::MatrixX2d uv = c.uv;
        CHECK_THROWS_AS(arap(c.mesh, uv, {}, options), InvalidInputError);
        CHECK_THROWS_AS(arap(c.mesh, uv, {{VertexHandle(), {0, 0}}}, options), InvalidInputError);
        CHECK_THROWS_AS(arap(c.mesh, uv, {{VertexHandle(100000), {0, 0}}}, options),
                        InvalidInputError);
        CHECK_THROWS_AS(arap(c.mesh, uv, {pin[0], pin[0]}, options), InvalidInputError);
        Eigen::MatrixX2d short_uv = c.uv.topRows(5);
        CHECK_THROWS_AS(arap(c.mesh, short_uv, pin, options), InvalidInputError);
        Eigen::MatrixX2d nan_uv = c.uv;
        nan_uv(3, 1) = NAN;
        CHECK_THROWS_AS(arap(c.mesh, nan_uv, pin, options), InvalidInputError);
        CHECK(uv == c.uv);  // failed calls leave the map alone
    }
    ArapOptions bad;
    bad.max_iterations = 0;
    CHECK_THROWS_AS(bad.validate(), InvalidInputError);
    bad = ArapOptions{};
    bad.tolerance = -1.0;
    CHECK_THROWS_AS(bad.validate(), InvalidInputError);
    bad.tolerance = NAN;
    CHECK_THROWS_AS(bad.validate(), InvalidInputError);
    bad = ArapOptions{};
    bad.threads = 0;
    CHECK_THROWS_AS(bad.validate(), InvalidInputError);
    Eigen::MatrixX2d uv = c.uv;
    CHECK_THROWS_AS(arap(c.mesh, uv, pin, bad), InvalidInputError);
    CHECK_NOTHROW(ArapOptions{}.validate());
    CHECK_THROWS_AS(arap_energy(c.mesh, Eigen::MatrixX2d::Zero(2, 2)), InvalidInputError);
}
