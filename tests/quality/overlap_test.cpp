#include <doctest/doctest.h>

#include "support/checks.h"
#include "support/meshes.h"
#include "vessel/core/errors.h"
#include "vessel/quality/metrics.h"
#include "vessel/quality/overlap.h"
#include "vessel/phantom/phantom.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>

using namespace vessel;

namespace {

// Two triangles covering the axis-aligned square [x0, x0 + s] x [y0, y0 + s].
void add_square(std::vector<Triangle2>& soup, double x0, double y0, double s)
{
    const Eigen::Vector2d a(x0, y0), b(x0 + s, y0), c(x0 + s, y0 + s), d(x0, y0 + s);
    soup.push_back({a, b, c});
    soup.push_back({a, c, d});
}


}  // namespace

TEST_CASE("overlap: two squares overlapping by a known area")
{
    std::vector<Triangle2> soup;
    add_square(soup, 0.0, 0.0, 2.0);
    add_square(soup, 1.0, 1.5, 2.0);  // overlap [1, 2] x [1.5, 2]: area 0.5
    const OverlapReport r = find_overlaps(soup);
    CHECK(r.overlap_area == doctest::Approx(0.5).epsilon(1e-12));
    CHECK(r.map_area == doctest::Approx(8.0));
    CHECK(r.overlap_fraction == doctest::Approx(0.5 / 8.0));
    CHECK(r.overlapping_triangles() == 4);
    for (const auto& [f, g] : r.pairs)
        CHECK(f / 2 != g / 2);  // never the two halves of one square
}

TEST_CASE("overlap: shared edges, shared corners and touching boundaries are not overlaps")
{
    std::vector<Triangle2> soup;
    add_square(soup, 0.0, 0.0, 1.0);
    add_square(soup, 1.0, 0.0, 1.0);  // shares an edge
    add_square(soup, 2.0, 1.0, 1.0);  // shares a corner
    add_square(soup, 0.3, 1.0, 0.1);  // lies on the top edge
    CHECK(find_overlaps(soup).pairs.empty());
    // Coordinates that are not representable exactly: the shared edge is still exact.
    const Eigen::Vector2d p(0.1, 0.2), q(0.3 + 1e-17, 0.7 / 3.0);
    CHECK_FALSE(interiors_intersect({p, q, Eigen::Vector2d(0.0, 1.0)},
                                    {q, p, Eigen::Vector2d(1.0, -1.0)}));
    CHECK(interiors_intersect({p, q, Eigen::Vector2d(0.0, 1.0)},
                              {q, p, Eigen::Vector2d(0.0, 0.9)}));
    // A zero-area triangle has no interior.
    CHECK_FALSE(interiors_intersect({Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 1),
                                     Eigen::Vector2d(2, 2)},
                                    {Eigen::Vector2d(0, 1), Eigen::Vector2d(2, 1),
                                     Eigen::Vector2d(1, 0)}));
}

TEST_CASE("overlap: a strip folded back over itself overlaps by the folded area")
{
    // A 8 x 8 grid of side 4, folded at x = 3: the last column of quads (x in [3, 4]) is mirrored
    // onto [2, 3] and covers it a second time: overlap area 1 x 4, and those faces are flipped.
    const Mesh grid = plane_grid(4.0, 8);
    Eigen::MatrixX2d uv = test::planar_uv(grid);
    for (Eigen::Index i = 0; i < uv.rows(); ++i)
        if (uv(i, 0) > 3.0)
            uv(i, 0) = 6.0 - uv(i, 0);
    const OverlapReport r = find_overlaps(grid, uv);
    CHECK(r.overlap_area == doctest::Approx(4.0).epsilon(1e-9));
    const FlatQuality q = flat_quality(grid, uv);
    CHECK(q.flipped_triangles == 2 * 2 * 8);  // two columns of quads beyond x = 3
    CHECK(q.overlapping_triangles == 4 * 2 * 8);  // they and the two columns they cover
    CHECK(q.overlap_area == doctest::Approx(4.0).epsilon(1e-9));
    CHECK(q.overlap_fraction == doctest::Approx(4.0 / 16.0).epsilon(1e-9));
}

TEST_CASE("overlap: an unrolled cut cylinder has none, a cylinder wrapped past 360 degrees does")
{
    const int n_around = 20, n_along = 6;
    const double radius = 1.0, length = 3.0;
    const Mesh cylinder = test::cut_cylinder(radius, length, n_around, n_along);
    Eigen::MatrixX2d unrolled(cylinder.n_vertices(), 2), wrapped(cylinder.n_vertices(), 2);
    for (int j = 0; j <= n_along; ++j)
        for (int i = 0; i <= n_around; ++i)
        {
            const int v = j * (n_around + 1) + i;
            const double z = length * j / n_along;
            unrolled.row(v) << 2.0 * M_PI * radius * i / n_around, z;
            // An annulus of radii [4, 4 + length] swept through 450 degrees; column i + 16
            // gets exactly column i's corners (angles taken modulo 360 degrees).
            const double angle = 2.5 * M_PI * (i % 16) / n_around, r = 4.0 + z;
            wrapped.row(v) << r * std::cos(angle), r * std::sin(angle);
        }
    CHECK(find_overlaps(cylinder, unrolled).pairs.empty());
    const OverlapReport r = find_overlaps(cylinder, wrapped);
    // Columns 16..19 (the last 90 degrees) cover columns 0..3 a second time, triangle on
    // triangle; each column's quads are chord trapezoids of total area (7^2 - 4^2) sin(step) / 2.
    const double quarter = 4 * 0.5 * (7.0 * 7.0 - 4.0 * 4.0) * std::sin(2.5 * M_PI / n_around);
    CHECK(r.overlap_area == doctest::Approx(quarter).epsilon(1e-9));
    CHECK(r.pairs.size() == 4 * 2 * n_along);
    CHECK(r.overlapping_triangles() == 2 * 4 * 2 * n_along);
}

TEST_CASE("overlap: a map certified one-to-one by its boundary reports what the grid search reports")
{
    // find_overlaps(mesh, uv) skips the pairwise search where every face turns the same way and
    // the boundary is a simple polygon; where either fails it searches. Either way its report
    // must be the triangle soup's.
    const int n_around = 20, n_along = 6;
    const Mesh cylinder = test::cut_cylinder(1.0, 3.0, n_around, n_along);
    const auto soup_of = [&](const Eigen::MatrixX2d& uv) {
        std::vector<Triangle2> soup;
        for (auto f : cylinder.faces())
        {
            Triangle2 t;
            int k = 0;
            for (auto v : f.vertices())
                t[k++] = uv.row(v.idx()).transpose();
            soup.push_back(t);
        }
        return soup;
    };
    const auto same_report = [&](const Eigen::MatrixX2d& uv) {
        const OverlapReport fast = find_overlaps(cylinder, uv);
        const OverlapReport searched = find_overlaps(soup_of(uv));
        CHECK(fast.pairs == searched.pairs);
        CHECK(fast.triangles == searched.triangles);
        CHECK(fast.overlap_area == doctest::Approx(searched.overlap_area));
        CHECK(fast.map_area == doctest::Approx(searched.map_area));
        return searched.pairs.size();
    };
    Eigen::MatrixX2d unrolled(cylinder.n_vertices(), 2), spiral(cylinder.n_vertices(), 2);
    for (int j = 0; j <= n_along; ++j)
        for (int i = 0; i <= n_around; ++i)
        {
            const int v = j * (n_around + 1) + i;
            unrolled.row(v) << 2.0 * M_PI * i / n_around, 3.0 * j / n_along;
            // A strip swept through 400 degrees with its radius growing by less than its width
            // per turn: every face keeps its orientation, the two ends lie over each other.
            const double angle = (400.0 / 360.0) * 2.0 * M_PI * i / n_around;
            const double r = 4.0 + 0.5 * angle / (2.0 * M_PI) + 3.0 * j / n_along;
            spiral.row(v) << r * std::cos(angle), r * std::sin(angle);
        }
    CHECK(same_report(unrolled) == 0);
    Eigen::MatrixX2d mirrored = unrolled;
    mirrored.col(0) *= -1.0;  // every face turned the other way: still one-to-one
    CHECK(same_report(mirrored) == 0);
    CHECK(same_report(spiral) > 0);
    // The strip closed into an annulus: its seam's two sides lie on each other, the boundary
    // touches itself (no certificate), and touching is no overlap.
    Eigen::MatrixX2d annulus(cylinder.n_vertices(), 2);
    for (int j = 0; j <= n_along; ++j)
        for (int i = 0; i <= n_around; ++i)
        {
            const double angle = 2.0 * M_PI * (i % n_around) / n_around, r = 4.0 + 3.0 * j / n_along;
            annulus.row(j * (n_around + 1) + i) << r * std::cos(angle), r * std::sin(angle);
        }
    CHECK(same_report(annulus) == 0);
    // One face flipped: no certificate, the search finds it.
    Eigen::MatrixX2d flipped = unrolled;
    flipped.row((n_along / 2) * (n_around + 1) + n_around / 2) +=
        Eigen::Vector2d(0.0, 1.5 * 3.0 / n_along);
    CHECK(same_report(flipped) > 0);
}

TEST_CASE("overlap: the grid finds exactly the pairs an all-pairs search finds")
{
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> position(0.0, 10.0), offset(-0.6, 0.6);
    std::vector<Triangle2> soup;
    for (int i = 0; i < 400; ++i)
    {
        const Eigen::Vector2d c(position(rng), position(rng));
        soup.push_back({c + Eigen::Vector2d(offset(rng), offset(rng)),
                        c + Eigen::Vector2d(offset(rng), offset(rng)),
                        c + Eigen::Vector2d(offset(rng), offset(rng))});
    }
    std::vector<std::pair<int, int>> expected;
    double area = 0.0;
    for (int f = 0; f < 400; ++f)
        for (int g = f + 1; g < 400; ++g)
            if (interiors_intersect(soup[f], soup[g]))
            {
                expected.emplace_back(f, g);
                area += intersection_area(soup[f], soup[g]);
            }
    const OverlapReport r = find_overlaps(soup);
    CHECK(expected.size() > 50);  // the soup is dense enough to exercise the grid
    CHECK(r.pairs == expected);
    CHECK(r.overlap_area == doctest::Approx(area));
    // intersection_area agrees with the symmetric computation.
    for (const auto& [f, g] : expected)
        CHECK(intersection_area(soup[f], soup[g]) ==
              doctest::Approx(intersection_area(soup[g], soup[f])));
}

TEST_CASE("overlap: bad input is refused")
{
    const Mesh grid = plane_grid(1.0, 2);
    CHECK_THROWS_AS(find_overlaps(grid, Eigen::MatrixX2d(3, 2)), InvalidInputError);
    Eigen::MatrixX2d uv = test::planar_uv(grid);
    uv(0, 0) = NAN;
    CHECK_THROWS_AS(find_overlaps(grid, uv), InvalidInputError);
    CHECK(find_overlaps(std::vector<Triangle2>{}).pairs.empty());
}

TEST_CASE("overlap: the report's exact fraction agrees with flatcheck.py's raster on real maps "
          "that overlap")
{
    // Independent yardstick: flatcheck rasterizes the map at a quarter edge and counts pixels
    // covered more than once; ours is exact (sum of pairwise areas / map area). The maps are the
    // unconstrained ones (`--overlaps keep`), which overlap themselves on these meshes, so both
    // figures are well above the raster's resolution and a counter that is off shows.
    for (const char* relative : {"vmtk-test-data/aorta-surface-open-ends.ply",
                                 "x-ray-angio-data/coronary-phantom-tri3-coarse.ply"})
    {
        const std::string input = std::string(VESSEL_SHARED_DATA) + "/" + relative;
        REQUIRE_MESSAGE(std::filesystem::exists(input), "missing shared data: " << input);
        const std::string dir = test::temp_dir("overlap_flatcheck");
        REQUIRE(test::run(std::string(VESSEL_FLATTEN_EXE) + " " + input + " -o " + dir +
                          "/flat.obj --report " + dir + "/report.json -q --overlaps keep") == 0);
        const auto report = nlohmann::json::parse(std::ifstream(dir + "/report.json"));
        const auto check = test::flatcheck(input, dir + "/flat.obj");
        const double exact = report["quality"]["overlap_fraction"];
        const double raster = check["overlap_fraction"];
        MESSAGE(std::string(relative) << ": exact " << exact << ", flatcheck " << raster << ", "
                         << report["quality"]["overlapping_triangles"] << " faces");
        // The premise: the map overlaps by more than the raster's resolution (a pixel is a
        // quarter edge; kOverlapFloor is 10x the absolute tolerance below).
        constexpr double kOverlapFloor = 0.02;
        REQUIRE_MESSAGE(raster >= kOverlapFloor, relative << ": the keep map no longer overlaps"
                        " enough to compare the counters; pick a mesh whose keep map does");
        CHECK(std::abs(exact - raster) <= 0.002 + 0.1 * raster);
        CHECK(report["quality"]["overlapping_triangles"].get<int>() > 0);
        CHECK(!report["overlaps"]["triangles"].empty());
    }
}
