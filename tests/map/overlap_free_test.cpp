#include <doctest/doctest.h>

#include "support/checks.h"
#include "support/meshes.h"
#include "vessel/map/embedding.h"
#include "vessel/phantom/phantom.h"
#include "vessel/pipeline.h"

using namespace vessel;

namespace {

// The pipeline on a seeded tree phantom (edge 0.75, as test::test_tree_phantom); with
// `overlaps` = Keep, the unconstrained map (the layout's map, overlaps and all) for comparison.
FlattenResult flatten_tree(int outlets, std::uint32_t seed, OverlapPolicy overlaps)
{
    FlattenOptions options;
    options.overlaps = overlaps;
    return flatten(test::test_tree_phantom(outlets, seed), options);
}

// With default options the map of one phantom is one-to-one, and its area distortion is
// within 1.5x of the unconstrained map's with the same options (the area polish included in
// both).
void check_one_to_one(int outlets, std::uint32_t seed)
{
    CAPTURE(outlets);
    CAPTURE(seed);
    const FlattenResult r = flatten_tree(outlets, seed, FlattenOptions().overlaps);
    CHECK(r.quality.flipped_triangles == 0);
    CHECK(r.quality.overlapping_triangles == 0);  // exact pairwise test (overlap.h)
    CHECK(boundary_self_intersection(r.mesh, r.uv).first == -1);
    CHECK(r.quality.area_ratio >= 0.95);
    CHECK(r.quality.area_ratio <= 1.05);
    const FlattenResult keep = flatten_tree(outlets, seed, OverlapPolicy::Keep);
    CHECK(r.quality.mean_abs_log_area <= 1.5 * keep.quality.mean_abs_log_area);
    MESSAGE(outlets << " outlets, seed " << seed << ": mean |log area| "
                    << r.quality.mean_abs_log_area << " (unconstrained "
                    << keep.quality.mean_abs_log_area << ", " << keep.quality.overlapping_triangles
                    << " overlapping faces; ratio "
                    << r.quality.mean_abs_log_area / keep.quality.mean_abs_log_area
                    << "), mean conformal " << r.quality.mean_conformal << " (unconstrained "
                    << keep.quality.mean_conformal << ")");
}

}  // namespace

TEST_CASE("overlaps: by default, tree phantoms with 3, 10 and 30 outlets map one-to-one within "
          "1.5x of the unconstrained map's area distortion")
{
    // Issue 7's bound, by default: the area polish (lambda 0.99, Newton steps) runs on both
    // maps. Without it 1.65x on 10 outlets and 1.93x on 30 (docs/overlaps.md "Area polish by
    // default").
    for (int outlets : {3, 10, 30})
        check_one_to_one(outlets, static_cast<std::uint32_t>(outlets));
}

TEST_SUITE("slow")
{
    // No comma in the name: doctest_discover_tests looks up the suite (the `slow` label) with
    // the name unescaped, so a name with a comma would lose its label.
    TEST_CASE("overlaps: the 1.5x bound holds by default on two more seeds of 10 and 30 outlets")
    {
        // With the default case's seeds 10 and 30, three seeds each; docs/overlaps.md "Area
        // polish by default": 0.98-1.13x on 10 outlets, 1.22-1.32x on 30 (before the polish was
        // the default: 1.60-2.26x).
        for (std::uint32_t seed : {11u, 12u})
            check_one_to_one(10, seed);
        for (std::uint32_t seed : {32u, 33u})
            check_one_to_one(30, seed);
    }
}

TEST_CASE("overlaps: a boundary that crosses once SLIM has all but converged skips the scaffold "
          "phase, one-to-one and as even in area")
{
    // The carotid phantom's unconstrained SLIM crosses its boundary after a few iterations,
    // within 3% of the energy it then has: by default it stops at its last simple iterate and
    // the area polish (with its own scaffold) goes on from there.
    const Mesh mesh = carotid_phantom();
    const FlattenResult skipped = flatten(mesh, FlattenOptions{});
    FlattenOptions never;
    never.injective.scaffold_skip_gap = -1.0;
    const FlattenResult scaffolded = flatten(mesh, never);
    REQUIRE(skipped.injective.scaffold_skipped);
    CHECK(skipped.injective.scaffold_from >= 1);
    CHECK(skipped.injective.scaffold_rebuilds == 0);
    CHECK_FALSE(scaffolded.injective.scaffold_skipped);
    CHECK(scaffolded.injective.scaffold_rebuilds > 0);
    for (const FlattenResult* r : {&skipped, &scaffolded})
    {
        CHECK(r->quality.flipped_triangles == 0);
        CHECK(r->quality.overlapping_triangles == 0);
    }
    MESSAGE("mean |log area|: skipped ", skipped.quality.mean_abs_log_area_normalized,
            ", with the scaffold phase ", scaffolded.quality.mean_abs_log_area_normalized);
    CHECK(skipped.quality.mean_abs_log_area_normalized <
          1.1 * scaffolded.quality.mean_abs_log_area_normalized);
}

TEST_CASE(
    "overlaps: SLIM's steps stop short of crossing the boundary and the scaffold starts where "
    "its parts touch")
{
    // A tree from the layout circle: a whole step crosses the boundary within the first
    // iterations, where a branch squeezed against the circle folds; halved, the steps go on
    // unrolling the tree without a scaffold until its parts touch.
    const FlattenResult r = flatten_tree(10, 1, FlattenOptions().overlaps);
    REQUIRE(r.injective.scaffold_from >= 0);
    CHECK(r.injective.shortened_steps >= 1);
    // Each shortened step's iterate is simple, so the scaffold goes on from one at least as late.
    CHECK(r.injective.scaffold_from >= r.injective.shortened_steps);
    CHECK(r.injective.report.find("steps shortened to keep the boundary simple") !=
          std::string::npos);
    CHECK(r.quality.flipped_triangles == 0);
    CHECK(r.quality.overlapping_triangles == 0);
    CHECK(boundary_self_intersection(r.mesh, r.uv).first == -1);
    MESSAGE("10 outlets, seed 1: " << r.injective.report);
}
