#include <doctest/doctest.h>

#include "support/meshes.h"
#include "vessel/map/embedding.h"
#include "vessel/map/injective.h"
#include "vessel/io/io.h"
#include "vessel/pipeline.h"
#include "vessel/map/untangle.h"
#include "vessel/check/validation.h"

#include <array>
#include <utility>

using namespace vessel;

TEST_CASE("untangle: a fold on a flat grid is removed by moving only the vertices near it")
{
    const int n = 20;
    const Mesh mesh = test::posed_grid(1.0, n, Eigen::Isometry3d::Identity());
    Eigen::MatrixX2d uv = test::planar_uv(mesh);
    const Eigen::MatrixX2d original = uv;
    // Push an interior vertex across two rings of its neighbours: a local fold.
    const int centre = (n / 2) * (n + 1) + n / 2;
    uv.row(centre) += Eigen::RowVector2d(2.5 / n, 1.5 / n);
    REQUIRE(test::count_flips(mesh, uv) > 0);

    const UntangleSummary s = untangle(mesh, uv, {});
    CHECK(s.flipped_before > 0);
    CHECK(s.flipped_after == 0);
    CHECK(test::count_flips(mesh, uv) == 0);
    int moved = 0;
    for (int v = 0; v < uv.rows(); ++v)
        moved += (uv.row(v) - original.row(v)).norm() > 1e-12;
    CHECK(moved <= s.free_vertices);
    CHECK(s.free_vertices < static_cast<int>(mesh.n_vertices()) / 2);
}

TEST_CASE("untangle: pinned vertices do not move and a map without flips is left alone")
{
    const Mesh mesh = test::posed_grid(1.0, 10, Eigen::Isometry3d::Identity());
    Eigen::MatrixX2d uv = test::planar_uv(mesh);
    const Eigen::MatrixX2d original = uv;
    const UntangleSummary clean = untangle(mesh, uv, {});
    CHECK(clean.flipped_before == 0);
    CHECK(clean.rounds == 0);
    CHECK((uv - original).norm() == 0.0);

    const int centre = 5 * 11 + 5;
    uv.row(centre) += Eigen::RowVector2d(0.25, 0.15);
    Pins pins;
    for (int v : {0, 10, 120})
        pins.push_back({VertexHandle(v), original.row(v).transpose()});
    const UntangleSummary s = untangle(mesh, uv, pins);
    CHECK(s.flipped_after == 0);
    for (const auto& pin : pins)
        CHECK((uv.row(pin.vertex.idx()).transpose() - pin.uv).norm() == 0.0);
}

TEST_CASE("embedding: a simple map boundary passes, a folded-over one is found")
{
    const Mesh mesh = test::posed_grid(1.0, 8, Eigen::Isometry3d::Identity());
    Eigen::MatrixX2d uv = test::planar_uv(mesh);
    CHECK(boundary_self_intersection(mesh, uv).first == -1);
    // Drag the corner (8, 8) across the opposite side: its boundary edges now cross others.
    uv.row(8 * 9 + 8) << -0.5, -0.5;
    const auto crossing = boundary_self_intersection(mesh, uv);
    CHECK(crossing.first >= 0);
    CHECK(crossing.second >= 0);
    CHECK(mesh.is_boundary(HalfedgeHandle(crossing.first)));
    CHECK(mesh.is_boundary(HalfedgeHandle(crossing.second)));
}

TEST_CASE("injective: with a scaffold, SLIM from the Tutte map keeps a cut cylinder one-to-one")
{
    // With one line search per step (Jiang et al.), and with steps that a scaffold triangle
    // stopped continued on a new triangulation (the default). The triangulation is kept while
    // no scaffold triangle stops a step, and only a step that a scaffold triangle (not a surface
    // one) stopped is continued.
    const Mesh mesh = test::cut_cylinder(1.0, 6.0, 24, 30);
    for (const int passes : {1, 4})
    {
        CAPTURE(passes);
        Eigen::MatrixX2d uv = tutte_embedding(mesh);
        InjectiveOptions options;
        options.scaffold = true;
        options.max_iterations = 30;
        options.scaffold_passes = passes;
        const InjectiveSummary s = injective_refine(mesh, uv, {}, options);
        CHECK(s.final_energy < s.initial_energy);
        CHECK(test::count_flips(mesh, uv) == 0);
        CHECK(boundary_self_intersection(mesh, uv).first == -1);
        // Every continued step triangulates again (a tried one that is not accepted too), by
        // edge flips or anew: the first triangulation, one per continued step, and one per
        // iteration after a stopped step at most. Only continued steps refit by flips.
        const int triangulations = s.scaffold_rebuilds + s.scaffold_refits;
        CHECK(s.scaffold_passes <= (passes - 1) * s.iterations);
        CHECK(s.scaffold_rebuilds >= 1);
        CHECK(triangulations >= 1 + s.scaffold_passes);
        CHECK(triangulations <= passes * s.iterations);
        if (passes == 1)
            CHECK(s.scaffold_refits == 0);
        else
            CHECK(s.scaffold_refits > 0);
        // Edge flips keep the global step's pattern: only the mesher's triangulations analyse
        // it anew.
        CHECK(s.pattern_analyses == s.scaffold_rebuilds);
        MESSAGE(s.report);
    }
}

TEST_CASE("injective: on a map of more than 100k vertices (the global step ordered by METIS) "
          "SLIM with a scaffold stays flip-free and one-to-one")
{
    const Mesh mesh = test::cut_cylinder(1.0, 6.0, 200, 520);
    REQUIRE(mesh.n_vertices() > 100000);
    Eigen::MatrixX2d uv = tutte_embedding(mesh);
    InjectiveOptions options;
    options.scaffold = true;
    options.max_iterations = 3;
    const InjectiveSummary s = injective_refine(mesh, uv, {}, options);
    CHECK(s.final_energy < s.initial_energy);
    CHECK(test::count_flips(mesh, uv) == 0);
    CHECK(boundary_self_intersection(mesh, uv).first == -1);
    MESSAGE(s.report);
}

TEST_CASE("pipeline: on a real tree every overlap policy returns a flip-free map and the "
          "default's does not overlap itself")
{
    const TreeSurface surface =
        load_tree_surface(std::string(VESSEL_SHARED_DATA) + "/vampy/artery-coarse.ply");
    for (const auto policy :
         {OverlapPolicy::Keep, OverlapPolicy::Restart, OverlapPolicy::Prevent})
    {
        FlattenOptions options;
        options.overlaps = policy;
        const FlattenResult r = flatten(surface.mesh, options);
        CAPTURE(static_cast<int>(policy));
        CHECK(r.quality.flipped_triangles == 0);
        CHECK(r.untangle.flipped_after == 0);
        if (policy == OverlapPolicy::Prevent)
            CHECK(boundary_self_intersection(r.mesh, r.uv).first == -1);
    }
}
