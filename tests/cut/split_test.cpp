#include <doctest/doctest.h>

#include "support/meshes.h"
#include "vessel/cut/boundary.h"
#include "vessel/core/errors.h"
#include "vessel/phantom/phantom.h"
#include "vessel/pipeline.h"
#include "vessel/cut/split.h"
#include "vessel/check/validation.h"

#include <string>

using namespace vessel;

namespace {

double area(const RawMesh& raw)
{
    double sum = 0.0;
    for (const auto& f : raw.faces)
        sum += 0.5 * (raw.points[f[1]] - raw.points[f[0]])
                         .cross(raw.points[f[2]] - raw.points[f[0]])
                         .norm();
    return sum;
}

Mesh small_tree(int outlets)
{
    return test::test_tree_phantom(outlets, 3, 1.0);
}

}  // namespace

TEST_CASE("split: every outlet pair is either cut off as a valid tree or refused as no subtree")
{
    const Mesh mesh = small_tree(4);
    const RawMesh whole = to_raw_mesh(mesh);
    const int n_loops = static_cast<int>(boundary_loops(mesh).size());
    REQUIRE(n_loops == 5);
    int split = 0, refused = 0;
    for (int a = 1; a < n_loops; ++a)
        for (int b = a + 1; b < n_loops; ++b)
        {
            std::vector<TreePiece> pieces;
            try
            {
                pieces = split_tree(mesh, {{a, b}});
            }
            catch (const InvalidInputError& e)
            {
                CHECK(std::string(e.what()).find("not one subtree") != std::string::npos);
                ++refused;
                continue;
            }
            ++split;
            REQUIRE(pieces.size() == 2);
            CHECK(pieces[0].loops == std::vector<int>{a, b});
            CHECK(pieces[0].level > 0.0);
            CHECK(pieces[1].loops.size() == static_cast<std::size_t>(n_loops - 2));
            CHECK(pieces[1].loops.front() == 0);  // the rest keeps the inlet
            // The slice is exact: the pieces tile the surface.
            CHECK(area(pieces[0].mesh) + area(pieces[1].mesh) ==
                  doctest::Approx(area(whole)).epsilon(1e-9));
            // Each piece is a valid tree with one new ring.
            CHECK(boundary_loops(make_tree_surface(pieces[0].mesh).mesh).size() == 3);
            CHECK(boundary_loops(make_tree_surface(pieces[1].mesh).mesh).size() ==
                  static_cast<std::size_t>(n_loops - 1));
        }
    CHECK(split >= 1);
    CHECK(refused >= 1);
}

TEST_CASE("split: one outlet at a time, in several sets, and each piece flattens")
{
    const Mesh mesh = small_tree(4);
    const std::vector<TreePiece> pieces = split_tree(mesh, {{1}, {3}});
    REQUIRE(pieces.size() == 3);
    CHECK(pieces[0].loops == std::vector<int>{1});
    CHECK(pieces[1].loops == std::vector<int>{3});
    CHECK(pieces[2].loops == std::vector<int>{0, 2, 4});
    for (const TreePiece& piece : pieces)
    {
        const TreeSurface surface = make_tree_surface(piece.mesh);
        const FlattenResult r = flatten(surface.mesh);
        CHECK(r.quality.flipped_triangles == 0);
        MESSAGE("piece with loops " << piece.loops.size() << " + rings: overlapping triangles "
                                    << r.quality.overlapping_triangles << ", mean |log area| "
                                    << r.quality.mean_abs_log_area);
    }
}

TEST_CASE("split: bad sets are refused")
{
    const Mesh mesh = small_tree(3);
    CHECK_THROWS_AS(split_tree(mesh, {{0}}), InvalidInputError);      // the inlet
    CHECK_THROWS_AS(split_tree(mesh, {{7}}), InvalidInputError);      // no such loop
    CHECK_THROWS_AS(split_tree(mesh, {{}}), InvalidInputError);       // empty
    CHECK_THROWS_AS(split_tree(mesh, {{1}, {1}}), InvalidInputError);  // overlapping sets
    CHECK_THROWS_AS(split_tree(mesh, {{1, 2, 3}}), InvalidInputError);  // every outlet
    SplitOptions options;
    options.offset_radii = 0.0;
    CHECK_THROWS_AS(split_tree(mesh, {{1}}, options), InvalidInputError);
}
