#include <doctest/doctest.h>

#include "support/checks.h"
#include "support/png.h"
#include "vessel/core/errors.h"
#include "vessel/phantom/phantom.h"
#include "vessel/pipeline.h"
#include "vessel/render/map_arrows.h"
#include "vessel/render/map_image.h"

#include <algorithm>
#include <cmath>
#include <string>

using namespace vessel;
using vessel::test::Png;
using vessel::test::temp_dir;

namespace {

const FlattenResult& flat_carotid()
{
    static const FlattenResult result = flatten(carotid_phantom());
    return result;
}

double map_area(const Mesh& mesh, const Eigen::MatrixX2d& uv)
{
    double area = 0.0;
    for (auto f : mesh.faces())
    {
        Eigen::Vector2d p[3];
        int k = 0;
        for (auto v : f.vertices())
            p[k++] = uv.row(v.idx()).transpose();
        const Eigen::Vector2d a = p[1] - p[0], b = p[2] - p[0];
        area += 0.5 * (a.x() * b.y() - a.y() * b.x());
    }
    return area;
}

// Longest run of dark pixels (all channels below 0.25) along rows (`horizontal`) or columns.
int longest_dark_run(const Png& png, bool horizontal)
{
    const int outer = horizontal ? png.height() : png.width();
    const int inner = horizontal ? png.width() : png.height();
    int longest = 0;
    for (int i = 0; i < outer; ++i)
    {
        int run = 0;
        for (int j = 0; j < inner; ++j)
        {
            const Eigen::Vector3d c = horizontal ? png.pixel(j, i) : png.pixel(i, j);
            run = c.maxCoeff() < 0.25 ? run + 1 : 0;
            longest = std::max(longest, run);
        }
    }
    return longest;
}

}  // namespace

TEST_CASE("sample_map_arrows: grid points on the map, a linear field reproduced")
{
    const FlattenResult& flat = flat_carotid();
    const Eigen::MatrixX2d& uv = flat.uv;
    const double width = (uv.colwise().maxCoeff() - uv.colwise().minCoeff()).maxCoeff();
    const double spacing = width / 150.0;
    Eigen::Matrix2d A;
    A << 0.3, -1.2, 2.0, 0.5;
    const Eigen::Vector2d b(-0.7, 4.0);
    const Eigen::MatrixX2d vectors = (uv * A.transpose()).rowwise() + b.transpose();
    const std::vector<MapArrow> arrows = sample_map_arrows(flat.mesh, uv, vectors, spacing);

    // One point per grid cell of the map: their count times a cell's area is the map's area
    // (points outside the faces would add to it, missing ones take away).
    const double covered = static_cast<double>(arrows.size()) * spacing * spacing;
    const double area = map_area(flat.mesh, uv);
    MESSAGE(arrows.size() << " arrows cover " << covered << " of the map's " << area);
    CHECK(std::abs(covered / area - 1.0) < 0.03);
    double worst = 0.0;
    for (const MapArrow& a : arrows)
        worst = std::max(worst, (a.vector - (A * a.at + b)).norm() / (A * a.at + b).norm());
    CHECK(worst < 1e-9);
    // Row-major from the lowest (u, v), on one grid.
    for (std::size_t k = 1; k < arrows.size(); ++k)
    {
        const Eigen::Vector2d step = (arrows[k].at - arrows[0].at) / spacing;
        CHECK(std::abs(step.x() - std::round(step.x())) < 1e-6);
        CHECK(std::abs(step.y() - std::round(step.y())) < 1e-6);
        const bool after = arrows[k].at.y() > arrows[k - 1].at.y() + 0.5 * spacing ||
                           (std::abs(arrows[k].at.y() - arrows[k - 1].at.y()) < 0.5 * spacing &&
                            arrows[k].at.x() > arrows[k - 1].at.x());
        if (!after)
        {
            CHECK(after);
            break;
        }
    }

    CHECK_THROWS_AS(sample_map_arrows(flat.mesh, uv, vectors.topRows(3), spacing),
                    InvalidInputError);
    CHECK_THROWS_AS(sample_map_arrows(flat.mesh, uv, vectors, 0.0), InvalidInputError);
    CHECK_THROWS_AS(sample_map_arrows(flat.mesh, uv, vectors, width * 1e-5), InvalidInputError);
}

TEST_CASE("map_image: arrows point along the map vectors")
{
    const FlattenResult& flat = flat_carotid();
    MapImageInput input = map_image_input(flat);
    const Eigen::VectorXd values = Eigen::VectorXd::Constant(flat.mesh.n_vertices(), 1.0);
    MapImageOptions options;
    options.outline = false;
    options.loop_labels = false;
    options.colorbar = false;
    options.scale_bar = false;
    options.arrow_spacing_px = 30.0;
    const std::string dir = temp_dir("map_arrows");
    const auto runs = [&](const Eigen::Vector2d& direction) {
        input.vectors = direction.transpose().replicate(flat.mesh.n_vertices(), 1);
        render_map_image(dir + "/arrows.png", input, values, options);
        const Png png(dir + "/arrows.png");
        return std::pair<int, int>(longest_dark_run(png, true), longest_dark_run(png, false));
    };
    // Without arrows, nothing is dark (a constant field in viridis' middle, white background).
    input.vectors.resize(0, 2);
    render_map_image(dir + "/plain.png", input, values, options);
    const Png plain(dir + "/plain.png");
    CHECK(longest_dark_run(plain, true) == 0);
    // Every arrow has the same length, 0.9 x spacing: a horizontal field gives long dark runs
    // along rows and only short ones (the heads, the line width) along columns; a vertical one
    // the other way round.
    const auto [along_u, across_u] = runs({1.0, 0.0});
    const auto [across_v, along_v] = runs({0.0, 2.0});
    MESSAGE("u arrows: rows " << along_u << " px, columns " << across_u << " px; v arrows: rows "
                              << across_v << " px, columns " << along_v << " px");
    CHECK(along_u >= 18);
    CHECK(across_u <= 10);
    CHECK(along_v >= 18);
    CHECK(across_v <= 10);

    input.vectors = Eigen::MatrixX2d::Zero(4, 2);
    CHECK_THROWS_AS(render_map_image(dir + "/bad.png", input, values, options), InvalidInputError);
    options.arrow_spacing_px = 2.0;
    input.vectors.resize(0, 2);
    CHECK_THROWS_AS(render_map_image(dir + "/bad.png", input, values, options), InvalidInputError);
}
