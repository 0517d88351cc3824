#include <doctest/doctest.h>

#include "vessel/core/errors.h"
#include "vessel/quality/metrics.h"
#include "vessel/phantom/phantom.h"

#include <cmath>

using namespace vessel;

TEST_CASE("metrics: the identity map of a flat grid has no distortion")
{
    const Mesh grid = plane_grid(2.0, 8);
    Eigen::MatrixX2d uv(grid.n_vertices(), 2);
    for (auto v : grid.vertices())
        uv.row(v.idx()) << grid.point(v)[0], grid.point(v)[1];
    const FlatQuality q = flat_quality(grid, uv);
    CHECK(q.flipped_triangles == 0);
    CHECK(q.area_ratio == doctest::Approx(1.0));
    CHECK(q.mean_abs_log_area == doctest::Approx(0.0));
    CHECK(q.mean_conformal == doctest::Approx(1.0));
}

TEST_CASE("metrics: scaling, stretching and mirroring are measured")
{
    const Mesh grid = plane_grid(1.0, 4);
    Eigen::MatrixX2d uv(grid.n_vertices(), 2);
    for (auto v : grid.vertices())
        uv.row(v.idx()) << 2.0 * grid.point(v)[0], grid.point(v)[1];  // stretch u by 2
    FlatQuality q = flat_quality(grid, uv);
    CHECK(q.area_ratio == doctest::Approx(2.0));
    CHECK(q.mean_abs_log_area == doctest::Approx(std::log(2.0)));
    // A uniform stretch of the areas is a scale: the normalized measure ignores it.
    CHECK(std::abs(q.mean_abs_log_area_normalized) < 1e-12);
    CHECK(q.mean_conformal == doctest::Approx(2.0));
    uv.col(0) *= -1.0;  // mirror: every triangle flips
    q = flat_quality(grid, uv);
    CHECK(q.flipped_triangles == static_cast<int>(grid.n_faces()));
    CHECK_THROWS_AS(flat_quality(grid, Eigen::MatrixX2d(3, 2)), InvalidInputError);
}

TEST_CASE("metrics: a map above the useful mean |log area| gets a warning with advice")
{
    FlatQuality q;
    q.mean_abs_log_area = 0.149;  // the Glenn tree's map
    CHECK(distortion_warning(q).empty());
    q.mean_abs_log_area = kMaxUsefulMeanAbsLogArea;
    CHECK(distortion_warning(q).empty());
    q.mean_abs_log_area = 6.8;  // 1000 one-triangle holes on a 19k-face tube
    const std::string w = distortion_warning(q);
    CHECK_MESSAGE(w.find("mean |log area| 6.8, above 1") != std::string::npos, w);
    CHECK(w.find("--fill-holes") != std::string::npos);
}
