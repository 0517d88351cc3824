#include <doctest/doctest.h>

#include "support/files.h"
#include "support/checks.h"
#include "support/meshes.h"
#include "support/png.h"
#include "vessel/core/errors.h"
#include "vessel/io/io.h"
#include "vessel/io/vtk_io.h"
#include "vessel/render/map_frames.h"
#include "vessel/render/map_image.h"
#include "vessel/phantom/phantom.h"
#include "vessel/pipeline.h"


#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <regex>
#include <string>

using namespace vessel;
using vessel::test::read_bytes;
using vessel::test::color_error;
using vessel::test::Png;
using vessel::test::run;
using vessel::test::temp_dir;

namespace {

//! The flattened carotid phantom, computed once for all cases.
const FlattenResult& flat_carotid()
{
    static const FlattenResult result = flatten(carotid_phantom());
    return result;
}

MapImageInput carotid_input()
{
    return map_image_input(flat_carotid());
}

//! A smooth known field: a linear function of the 3D position.
Eigen::VectorXd linear_field(const Mesh& mesh, const Eigen::Vector3d& a, double b)
{
    return vertex_positions(mesh) * a + Eigen::VectorXd::Constant(mesh.n_vertices(), b);
}

struct PixelCheck
{
    int checked = 0;
    double max_error = 0;
};

//! Pixel-space corners of every face, rows `f.idx()`.
std::vector<std::array<Eigen::Vector2d, 3>> face_pixels(const MapImageInput& input,
                                                        const MapImageLayout& layout)
{
    std::vector<std::array<Eigen::Vector2d, 3>> corners;
    for (auto f : input.mesh->faces())
    {
        std::array<Eigen::Vector2d, 3> p;
        int k = 0;
        for (auto vh : f.vertices())
            p[k++] = layout.to_pixel(input.uv.row(vh.idx()).transpose());
        corners.push_back(p);
    }
    return corners;
}

//! Barycentric coordinates of \p c in the triangle \p p (NaN if degenerate).
Eigen::Vector3d barycentric(const std::array<Eigen::Vector2d, 3>& p, const Eigen::Vector2d& c)
{
    Eigen::Matrix2d T;
    T << p[1] - p[0], p[2] - p[0];
    if (std::abs(T.determinant()) < 1e-9)
        return Eigen::Vector3d::Constant(NAN);
    const Eigen::Vector2d b = T.inverse() * (c - p[0]);
    return {1 - b.sum(), b.x(), b.y()};
}

//! How many faces contain each pixel centre (row-major, width x height): the flattened map may
//! overlap itself, and a pixel covered twice shows only the face drawn last.
std::vector<int> coverage(const std::vector<std::array<Eigen::Vector2d, 3>>& faces, int width,
                          int height)
{
    std::vector<int> count(static_cast<std::size_t>(width) * height, 0);
    for (const auto& p : faces)
    {
        Eigen::AlignedBox2d b;
        for (const auto& q : p)
            b.extend(q);
        for (int y = std::max(0, int(b.min().y())); y <= std::min(height - 1, int(b.max().y()));
             ++y)
            for (int x = std::max(0, int(b.min().x())); x <= std::min(width - 1, int(b.max().x()));
                 ++x)
                if (barycentric(p, Eigen::Vector2d(x + 0.5, y + 0.5)).minCoeff() >= 0)
                    ++count[static_cast<std::size_t>(y) * width + x];
    }
    return count;
}

//! For every face, the pixel containing its centroid, if that pixel's centre lies well inside
//! the face (barycentric coordinates > 0.15) and no other face comes within 2 px: its colour against the
//! colormap of the value interpolated linearly at the pixel centre.
PixelCheck check_face_pixels(const Png& png, const MapImageInput& input,
                             const Eigen::VectorXd& values, const MapImageLayout& layout)
{
    PixelCheck check;
    const auto faces = face_pixels(input, layout);
    const std::vector<int> count = coverage(faces, png.width(), png.height());
    for (auto f : input.mesh->faces())
    {
        const auto& p = faces[f.idx()];
        double v[3];
        int k = 0;
        for (auto vh : f.vertices())
            v[k++] = values[vh.idx()];
        const Eigen::Vector2d centroid = (p[0] + p[1] + p[2]) / 3;
        const int x = static_cast<int>(centroid.x()), y = static_cast<int>(centroid.y());
        const Eigen::Vector3d bary = barycentric(p, Eigen::Vector2d(x + 0.5, y + 0.5));
        if (!(bary.minCoeff() > 0.15) || x < 2 || y < 2 || x + 2 >= png.width() ||
            y + 2 >= png.height())
            continue;
        int overlap = 0;  // faces drawn over each other within 2 px
        for (int dy = -2; dy <= 2; ++dy)
            for (int dx = -2; dx <= 2; ++dx)
                overlap = std::max(overlap,
                                   count[static_cast<std::size_t>(y + dy) * png.width() + x + dx]);
        if (overlap > 1)
            continue;
        const double value = bary[0] * v[0] + bary[1] * v[1] + bary[2] * v[2];
        const Eigen::Vector3d expected = colormap_rgb(
            layout.colormap, (value - layout.range_min) / (layout.range_max - layout.range_min));
        const double err = color_error(png.pixel(x, y), expected);
        check.max_error = std::max(check.max_error, err);
        ++check.checked;
    }
    return check;
}

}  // namespace

TEST_CASE("map_image: colormap tables and automatic range")
{
    // viridis runs from dark purple to yellow; cool-warm from blue through grey to red.
    CHECK(colormap_rgb(Colormap::Viridis, 0)
              .isApprox(Eigen::Vector3d(0.267004, 0.004874, 0.329415), 1e-5));
    CHECK(colormap_rgb(Colormap::Viridis, 1)
              .isApprox(Eigen::Vector3d(0.993248, 0.906157, 0.143936), 1e-5));
    const Eigen::Vector3d mid = colormap_rgb(Colormap::Diverging, 0.5);
    CHECK(mid.maxCoeff() - mid.minCoeff() < 0.1);
    CHECK(colormap_rgb(Colormap::Diverging, 0)[2] > colormap_rgb(Colormap::Diverging, 0)[0]);
    CHECK(colormap_rgb(Colormap::Diverging, 1)[0] > colormap_rgb(Colormap::Diverging, 1)[2]);
    CHECK(colormap_rgb(Colormap::Viridis, -3) == colormap_rgb(Colormap::Viridis, 0));

    Eigen::VectorXd positive(3), signed_values(3);
    positive << 1, 2, 5;
    signed_values << -1, 0.5, 3;
    MapImageLayout r = map_image_range(positive, {});
    CHECK(r.colormap == Colormap::Viridis);
    CHECK(r.range_min == 1);
    CHECK(r.range_max == 5);
    r = map_image_range(signed_values, {});
    CHECK(r.colormap == Colormap::Diverging);
    CHECK(r.range_min == -3);  // symmetric about 0
    CHECK(r.range_max == 3);
    MapImageOptions fixed;
    fixed.auto_range = false;
    fixed.range_min = -1;
    fixed.range_max = 10;
    fixed.colormap = Colormap::Viridis;
    r = map_image_range(signed_values, fixed);
    CHECK(r.colormap == Colormap::Viridis);
    CHECK(r.range_min == -1);
    CHECK(r.range_max == 10);
    r = map_image_range(Eigen::VectorXd::Constant(4, 2.0), {});
    CHECK(r.range_min < 2);
    CHECK(r.range_max > 2);
    CHECK_THROWS_AS(map_image_range(Eigen::VectorXd::Constant(2, NAN), {}), InvalidInputError);
}

TEST_CASE("map_image: a linear field on an unrolled cylinder, pixel by pixel")
{
    // The cut cylinder unrolled exactly: u = arc length around, v = height. On this rectangle a
    // linear field a u + b v is the same inside every triangle, so every pixel is known.
    const int n_around = 24, n_along = 8;
    const Mesh mesh = vessel::test::cut_cylinder(1.0, 4.0, n_around, n_along);
    Eigen::MatrixX2d uv(mesh.n_vertices(), 2);
    Eigen::VectorXd values(mesh.n_vertices());
    for (int j = 0; j <= n_along; ++j)
        for (int i = 0; i <= n_around; ++i)
        {
            const int k = j * (n_around + 1) + i;
            uv.row(k) << 2 * M_PI * i / n_around, 4.0 * j / n_along;
            values[k] = 3.0 * uv(k, 0) - 2.0 * uv(k, 1);
        }
    MapImageOptions options;
    options.width_px = 800;
    options.height_px = 500;
    options.outline = false;
    options.background = Eigen::Vector3d(0, 0, 0);
    const std::string path = temp_dir("map_image_cylinder") + "/cylinder.png";
    const MapImageLayout layout = render_map_image(path, {&mesh, uv, {}}, values, options);
    CHECK(layout.colormap == Colormap::Diverging);
    CHECK(layout.range_min == doctest::Approx(-2 * M_PI * 3));  // symmetric: max is 6 pi
    const Png png(path);
    const Eigen::Vector2d lo = layout.to_pixel(Eigen::Vector2d(0, 4)),
                          hi = layout.to_pixel(
                              Eigen::Vector2d(2 * M_PI, 0));  // top-left, bottom-right
    int inside = 0, outside = 0;
    double inside_error = 0, outside_error = 0;
    for (int y = 0; y < png.height(); ++y)
        for (int x = 0; x < int(layout.map_box.max().x()); ++x)
        {
            const Eigen::Vector2d c(x + 0.5, y + 0.5);
            if (c.x() > lo.x() + 2 && c.x() < hi.x() - 2 && c.y() > lo.y() + 2 &&
                c.y() < hi.y() - 2)
            {
                const Eigen::Vector2d q(
                    (c.x() - layout.map_origin.x()) / layout.scale + layout.uv_min.x(),
                    (layout.map_origin.y() - c.y()) / layout.scale + layout.uv_min.y());
                const double value = 3.0 * q.x() - 2.0 * q.y();
                inside_error = std::max(
                    inside_error,
                    color_error(
                        png.pixel(x, y),
                        colormap_rgb(layout.colormap, (value - layout.range_min) /
                                                          (layout.range_max - layout.range_min))));
                ++inside;
            }
            else if (c.x() < lo.x() - 2 || c.x() > hi.x() + 2 || c.y() < lo.y() - 2 ||
                     c.y() > hi.y() + 2)
            {
                outside_error =
                    std::max(outside_error, color_error(png.pixel(x, y), options.background));
                ++outside;
            }
        }
    MESSAGE(inside << " pixels inside, max colour error " << inside_error << "; " << outside
                   << " outside, max " << outside_error);
    CHECK(inside > 50000);
    // Every pixel, including those on patch edges, where cairo's rasterization and the RGB chord
    // of the colormap across a subdivided piece add up (measured 0.0153, i.e. 3.9/255).
    CHECK(inside_error < 0.02);
    CHECK(outside > 10000);
    CHECK(outside_error <= 1.0 / 255);
}

TEST_CASE("map_image: a scale bar of a round length under the map, and a caption")
{
    const int n_around = 24, n_along = 8;
    const Mesh mesh = vessel::test::cut_cylinder(1.0, 4.0, n_around, n_along);
    Eigen::MatrixX2d uv(mesh.n_vertices(), 2);
    for (int j = 0; j <= n_along; ++j)
        for (int i = 0; i <= n_around; ++i)
            uv.row(j * (n_around + 1) + i) << 2 * M_PI * i / n_around, 4.0 * j / n_along;
    const Eigen::VectorXd values = uv.col(1);
    MapImageOptions options;
    options.caption = "t = 0.250 s";
    const std::string dir = temp_dir("map_image_scale_bar");
    const MapImageLayout layout = render_map_image(dir + "/bar.png", {&mesh, uv, {}}, values, options);
    // The map is 2 pi wide: a fifth of it is 1.26, so the bar is 1 unit long.
    CHECK(layout.scale_bar_length == 1.0);
    CHECK(layout.scale_bar_box.sizes().x() == doctest::Approx(layout.scale));
    // Under the map, inside its panel, starting at the map's left end.
    CHECK(layout.scale_bar_box.min().y() > layout.to_pixel(Eigen::Vector2d(0, 0)).y());
    CHECK(layout.scale_bar_box.max().y() < layout.map_box.max().y());
    CHECK(layout.scale_bar_box.min().x() == doctest::Approx(layout.to_pixel(Eigen::Vector2d(0, 0)).x()));
    // The caption's strip is above the map.
    CHECK(layout.to_pixel(Eigen::Vector2d(0, 4)).y() > layout.map_box.min().y() + options.font_size_px);
    const Png png(dir + "/bar.png");
    const Eigen::Vector2d c = layout.scale_bar_box.center();
    CHECK(color_error(png.pixel(int(c.x()), int(c.y())), Eigen::Vector3d::Zero()) < 0.05);
    // Dark caption pixels in the top left corner, none without a caption.
    const auto dark_top_left = [&](const Png& image) {
        int n = 0;
        for (int y = int(layout.map_box.min().y()); y < int(layout.map_box.min().y() + options.font_size_px); ++y)
            for (int x = int(layout.map_box.min().x()); x < int(layout.map_box.min().x() + 80); ++x)
                n += image.pixel(x, y).maxCoeff() < 0.5;
        return n;
    };
    CHECK(dark_top_left(png) > 20);
    options.scale_bar = false;
    options.caption.clear();
    const MapImageLayout plain = render_map_image(dir + "/plain.png", {&mesh, uv, {}}, values, options);
    CHECK(plain.scale_bar_box.isEmpty());
    CHECK(plain.scale_bar_length == 0.0);
    CHECK(dark_top_left(Png(dir + "/plain.png")) == 0);
}

TEST_CASE("map_image: per-face values are drawn flat")
{
    const MapImageInput input = carotid_input();
    const Mesh& mesh = *input.mesh;
    Eigen::VectorXd values(mesh.n_faces());
    for (auto f : mesh.faces())
        values[f.idx()] = f.idx() % 7;  // neighbours differ: any bleeding would show
    MapImageOptions options;
    options.per_face = true;
    options.outline = false;
    // The loop labels' translucent patches may land on the map (draw_loop_labels()): off, so
    // that every pixel inside a face shows that face alone.
    options.loop_labels = false;
    options.width_px = 1400;
    options.height_px = 900;
    const std::string path = temp_dir("map_image_per_face") + "/faces.png";
    const MapImageLayout layout = render_map_image(path, input, values, options);
    const Png png(path);
    const auto faces = face_pixels(input, layout);
    const std::vector<int> count = coverage(faces, png.width(), png.height());
    int checked = 0;
    double max_error = 0;
    for (auto f : mesh.faces())
    {
        const Eigen::Vector3d expected = colormap_rgb(layout.colormap, (f.idx() % 7) / 6.0);
        const auto& p = faces[f.idx()];
        // Pixels whose 3 x 3 neighbourhood lies inside the face, away from any overlap.
        for (const Eigen::Vector3d& w :
             {Eigen::Vector3d(0.6, 0.2, 0.2), Eigen::Vector3d(0.2, 0.6, 0.2),
              Eigen::Vector3d(0.2, 0.2, 0.6), Eigen::Vector3d(0.34, 0.33, 0.33)})
        {
            const Eigen::Vector2d q = w[0] * p[0] + w[1] * p[1] + w[2] * p[2];
            const int x = int(q.x()), y = int(q.y());
            bool clear = true;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx)
                    clear =
                        clear &&
                        barycentric(p, Eigen::Vector2d(x + dx + 0.5, y + dy + 0.5)).minCoeff() >=
                            0 &&
                        count[static_cast<std::size_t>(y + dy) * png.width() + x + dx] == 1;
            if (!clear)
                continue;
            max_error = std::max(max_error, color_error(png.pixel(x, y), expected));
            ++checked;
        }
    }
    MESSAGE(checked << " pixels inside faces, max colour error " << max_error);
    CHECK(checked > 1000);
    CHECK(max_error <= 1.5 / 255);
    options.per_face = false;  // now the sizes disagree
    CHECK_THROWS_AS(render_map_image(path, input, values, options), InvalidInputError);
}

TEST_CASE("map_image: PNG of the flattened phantom shows the field, background and colorbar")
{
    const MapImageInput input = carotid_input();
    const Eigen::VectorXd values = linear_field(*input.mesh, Eigen::Vector3d(0.2, 0.1, 1.0), 3.0);
    MapImageOptions options;
    options.width_px = 1400;
    options.height_px = 900;
    options.background = Eigen::Vector3d(0.9, 0.95, 1.0);
    options.loop_labels = false;  // text would sit in the background checked below
    options.scale_bar = false;    // as would the scale bar
    options.outline = false;      // the outline covers the pixels of faces along the boundary
    options.field_name = "z";
    options.units = "mm";
    const std::string path = temp_dir("map_image_png") + "/map.png";
    const MapImageLayout layout = render_map_image(path, input, values, options);
    const Png png(path);
    REQUIRE(png.width() == 1400);
    REQUIRE(png.height() == 900);
    CHECK(layout.colormap == Colormap::Diverging);  // the field straddles 0

    // Inside faces: the colormap of the linearly interpolated value (8-bit rounding and the RGB
    // blend within each subdivided piece stay below 0.015; measured 0.006).
    const PixelCheck faces = check_face_pixels(png, input, values, layout);
    MESSAGE("checked " << faces.checked << " face pixels, max colour error " << faces.max_error);
    CHECK(faces.checked > 1000);
    CHECK(faces.max_error < 0.015);

    // Background: every pixel of the map panel at least 3 px from every face's bounding box.
    std::vector<char> near(static_cast<std::size_t>(png.width()) * png.height(), 0);
    for (auto f : input.mesh->faces())
    {
        Eigen::AlignedBox2d b;
        for (auto v : f.vertices())
            b.extend(layout.to_pixel(input.uv.row(v.idx()).transpose()));
        for (int y = std::max(0, int(b.min().y()) - 3);
             y <= std::min(png.height() - 1, int(b.max().y()) + 3); ++y)
            for (int x = std::max(0, int(b.min().x()) - 3);
                 x <= std::min(png.width() - 1, int(b.max().x()) + 3); ++x)
                near[static_cast<std::size_t>(y) * png.width() + x] = 1;
    }
    int background = 0;
    double background_error = 0;
    for (int y = int(layout.map_box.min().y()); y < int(layout.map_box.max().y()); ++y)
        for (int x = int(layout.map_box.min().x()); x < int(layout.map_box.max().x()); ++x)
            if (!near[static_cast<std::size_t>(y) * png.width() + x])
            {
                background_error =
                    std::max(background_error, color_error(png.pixel(x, y), options.background));
                ++background;
            }
    CHECK(background > 10000);
    CHECK(background_error <= 1.0 / 255);  // cairo's 16-bit to 8-bit rounding

    // Colorbar: the centre column runs through the colormap from bottom to top.
    REQUIRE(!layout.colorbar_box.isEmpty());
    const auto& cb = layout.colorbar_box;
    const int x = static_cast<int>(cb.center().x());
    double bar_error = 0;
    for (int i = 1; i < 20; ++i)
    {
        const double y = cb.max().y() - i / 20.0 * cb.sizes().y();
        bar_error = std::max(bar_error, color_error(png.pixel(x, static_cast<int>(y)),
                                                    colormap_rgb(layout.colormap, i / 20.0)));
    }
    CHECK(bar_error < 0.03);
    CHECK(layout.view3d_box.isEmpty());
}

TEST_CASE("map_image: 3D view beside the map, labels, SVG and PDF")
{
    const MapImageInput input = carotid_input();
    const Eigen::VectorXd& values = flat_carotid().uv.col(0);  // any field
    MapImageOptions options;
    options.view3d = true;
    options.labels = {"CCA", "ICA"};  // the third loop gets the default "outlet 2"
    const std::string dir = temp_dir("map_image_formats");
    const MapImageLayout layout = render_map_image(dir + "/map.png", input, values, options);
    REQUIRE(!layout.view3d_box.isEmpty());
    CHECK(layout.view3d_box.min().x() > layout.map_box.max().x());
    CHECK(layout.colorbar_box.min().x() > layout.view3d_box.max().x());
    const Png png(dir + "/map.png");
    int coloured = 0, total = 0;
    for (int y = int(layout.view3d_box.min().y()); y < int(layout.view3d_box.max().y()); y += 2)
        for (int x = int(layout.view3d_box.min().x()); x < int(layout.view3d_box.max().x()); x += 2)
        {
            ++total;
            coloured += color_error(png.pixel(x, y), options.background) > 0.1;
        }
    MESSAGE("3D view covers " << coloured << " of " << total << " sampled pixels");
    CHECK(coloured > total / 20);

    // The outline: dark pixels at the middle of the boundary edges.
    const Mesh& mesh = *input.mesh;
    int boundary = 0, dark = 0;
    for (auto h : mesh.halfedges())
        if (h.is_boundary())
        {
            const Eigen::Vector2d mid = layout.to_pixel(
                (input.uv.row(h.from().idx()) + input.uv.row(h.to().idx())).transpose() / 2);
            ++boundary;
            dark += png.pixel(int(mid.x()), int(mid.y())).maxCoeff() < 0.4;
        }
    MESSAGE(dark << " of " << boundary << " boundary edge midpoints are dark");
    CHECK(dark > 0.95 * boundary);

    render_map_image(dir + "/map.svg", input, values, options);
    const std::string svg = read_bytes(dir + "/map.svg");
    CHECK(svg.find("<svg") != std::string::npos);
    CHECK(run("/usr/bin/python3 -c \"import sys, xml.etree.ElementTree as E; "
              "r = E.parse(sys.argv[1]).getroot(); sys.exit(0 if r.tag.endswith('svg') else 1)\" " +
              dir + "/map.svg") == 0);

    render_map_image(dir + "/map.pdf", input, values, options);
    const std::string pdf = read_bytes(dir + "/map.pdf");
    CHECK(pdf.rfind("%PDF-", 0) == 0);
    const std::regex page("/Type\\s*/Page[^s]");
    CHECK(std::distance(std::sregex_iterator(pdf.begin(), pdf.end(), page),
                        std::sregex_iterator()) == 1);
    CHECK(pdf.find("%%EOF") != std::string::npos);
    CHECK_FALSE(std::filesystem::exists(dir + "/map.pdf.tmp"));
}

TEST_CASE("map_image: bad inputs are refused")
{
    const MapImageInput input = carotid_input();
    const Eigen::VectorXd values = Eigen::VectorXd::Ones(input.uv.rows());
    const std::string dir = temp_dir("map_image_bad");
    CHECK_THROWS_AS(render_map_image(dir + "/a.jpg", input, values), InvalidInputError);
    CHECK_THROWS_AS(render_map_image(dir + "/a.png", input, values.head(10)), InvalidInputError);
    CHECK_THROWS_AS(render_map_image(dir + "/a.png", MapImageInput{}, values), InvalidInputError);
    CHECK_THROWS_AS(
        render_map_image(dir + "/a.png", input, Eigen::VectorXd::Constant(values.size(), NAN)),
        InvalidInputError);
    MapImageOptions options;
    options.width_px = 10;
    CHECK_THROWS_AS(options.validate(), InvalidInputError);
    options = {};
    options.auto_range = false;
    options.range_min = 2;
    options.range_max = 1;
    CHECK_THROWS_AS(render_map_image(dir + "/a.png", input, values, options), InvalidInputError);
    options = {};
    options.view_direction = Eigen::Vector3d::UnitZ();
    options.view_up = -Eigen::Vector3d::UnitZ();
    CHECK_THROWS_AS(options.validate(), InvalidInputError);
    CHECK_THROWS_AS(render_map_image(dir + "/no/such/dir/a.png", input, values), IoError);
}

TEST_CASE("map_image: the map can come from the mesh's uv property")
{
    const FlattenResult& flat = flat_carotid();
    const MapImageInput from_property = map_image_input(flat.mesh);
    CHECK(from_property.mesh == &flat.mesh);
    CHECK(from_property.uv == flat.uv);  // flatten() stores the same uv in prop::uv
    CHECK(from_property.loops.empty());
    const Mesh bare = carotid_phantom();
    CHECK_THROWS_AS(map_image_input(bare), InvalidInputError);
}

TEST_CASE("map_frames: linear interpolation between time steps")
{
    FieldSeries series;
    series.times = {0.0, 0.5, 2.0};
    series.values = {Eigen::Vector3d(0, 1, 2), Eigen::Vector3d(4, 1, -2), Eigen::Vector3d(1, 1, 1)};
    CHECK(interpolate_series(series, 0.25).isApprox(Eigen::Vector3d(2, 1, 0)));
    CHECK(interpolate_series(series, 1.25).isApprox(Eigen::Vector3d(2.5, 1, -0.5)));
    CHECK(interpolate_series(series, 0.5) == series.values[1]);
    CHECK(interpolate_series(series, -1) == series.values[0]);
    CHECK(interpolate_series(series, 3) == series.values[2]);

    FrameOptions options;
    options.fps = 4;
    options.slowdown = 2;  // 8 frames per series second
    const std::vector<double> t = frame_times(series, options);
    REQUIRE(t.size() == 17);
    CHECK(t[1] == doctest::Approx(0.125));
    CHECK(t.back() == doctest::Approx(2.0));

    FieldSeries bad = series;
    bad.times[2] = 0.5;
    CHECK_THROWS_AS(interpolate_series(bad, 0.1), InvalidInputError);
    bad = series;
    bad.values[1] = Eigen::Vector2d(0, 0);
    CHECK_THROWS_AS(bad.validate(), InvalidInputError);
    options.fps = 0;
    CHECK_THROWS_AS(frame_times(series, options), InvalidInputError);
    options = {};
    options.animation = "movie.avi";
    CHECK_THROWS_AS(options.validate(), InvalidInputError);
}

TEST_CASE("map_frames: frames of a travelling pulse show the interpolated values")
{
    const MapImageInput input = carotid_input();
    const Mesh& mesh = *input.mesh;
    // A pulse moving along z, 4 steps over 0.3 s; frames at 10 fps fall between the steps.
    FieldSeries series;
    for (int k = 0; k < 4; ++k)
    {
        series.times.push_back(0.1 * k);
        Eigen::VectorXd v(mesh.n_vertices());
        for (auto vh : mesh.vertices())
            v[vh.idx()] = std::exp(-std::pow((mesh.point(vh)[2] + 20 - 10 * k) / 8, 2));
        series.values.push_back(v);
    }
    FrameOptions options;
    options.fps = 20;
    options.slowdown = 1.0 / 3;  // frames every 0.15 s: 0, 0.15, 0.3
    options.animation = temp_dir("map_frames_anim") + "/pulse.gif";
    MapImageOptions image;
    image.width_px = 900;
    image.height_px = 600;
    image.outline = false;
    image.loop_labels = false;  // the check reads face pixels; a label may lie over the map
    const std::string dir = temp_dir("map_frames") + "/frames";
    const FramesSummary summary = render_frames(dir, input, series, image, options);
    REQUIRE(summary.frames == 3);
    CHECK(summary.frame_times[1] == doctest::Approx(0.15));
    for (int k = 0; k < 3; ++k)
        CHECK(std::filesystem::exists(dir + "/frame_000" + std::to_string(k) + ".png"));
    CHECK(summary.animation_written == std::filesystem::exists(options.animation));
    CHECK(summary.animation_written == summary.message.empty());

    // Frame 1 (t = 0.15, halfway between steps 1 and 2) in the range of the whole series.
    const Eigen::VectorXd blend = 0.5 * series.values[1] + 0.5 * series.values[2];
    CHECK(interpolate_series(series, 0.15).isApprox(blend));
    double lo = 1e300, hi = -1e300;
    for (const auto& v : series.values)
    {
        lo = std::min(lo, v.minCoeff());
        hi = std::max(hi, v.maxCoeff());
    }
    // The same picture with the series' range given explicitly and the frame's time caption:
    // its layout is the frame's.
    MapImageOptions same = image;
    same.caption = "t = 0.150 s";
    same.auto_range = false;
    same.range_min = lo;
    same.range_max = hi;
    const MapImageLayout layout =
        render_map_image(temp_dir("map_frames_ref") + "/ref.png", input, blend, same);
    CHECK(summary.range_min == doctest::Approx(lo));
    CHECK(summary.range_max == doctest::Approx(hi));
    const PixelCheck frame = check_face_pixels(Png(dir + "/frame_0001.png"), input, blend, layout);
    MESSAGE("frame 1: checked " << frame.checked << " face pixels, max colour error "
                                << frame.max_error);
    CHECK(frame.checked > 500);
    CHECK(frame.max_error < 0.015);

    // Per-frame range: each frame spans its own values (the pulse's peak moves, its top stays).
    options.fixed_range = false;
    options.animation.clear();
    options.slowdown = 1.0 / 6;  // frames at 0 and 0.3 s
    const FramesSummary own = render_frames(dir + "_own", input, series, image, options);
    REQUIRE(own.frames == 2);

    // Without ffmpeg on PATH the frames are still written and the summary says why there is no
    // animation (whether or not this machine has ffmpeg).
    const std::string path_before = std::getenv("PATH") ? std::getenv("PATH") : "";
    setenv("PATH", dir.c_str(), 1);
    options.animation = dir + "/none.gif";
    const FramesSummary without = render_frames(dir + "_noffmpeg", input, series, image, options);
    setenv("PATH", path_before.c_str(), 1);
    CHECK(without.frames == 2);
    CHECK_FALSE(without.animation_written);
    CHECK(without.message.find("ffmpeg") != std::string::npos);
    CHECK_FALSE(std::filesystem::exists(options.animation));
    CHECK(own.range_min == doctest::Approx(series.values[0].minCoeff()));
    CHECK(own.range_max == doctest::Approx(series.values[0].maxCoeff()));
}

TEST_CASE("vessel-render: draws a map written by vessel-flatten with values from a CSV")
{
    const std::string dir = temp_dir("vessel_render");
    const std::string render = VESSEL_RENDER_EXE, flatten_exe = VESSEL_FLATTEN_EXE;
    CarotidPhantomOptions coarse;
    coarse.edge_length = 0.8;
    const Mesh mesh = carotid_phantom(coarse);
    write_mesh(mesh, dir + "/carotid.ply");
    REQUIRE(run(flatten_exe + " -q " + dir + "/carotid.ply -o " + dir + "/flat.obj") == 0);
    {
        std::ofstream csv(dir + "/values.csv");
        csv << "value\n";
        for (auto v : mesh.vertices())
            csv << mesh.point(v)[2] << "\n";
    }
    const std::string common = " " + dir + "/flat.obj --values " + dir + "/values.csv";
    CHECK(run(render + common + " " + dir + "/map.png --view3d > /dev/null") == 0);
    const Png png(dir + "/map.png");
    CHECK(png.width() == 1200);
    CHECK(run(render + common + " " + dir + "/map.pdf > /dev/null") == 0);
    CHECK(read_bytes(dir + "/map.pdf").rfind("%PDF-", 0) == 0);
    // Too few rows, a field that needs the surface, an unknown format: exit 1 with a message.
    std::ofstream(dir + "/short.csv") << "1\n2\n";
    CHECK(run(render + " " + dir + "/flat.obj --values " + dir + "/short.csv " + dir +
              "/x.png 2> /dev/null") == 1);
    CHECK(run(render + " " + dir + "/flat.obj --field geodesic " + dir + "/x.png 2> /dev/null") ==
          1);
    CHECK(run(render + common + " " + dir + "/x.bmp 2> /dev/null") == 1);
    CHECK_FALSE(std::filesystem::exists(dir + "/x.png"));
}

TEST_CASE("vessel-render: draws a point array of a .vtp input or of --fields, as vessel-flatten")
{
    const std::string dir = temp_dir("vessel_render_arrays");
    const std::string render = VESSEL_RENDER_EXE;
    CarotidPhantomOptions coarse;
    coarse.edge_length = 0.8;
    Mesh mesh = carotid_phantom(coarse);
    // The PLY below stores coordinates as float, the .vtp as double: the points rounded to
    // float first, so that both files hold the same surface and flatten to the same map.
    for (auto v : mesh.vertices())
    {
        const auto p = mesh.point(v);
        mesh.set_point(v, {static_cast<float>(p[0]), static_cast<float>(p[1]),
                           static_cast<float>(p[2])});
    }
    // Pressure: the height; WSS: a vector whose x component is the height too.
    PolyData data;
    data.mesh = to_raw_mesh(mesh);
    Field pressure{"Pressure", FieldLocation::Point, FieldType::Float64,
                   Eigen::MatrixXd(mesh.n_vertices(), 1)};
    Field wss{"WSS", FieldLocation::Point, FieldType::Float32, Eigen::MatrixXd(mesh.n_vertices(), 3)};
    for (auto v : mesh.vertices())
    {
        const double z = mesh.point(v)[2];
        pressure.values(v.idx(), 0) = z;
        wss.values.row(v.idx()) << z, 0.0, -2.0;
    }
    data.point_data = {pressure, wss};
    write_polydata(dir + "/carotid.vtp", data);
    double z_min = 1e300, z_max = -1e300;
    for (auto v : mesh.vertices())
    {
        z_min = std::min(z_min, mesh.point(v)[2]);
        z_max = std::max(z_max, mesh.point(v)[2]);
    }

    // The input's own array, a vector's component, and the same array given by --fields: the
    // same picture, coloured over the height's range.
    REQUIRE(run(render + " " + dir + "/carotid.vtp " + dir + "/p.png --field Pressure 2> " + dir +
                "/p.err") == 0);
    CHECK(read_bytes(dir + "/p.err").find("image of Pressure") != std::string::npos);
    REQUIRE(run(render + " " + dir + "/carotid.vtp " + dir + "/wx.png --field WSS:x 2> /dev/null") ==
            0);
    write_mesh(mesh, dir + "/carotid.ply");
    REQUIRE(run(render + " " + dir + "/carotid.ply " + dir + "/f.png --fields " + dir +
                "/carotid.vtp --field Pressure 2> /dev/null") == 0);
    const Png p(dir + "/p.png"), wx(dir + "/wx.png"), f(dir + "/f.png");
    REQUIRE(p.width() == 1200);
    long differ_wx = 0, differ_f = 0, coloured = 0;
    for (int y = 0; y < p.height(); ++y)
        for (int x = 0; x < p.width(); ++x)
        {
            const Eigen::Vector3d a = p.pixel(x, y), b = wx.pixel(x, y), c = f.pixel(x, y);
            coloured += std::abs(a[0] - a[1]) + std::abs(a[1] - a[2]) > 0.05;  // not grey
            differ_wx += color_error(a, b) > 0.05;
            differ_f += color_error(a, c) > 0.05;
        }
    CHECK(coloured > 20000);
    CHECK(differ_wx < 0.002 * p.width() * p.height());  // WSS_x: only the title differs
    CHECK(differ_f < 0.001 * p.width() * p.height());

    // A vector's magnitude differs from its x component; an unknown array, a component the
    // array lacks and an array with a flattened map are refused, writing nothing.
    REQUIRE(run(render + " " + dir + "/carotid.vtp " + dir + "/wm.png --field WSS 2> /dev/null") == 0);
    CHECK(read_bytes(dir + "/wm.png") != read_bytes(dir + "/wx.png"));
    CHECK(run(render + " " + dir + "/carotid.vtp " + dir + "/x.png --field nope 2> " + dir +
              "/nope.err") == 1);
    CHECK(read_bytes(dir + "/nope.err") ==
          "vessel-render: no field named 'nope'; available: Pressure, WSS\n");
    CHECK(run(render + " " + dir + "/carotid.vtp " + dir + "/x.png --field Pressure:y 2> /dev/null") ==
          1);
    CHECK_FALSE(std::filesystem::exists(dir + "/x.png"));
}
