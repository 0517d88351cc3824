#include <doctest/doctest.h>

#include "support/meshes.h"
#include "vessel/core/errors.h"
#include "vessel/map/injective.h"
#include "vessel/quality/metrics.h"
#include "vessel/phantom/phantom.h"

#include <array>
#include <cmath>

using namespace vessel;

TEST_CASE("injective: the Tutte embedding of a cut cylinder has no flipped triangle")
{
    const Mesh mesh = test::cut_cylinder(1.0, 6.0, 32, 40);
    const Eigen::MatrixX2d uv = tutte_embedding(mesh);
    CHECK(test::count_flips(mesh, uv) == 0);
    // Scaled to the 3D area.
    CHECK(flat_quality(mesh, uv).area_ratio == doctest::Approx(1.0));
}

TEST_CASE("injective: SLIM from the Tutte embedding unrolls a cut cylinder isometrically")
{
    const Mesh mesh = test::cut_cylinder(1.0, 6.0, 32, 40);
    Eigen::MatrixX2d uv = tutte_embedding(mesh);
    InjectiveOptions options;
    options.max_iterations = 500;
    options.tolerance = 1e-12;
    const InjectiveSummary s = injective_refine(mesh, uv, {}, options);
    CHECK(s.final_energy < s.initial_energy);
    CHECK(test::count_flips(mesh, uv) == 0);
    // Symmetric Dirichlet is 4 x area at an isometry.
    const double area = face_areas(mesh).sum();
    CHECK(s.final_energy == doctest::Approx(4.0 * area).epsilon(1e-4));
    CHECK(test::max_edge_length_error(mesh, uv) < 1e-2);
    const FlatQuality q = flat_quality(mesh, uv);
    CHECK(q.area_ratio == doctest::Approx(1.0).epsilon(1e-3));
}

TEST_CASE("injective: momentum reaches the isometry of a cut cylinder in fewer iterations")
{
    const Mesh mesh = test::cut_cylinder(1.0, 6.0, 32, 40);
    const double isometry = 4.0 * face_areas(mesh).sum();
    // Iterations until the energy is within 1e-4 of the isometry's (the tolerance stops there).
    const auto iterations = [&](double momentum) {
        Eigen::MatrixX2d uv = tutte_embedding(mesh);
        InjectiveOptions options;
        options.max_iterations = 500;
        options.tolerance = 1e-12;
        options.momentum = momentum;
        int reached = -1;
        for (int its = 1; its <= 200 && reached < 0; ++its)
        {
            Eigen::MatrixX2d step = uv;
            options.max_iterations = its;
            const InjectiveSummary s = injective_refine(mesh, step, {}, options);
            CHECK(test::count_flips(mesh, step) == 0);
            if (s.final_energy < isometry * (1.0 + 1e-4))
                reached = its;
        }
        return reached;
    };
    const int plain = iterations(0.0);
    const int heavy = iterations(0.5);
    MESSAGE("iterations to the isometry: plain ", plain, ", momentum 0.5 ", heavy);
    REQUIRE(plain > 0);
    REQUIRE(heavy > 0);
    CHECK(heavy < plain);
}

TEST_CASE("injective: pins hold and every iterate stays flip-free on a bumped disk")
{
    const Mesh mesh = test::bumped_grid(4.0, 24, 1.5);
    Eigen::MatrixX2d uv = tutte_embedding(mesh);
    const Pins pins = {{VertexHandle(0), uv.row(0).transpose()}};
    for (int iterations : {1, 2, 5, 20})
    {
        Eigen::MatrixX2d step = uv;
        InjectiveOptions options;
        options.max_iterations = iterations;
        injective_refine(mesh, step, pins, options);
        CHECK(test::count_flips(mesh, step) == 0);
        CHECK((step.row(0) - uv.row(0)).norm() < 1e-4);
    }
}

TEST_CASE("injective: a flipped start, a non-disk and bad options are refused")
{
    const Mesh mesh = test::cut_cylinder(1.0, 2.0, 12, 6);
    Eigen::MatrixX2d uv = tutte_embedding(mesh);
    uv.col(0) *= -1.0;  // mirror: every triangle flipped
    CHECK_THROWS_AS(injective_refine(mesh, uv, {}), InvalidInputError);
    Eigen::MatrixX2d wrong_size(3, 2);
    CHECK_THROWS_AS(injective_refine(mesh, wrong_size, {}), InvalidInputError);
    CHECK_THROWS_AS(tutte_embedding(open_cylinder(1.0, 2.0, 12, 6)), TopologyError);
    // Each bad field on its own is refused.
    const std::array<void (*)(InjectiveOptions&), 7> spoil = {
        [](InjectiveOptions& o) { o.max_iterations = 0; },
        [](InjectiveOptions& o) { o.scaffold_rebuild_every = 0; },
        [](InjectiveOptions& o) { o.scaffold_passes = 0; },
        [](InjectiveOptions& o) { o.crossing_patience = 0; },
        [](InjectiveOptions& o) { o.momentum = 1.0; },
        [](InjectiveOptions& o) { o.momentum = -0.1; },
        [](InjectiveOptions& o) { o.scaffold_skip_gap = INFINITY; },
    };
    for (const auto& make_bad : spoil)
    {
        InjectiveOptions bad;
        make_bad(bad);
        CHECK_THROWS_AS(bad.validate(), InvalidInputError);
    }
}
