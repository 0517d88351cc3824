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
    const Mesh mesh = test::cut_cylinder(1.0, 6.0, 24, 30);
    // Triangulated anew every iteration (Jiang et al.), and reused for up to 10 iterations;
    // with one line search per step, or with blocked steps continued on a new triangulation;
    // last, kept while no scaffold triangle stops the step (the default).
    struct Setting
    {
        int every, passes;
        bool keep;
    };
    for (const auto [every, passes, keep] : {Setting{1, 1, false}, Setting{1, 4, false},
                                             Setting{10, 4, false}, Setting{1, 4, true}})
    {
        CAPTURE(every);
        CAPTURE(passes);
        CAPTURE(keep);
        Eigen::MatrixX2d uv = tutte_embedding(mesh);
        InjectiveOptions options;
        options.scaffold = true;
        options.max_iterations = 30;
        options.scaffold_rebuild_every = every;
        options.scaffold_passes = passes;
        options.scaffold_keep_unblocked = keep;
        const InjectiveSummary s = injective_refine(mesh, uv, {}, options);
        CHECK(s.final_energy < s.initial_energy);
        CHECK(test::count_flips(mesh, uv) == 0);
        CHECK(boundary_self_intersection(mesh, uv).first == -1);
        // Every continued step triangulates anew (a tried one that is not accepted too), and
        // the next iteration triangulates again.
        CHECK(s.scaffold_passes <= (passes - 1) * s.iterations);
        if (keep)  // the first triangulation, and one per continued step
            CHECK(s.scaffold_rebuilds >= 1 + s.scaffold_passes);
        else
            CHECK(s.scaffold_rebuilds >= (s.iterations + every - 1) / every + s.scaffold_passes);
        CHECK(s.scaffold_rebuilds <= passes * s.iterations);
        if (every == 1 && passes == 1)
            CHECK(s.scaffold_rebuilds == s.iterations);
        if (every > 1)
            CHECK(s.scaffold_rebuilds < s.iterations + s.scaffold_passes);
        MESSAGE(s.report);
    }
}

TEST_CASE("injective: steps stopped by a surface triangle are not continued on a new scaffold")
{
    // Re-triangulating the scaffold only for steps that a scaffold triangle stopped keeps the
    // map one-to-one and flip-free with no more triangulations than doing it for every stopped
    // step (on this cut cylinder scaffold triangles stop all of them: both runs are the same).
    const Mesh mesh = test::cut_cylinder(1.0, 6.0, 24, 30);
    std::array<InjectiveSummary, 2> runs;
    for (const bool continue_surface : {false, true})
    {
        CAPTURE(continue_surface);
        Eigen::MatrixX2d uv = tutte_embedding(mesh);
        InjectiveOptions options;
        options.scaffold = true;
        options.max_iterations = 30;
        options.scaffold_continue_surface_blocked = continue_surface;
        const InjectiveSummary s = injective_refine(mesh, uv, {}, options);
        CHECK(s.final_energy < s.initial_energy);
        CHECK(test::count_flips(mesh, uv) == 0);
        CHECK(boundary_self_intersection(mesh, uv).first == -1);
        runs[continue_surface ? 1 : 0] = s;
        MESSAGE(s.report);
    }
    CHECK(runs[0].scaffold_rebuilds <= runs[1].scaffold_rebuilds);
    CHECK(runs[0].scaffold_passes <= runs[1].scaffold_passes);
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
