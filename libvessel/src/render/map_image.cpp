#include "vessel/render/map_image.h"

#include "vessel/render/map_arrows.h"

#include "detail/atomic_file.h"
#include "vessel/core/errors.h"
#include "vessel/pipeline.h"
#include "vessel/core/properties.h"

#include <cairo-pdf.h>
#include <cairo-svg.h>
#include <cairo.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <numeric>

namespace vessel {
namespace {

using Vec2 = Eigen::Vector2d;
using Rgb = Eigen::Vector3d;

enum class Format
{
    Png,
    Svg,
    Pdf
};

Format format_of(const std::string& path)
{
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return std::tolower(c); });
    if (ext == ".png")
        return Format::Png;
    if (ext == ".svg")
        return Format::Svg;
    if (ext == ".pdf")
        return Format::Pdf;
    throw InvalidInputError("render_map_image: cannot tell the format of '" + path +
                            "'; end the file name in .png, .svg or .pdf");
}

struct CairoDeleter
{
    void operator()(cairo_t* cr) const { cairo_destroy(cr); }
    void operator()(cairo_surface_t* s) const { cairo_surface_destroy(s); }
    void operator()(cairo_pattern_t* p) const { cairo_pattern_destroy(p); }
};
template <class T>
using CairoPtr = std::unique_ptr<T, CairoDeleter>;

void set_rgb(cairo_t* cr, const Rgb& c)
{
    cairo_set_source_rgb(cr, c[0], c[1], c[2]);
}

//! Maps values to colours with the range and table of a layout.
struct Shader
{
    const MapImageLayout* layout;
    Rgb nan_color;
    Rgb operator()(double value) const
    {
        if (!std::isfinite(value))
            return nan_color;
        return colormap_rgb(layout->colormap,
                            (value - layout->range_min) / (layout->range_max - layout->range_min));
    }
};

//! Adds Gouraud-shaded triangles to a cairo mesh pattern, splitting those whose values span
//! more than `max_step` (in range units) so that colours follow the colormap between vertices.
class TrianglePainter
{
public:
    TrianglePainter(const Shader& shader, double max_step, cairo_pattern_t* pattern)
        : shader_(shader), max_step_(max_step), pattern_(pattern)
    {}
    void add(const Vec2 (&p)[3], const double (&value)[3], double shade, int depth = 0) const
    {
        const double span =
            std::max({value[0], value[1], value[2]}) - std::min({value[0], value[1], value[2]});
        const double range = shader_.layout->range_max - shader_.layout->range_min;
        if (depth < 4 && std::isfinite(span) && span > max_step_ * range)
        {
            const Vec2 m[3] = {(p[0] + p[1]) / 2, (p[1] + p[2]) / 2, (p[2] + p[0]) / 2};
            const double mv[3] = {(value[0] + value[1]) / 2, (value[1] + value[2]) / 2,
                                  (value[2] + value[0]) / 2};
            add({p[0], m[0], m[2]}, {value[0], mv[0], mv[2]}, shade, depth + 1);
            add({m[0], p[1], m[1]}, {mv[0], value[1], mv[1]}, shade, depth + 1);
            add({m[2], m[1], p[2]}, {mv[2], mv[1], value[2]}, shade, depth + 1);
            add({m[0], m[1], m[2]}, {mv[0], mv[1], mv[2]}, shade, depth + 1);
            return;
        }
        cairo_mesh_pattern_begin_patch(pattern_);
        cairo_mesh_pattern_move_to(pattern_, p[0].x(), p[0].y());
        cairo_mesh_pattern_line_to(pattern_, p[1].x(), p[1].y());
        cairo_mesh_pattern_line_to(pattern_, p[2].x(), p[2].y());
        for (int k = 0; k < 3; ++k)
        {
            const Rgb c = shade * shader_(value[k]);
            cairo_mesh_pattern_set_corner_color_rgb(pattern_, k, c[0], c[1], c[2]);
        }
        cairo_mesh_pattern_end_patch(pattern_);
    }

private:
    Shader shader_;
    double max_step_;
    cairo_pattern_t* pattern_;
};

void paint_pattern(cairo_t* cr, cairo_pattern_t* pattern, const Eigen::AlignedBox2d& clip)
{
    cairo_save(cr);
    cairo_rectangle(cr, clip.min().x(), clip.min().y(), clip.sizes().x(), clip.sizes().y());
    cairo_clip(cr);
    cairo_set_source(cr, pattern);
    cairo_paint(cr);
    cairo_restore(cr);
}

Eigen::AlignedBox2d box(double x0, double y0, double x1, double y1)
{
    return Eigen::AlignedBox2d(Vec2(x0, y0), Vec2(x1, y1));
}

void draw_text(cairo_t* cr, const std::string& text, const Vec2& at, double align_x, double align_y)
{
    cairo_text_extents_t e;
    cairo_text_extents(cr, text.c_str(), &e);
    cairo_move_to(cr, at.x() - e.x_bearing - align_x * e.width,
                  at.y() - e.y_bearing - align_y * e.height);
    cairo_show_text(cr, text.c_str());
}

double text_width(cairo_t* cr, const std::string& text)
{
    cairo_text_extents_t e;
    cairo_text_extents(cr, text.c_str(), &e);
    return e.x_advance;
}

std::string format_tick(double x)
{
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.4g", std::abs(x) < 1e-12 ? 0.0 : x);
    return buf;
}

//! Round tick positions (1, 2, 5 x 10^k steps) inside [lo, hi], about five of them.
std::vector<double> nice_ticks(double lo, double hi)
{
    const double raw = (hi - lo) / 5.0;
    const double mag = std::pow(10.0, std::floor(std::log10(raw)));
    double step = mag;
    for (double m : {1.0, 2.0, 5.0, 10.0})
        if (m * mag >= raw)
        {
            step = m * mag;
            break;
        }
    std::vector<double> ticks;
    for (double t = std::ceil(lo / step - 1e-9) * step; t <= hi + 1e-9 * step; t += step)
        ticks.push_back(t);
    return ticks;
}

//! The largest 1, 2 or 5 x 10^k not above \p most (> 0).
double round_length_below(double most)
{
    const double mag = std::pow(10.0, std::floor(std::log10(most)));
    for (double m : {5.0, 2.0, 1.0})
        if (m * mag <= most * (1 + 1e-12))
            return m * mag;
    return mag;
}

//! Pixel height of the strip under the map that the scale bar takes.
double scale_bar_strip(const MapImageOptions& o) { return 1.6 * o.font_size_px + 6; }

//! The bar under the map's left end (below the labels' room \p label_room), its length a round
//! number of map units, the length and units right of it.
void plan_scale_bar(MapImageLayout& layout, const Eigen::MatrixX2d& uv, double label_room,
                    const MapImageOptions& o)
{
    const double width = uv.col(0).maxCoeff() - uv.col(0).minCoeff();
    if (!(width > 0))
        return;
    layout.scale_bar_length = round_length_below(0.2 * width);
    const double x0 = layout.map_origin.x();
    const double strip = scale_bar_strip(o);
    const double y = std::min(layout.map_origin.y() + label_room + 0.5 * strip,
                              layout.map_box.max().y() - 0.5 * strip);
    layout.scale_bar_box = box(x0, y - 2, x0 + layout.scale * layout.scale_bar_length, y + 2);
}

void draw_scale_bar(cairo_t* cr, const MapImageLayout& layout, const MapImageOptions& o)
{
    const auto& b = layout.scale_bar_box;
    cairo_set_source_rgb(cr, 0, 0, 0);
    cairo_rectangle(cr, b.min().x(), b.min().y(), b.sizes().x(), b.sizes().y());
    cairo_fill(cr);
    for (double x : {b.min().x(), b.max().x()})
    {
        cairo_move_to(cr, x, b.min().y() - 4);
        cairo_line_to(cr, x, b.max().y() + 4);
    }
    cairo_set_line_width(cr, 1.5);
    cairo_stroke(cr);
    std::string text = format_tick(layout.scale_bar_length);
    if (!o.length_units.empty())
        text += " " + o.length_units;
    draw_text(cr, text, Vec2(b.max().x() + 0.5 * o.font_size_px, b.center().y()), 0.0, 0.5);
}

std::string colorbar_title(const MapImageOptions& o)
{
    return o.field_name + (o.units.empty() ? "" : " [" + o.units + "]");
}

double tick_labels_width(cairo_t* cr, const MapImageLayout& layout)
{
    double w = 0;
    for (double t : nice_ticks(layout.range_min, layout.range_max))
        w = std::max(w, text_width(cr, format_tick(t)));
    return w;
}

void draw_colorbar(cairo_t* cr, const MapImageLayout& layout, const MapImageOptions& o)
{
    const std::string title = colorbar_title(o);
    const double ticks_width = tick_labels_width(cr, layout);
    const auto& b = layout.colorbar_box;
    CairoPtr<cairo_pattern_t> gradient(cairo_pattern_create_linear(0, b.max().y(), 0, b.min().y()));
    for (int i = 0; i < 256; ++i)
    {
        const Rgb c = colormap_rgb(layout.colormap, i / 255.0);
        cairo_pattern_add_color_stop_rgb(gradient.get(), i / 255.0, c[0], c[1], c[2]);
    }
    cairo_rectangle(cr, b.min().x(), b.min().y(), b.sizes().x(), b.sizes().y());
    cairo_set_source(cr, gradient.get());
    cairo_fill_preserve(cr);
    cairo_set_source_rgb(cr, 0.15, 0.15, 0.15);
    cairo_set_line_width(cr, 1.0);
    cairo_stroke(cr);
    const double lo = layout.range_min, hi = layout.range_max;
    for (double t : nice_ticks(lo, hi))
    {
        const double y = b.max().y() - (t - lo) / (hi - lo) * b.sizes().y();
        cairo_move_to(cr, b.max().x(), y);
        cairo_line_to(cr, b.max().x() + 5, y);
        cairo_stroke(cr);
        draw_text(cr, format_tick(t), Vec2(b.max().x() + 8, y), 0.0, 0.5);
    }
    // Title along the bar, to the right of the tick labels (as matplotlib places it).
    cairo_save(cr);
    cairo_translate(cr, b.max().x() + 8 + ticks_width + 0.5 * o.font_size_px, b.center().y());
    cairo_rotate(cr, M_PI / 2);
    draw_text(cr, title, Vec2::Zero(), 0.5, 1.0);
    cairo_restore(cr);
}

//! uv -> pixel transform that fits the uv bounding box into \p panel, centred, v up.
void fit_map(MapImageLayout& layout, const Eigen::MatrixX2d& uv, const Eigen::AlignedBox2d& panel)
{
    const Vec2 lo = uv.colwise().minCoeff().transpose(), hi = uv.colwise().maxCoeff().transpose();
    const Vec2 size = (hi - lo).cwiseMax(1e-12);
    layout.scale = std::min(panel.sizes().x() / size.x(), panel.sizes().y() / size.y());
    layout.uv_min = lo;
    const Vec2 used = layout.scale * size;
    layout.map_origin = Vec2(panel.min().x() + (panel.sizes().x() - used.x()) / 2,
                             panel.max().y() - (panel.sizes().y() - used.y()) / 2);
}

//! Value at corner \p v of face \p f: the vertex's, or the face's with per-face values.
double corner_value(const Eigen::VectorXd& values, bool per_face, int f, int v)
{
    return values[per_face ? f : v];
}

void draw_map(cairo_t* cr, const Mesh& mesh, const std::vector<Vec2>& px,
              const Eigen::VectorXd& values, bool per_face, const TrianglePainter& painter,
              cairo_pattern_t* pattern, const Eigen::AlignedBox2d& panel)
{
    for (auto f : mesh.faces())
    {
        Vec2 p[3];
        double v[3];
        int k = 0;
        for (auto vh : f.vertices())
        {
            p[k] = px[vh.idx()];
            v[k++] = corner_value(values, per_face, f.idx(), vh.idx());
        }
        painter.add(p, v, 1.0);
    }
    paint_pattern(cr, pattern, panel);
}

// The arrows of input.vectors (MapImageOptions::arrow_spacing_px): each a shaft and a filled
// head, stroked white and wide first and then black and thin, so that they read on any colour.
void draw_arrows(cairo_t* cr, const MapImageInput& input, const MapImageLayout& layout,
                 const MapImageOptions& o)
{
    const double spacing = o.arrow_spacing_px;
    const std::vector<MapArrow> arrows =
        sample_map_arrows(*input.mesh, input.uv, input.vectors, spacing / layout.scale);
    double longest = 0.0;
    for (const MapArrow& a : arrows)
        longest = std::max(longest, a.vector.norm());
    if (!(longest > 0.0))
        return;
    // From 0.3 x 0.9 x spacing (a vector near zero) to 0.9 x spacing (the longest).
    const auto length_of = [&](const Eigen::Vector2d& v) {
        return 0.9 * spacing * (0.3 + 0.7 * v.norm() / longest);
    };
    const auto path = [&](const MapArrow& a) {
        const Vec2 centre = layout.to_pixel(a.at);
        if (!(a.vector.norm() > 1e-9 * longest))
            return false;  // no direction to show
        const double length = length_of(a.vector);
        const Vec2 dir = Vec2(a.vector.x(), -a.vector.y()).normalized();  // image y is down
        const Vec2 side(-dir.y(), dir.x());
        const Vec2 tail = centre - 0.5 * length * dir, tip = centre + 0.5 * length * dir;
        const double head = std::min(0.4 * length, 0.25 * spacing);
        const Vec2 base = tip - head * dir;
        cairo_move_to(cr, tail.x(), tail.y());
        cairo_line_to(cr, base.x(), base.y());
        const Vec2 left = base + 0.45 * head * side, right = base - 0.45 * head * side;
        cairo_move_to(cr, tip.x(), tip.y());
        cairo_line_to(cr, left.x(), left.y());
        cairo_line_to(cr, right.x(), right.y());
        cairo_close_path(cr);
        return true;
    };
    cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
    cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
    const double width = std::max(1.5, spacing / 15.0);
    for (const auto& [rgb, line] : {std::pair<double, double>{1.0, width + 2.0}, {0.0, width}})
    {
        for (const MapArrow& a : arrows)
            path(a);
        cairo_set_source_rgb(cr, rgb, rgb, rgb);
        cairo_set_line_width(cr, line);
        cairo_stroke(cr);
    }
    for (const MapArrow& a : arrows)  // the heads filled black
        path(a);
    cairo_set_source_rgb(cr, 0.0, 0.0, 0.0);
    cairo_fill(cr);
}

void draw_outline(cairo_t* cr, const Mesh& mesh, const std::vector<Vec2>& px, double width)
{
    for (auto h : mesh.halfedges())
        if (h.is_boundary())
        {
            cairo_move_to(cr, px[h.from().idx()].x(), px[h.from().idx()].y());
            cairo_line_to(cr, px[h.to().idx()].x(), px[h.to().idx()].y());
        }
    cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
    cairo_set_line_width(cr, width);
    cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
    cairo_stroke(cr);
}

std::string loop_label(const MapImageOptions& o, std::size_t i)
{
    return i < o.labels.size() ? o.labels[i]
           : i == 0            ? std::string("inlet")
                               : "outlet " + std::to_string(i);
}

//! Room the loop labels need on each side of a panel: the widest label plus a font size.
Vec2 label_padding(cairo_t* cr, const MapImageInput& input, const MapImageOptions& o)
{
    if (!o.loop_labels || input.loops.empty())
        return Vec2::Zero();
    double w = 0;
    for (std::size_t i = 0; i < input.loops.size(); ++i)
        w = std::max(w, text_width(cr, loop_label(o, i)));
    return Vec2(w + o.font_size_px, 2.0 * o.font_size_px);
}

Eigen::AlignedBox2d shrink(const Eigen::AlignedBox2d& b, const Vec2& pad)
{
    return Eigen::AlignedBox2d(b.min() + pad, b.max() - pad);
}

void draw_loop_labels(cairo_t* cr, const std::vector<BoundaryLoop>& loops,
                      const std::vector<Vec2>& px, const MapImageOptions& o,
                      const Eigen::AlignedBox2d& map_drawn, const Eigen::AlignedBox2d& image)
{
    std::vector<Eigen::AlignedBox2d> placed;
    for (std::size_t i = 0; i < loops.size(); ++i)
    {
        if (loops[i].vertices.empty())
            continue;
        const std::string text = loop_label(o, i);
        Vec2 anchor = Vec2::Zero();
        for (auto v : loops[i].vertices)
            anchor += px[v.idx()];
        anchor /= static_cast<double>(loops[i].vertices.size());
        Vec2 out = anchor - map_drawn.center();
        out = out.norm() > 0 ? out.normalized() : Vec2(0, 1);
        cairo_text_extents_t e;
        cairo_text_extents(cr, text.c_str(), &e);
        // Push the text centre out until its box clears the anchor by a font size, in x
        // or in y, whichever comes first along `out`.
        const double gap = o.font_size_px, big = 1e9;
        const double reach =
            std::min(std::abs(out.x()) > 1e-9 ? (0.5 * e.width + gap) / std::abs(out.x()) : big,
                     std::abs(out.y()) > 1e-9 ? (0.5 * e.height + gap) / std::abs(out.y()) : big);
        Vec2 c = anchor + out * reach;
        const Vec2 half(0.5 * e.width + 2, 0.5 * e.height + 1);
        auto place = [&](const Vec2& at) {
            Vec2 q(std::clamp(at.x(), image.min().x() + half.x(), image.max().x() - half.x()),
                   std::clamp(at.y(), image.min().y() + half.y(), image.max().y() - half.y()));
            return Eigen::AlignedBox2d(q - half, q + half);
        };
        // Many openings close together (e.g. 20 outlets): step further out, up to 12 lines'
        // heights, until the label overlaps no label placed before it.
        int steps = 0;
        auto overlaps = [&](const Eigen::AlignedBox2d& b) {
            return std::any_of(placed.begin(), placed.end(),
                               [&](const Eigen::AlignedBox2d& p) { return p.intersects(b); });
        };
        while (steps < 12 && overlaps(place(c)))
        {
            c += out * (e.height + 3);
            ++steps;
        }
        const Eigen::AlignedBox2d b = place(c);
        placed.push_back(b);
        if (steps > 0)
        {
            // A leader line says which opening a displaced label belongs to.
            cairo_set_source_rgb(cr, 0.45, 0.45, 0.45);
            cairo_set_line_width(cr, 0.75);
            cairo_move_to(cr, anchor.x(), anchor.y());
            cairo_line_to(cr, b.center().x() - out.x() * half.x(),
                          b.center().y() - out.y() * half.y());
            cairo_stroke(cr);
        }
        // A translucent patch of background keeps a label readable where it lands on the map.
        cairo_set_source_rgba(cr, o.background[0], o.background[1], o.background[2], 0.7);
        cairo_rectangle(cr, b.min().x(), b.min().y(), b.sizes().x(), b.sizes().y());
        cairo_fill(cr);
        cairo_set_source_rgb(cr, 0.05, 0.05, 0.05);
        draw_text(cr, text, b.center(), 0.5, 0.5);
    }
}

//! Orthonormal view frame (right, up, forward) of the 3D view.
Eigen::Matrix3d view_frame(const Eigen::MatrixX3d& P, const MapImageInput& input,
                           const MapImageOptions& o)
{
    const Eigen::RowVector3d mean = P.colwise().mean();
    const Eigen::MatrixX3d C = P.rowwise() - mean;
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(C.transpose() * C);
    Eigen::Vector3d d = o.view_direction.norm() > 0 ? o.view_direction.normalized()
                                                    : Eigen::Vector3d(eig.eigenvectors().col(0));
    Eigen::Vector3d up =
        o.view_up.norm() > 0 ? o.view_up : Eigen::Vector3d(eig.eigenvectors().col(2));
    up = (up - up.dot(d) * d).normalized();
    if (o.view_up.norm() == 0 && !input.loops.empty() && !input.loops[0].vertices.empty())
    {
        // Automatic up: put the inlet at the bottom, as vessels are usually drawn.
        const Eigen::Vector3d inlet = P.row(input.loops[0].vertices[0].idx()).transpose();
        if ((inlet - mean.transpose()).dot(up) > 0)
            up = -up;
    }
    Eigen::Matrix3d frame;
    frame.col(0) = d.cross(up);
    frame.col(1) = up;
    frame.col(2) = d;
    return frame;
}

void draw_view3d(cairo_t* cr, const MapImageInput& input, const Eigen::VectorXd& values,
                 const MapImageOptions& o, const Shader& shader, const Eigen::AlignedBox2d& panel)
{
    const Mesh& mesh = *input.mesh;
    const Eigen::MatrixX3d P = vertex_positions(mesh);
    const Eigen::Matrix3d frame = view_frame(P, input, o);
    const Eigen::MatrixX3d Q = P * frame;  // columns: screen x, screen y, depth
    Eigen::MatrixX2d screen(Q.rows(), 2);
    screen.col(0) = Q.col(0);
    screen.col(1) = Q.col(1);
    MapImageLayout fit;
    fit_map(fit, screen, shrink(panel, label_padding(cr, input, o)));
    std::vector<Vec2> px(mesh.n_vertices());
    Eigen::AlignedBox2d drawn;
    for (auto v : mesh.vertices())
        drawn.extend(px[v.idx()] = fit.to_pixel(screen.row(v.idx()).transpose()));

    const Eigen::MatrixX3i F = face_indices(mesh);
    std::vector<int> order(F.rows());
    std::iota(order.begin(), order.end(), 0);
    Eigen::VectorXd depth(F.rows());
    for (Eigen::Index f = 0; f < F.rows(); ++f)
        depth[f] = Q(F(f, 0), 2) + Q(F(f, 1), 2) + Q(F(f, 2), 2);
    // Painter's algorithm: far faces (largest depth along the view direction) first.
    std::sort(order.begin(), order.end(), [&](int a, int b) { return depth[a] > depth[b]; });

    CairoPtr<cairo_pattern_t> pattern(cairo_pattern_create_mesh());
    const TrianglePainter painter(shader, o.max_color_step, pattern.get());
    for (int f : order)
    {
        Vec2 p[3];
        double v[3];
        for (int k = 0; k < 3; ++k)
        {
            p[k] = px[F(f, k)];
            v[k] = corner_value(values, o.per_face, f, F(f, k));
        }
        double shade = 1.0;
        if (o.shade3d)
        {
            const Eigen::Vector3d a = P.row(F(f, 0)), b = P.row(F(f, 1)), c = P.row(F(f, 2));
            const Eigen::Vector3d n = (b - a).cross(c - a);
            shade = 0.55 + 0.45 * (n.norm() > 0 ? std::abs(n.normalized().dot(frame.col(2))) : 1.0);
        }
        painter.add(p, v, shade);
    }
    paint_pattern(cr, pattern.get(), panel);
    if (o.loop_labels)
        draw_loop_labels(cr, input.loops, px, o, drawn, panel);
}

void check_input(const MapImageInput& input, const Eigen::VectorXd& values, bool per_face)
{
    if (input.mesh == nullptr)
        throw InvalidInputError("render_map_image: input.mesh is null; pass the cut mesh");
    const auto n = static_cast<Eigen::Index>(input.mesh->n_vertices());
    const auto n_values = per_face ? static_cast<Eigen::Index>(input.mesh->n_faces()) : n;
    if (input.uv.rows() != n || values.size() != n_values)
        throw InvalidInputError(
            "render_map_image: the mesh has " + std::to_string(n) + " vertices and " +
            std::to_string(input.mesh->n_faces()) + " faces but uv has " +
            std::to_string(input.uv.rows()) + " rows and values " + std::to_string(values.size()) +
            " entries; give uv per cut-mesh vertex and values " +
            (per_face ? "per face (per_face is set)" : "per cut-mesh vertex (or set per_face)"));
    if (input.mesh->n_faces() == 0)
        throw InvalidInputError("render_map_image: the mesh has no faces");
    if (input.vectors.rows() != 0 && input.vectors.rows() != n)
        throw InvalidInputError("render_map_image: vectors has " +
                                std::to_string(input.vectors.rows()) + " rows for " +
                                std::to_string(n) + " vertices; give one map vector per "
                                "cut-mesh vertex, or none");
    if (!input.vectors.allFinite())
        throw InvalidInputError("render_map_image: vectors has non-finite entries");
    if (!input.uv.allFinite())
        throw InvalidInputError("render_map_image: uv has non-finite entries");
    for (const auto& loop : input.loops)
        for (auto v : loop.vertices)
            if (v.idx() < 0 || v.idx() >= n)
                throw InvalidInputError("render_map_image: a boundary loop names vertex " +
                                        std::to_string(v.idx()) + ", not in the mesh");
}

CairoPtr<cairo_surface_t> make_surface(Format format, const std::string& path, int w, int h)
{
    cairo_surface_t* s = nullptr;
    switch (format)
    {
        case Format::Png:
            s = cairo_image_surface_create(CAIRO_FORMAT_RGB24, w, h);
            break;
        case Format::Svg:
            s = cairo_svg_surface_create(path.c_str(), w, h);
            break;
        case Format::Pdf:
            s = cairo_pdf_surface_create(path.c_str(), w, h);
            break;
    }
    CairoPtr<cairo_surface_t> surface(s);
    if (cairo_surface_status(s) != CAIRO_STATUS_SUCCESS)
        throw IoError("render_map_image: cannot create " + path + ": " +
                      cairo_status_to_string(cairo_surface_status(s)));
    return surface;
}

//! Panels, left to right: map, 3D view, colorbar (bar, tick labels, rotated title); the map's
//! uv -> pixel transform leaves room for the loop labels.
void plan_panels(cairo_t* cr, const MapImageInput& input, const MapImageOptions& o,
                 MapImageLayout& layout)
{
    const double m = o.margin_px, fs = o.font_size_px;
    const Eigen::AlignedBox2d image = box(m, m, o.width_px - m, o.height_px - m);
    double right = image.max().x();
    if (o.colorbar)
    {
        const double strip = 22 + 8 + tick_labels_width(cr, layout) + 2 * fs;
        const double x0 = image.max().x() - strip;
        layout.colorbar_box = box(x0, image.min().y() + fs, x0 + 22, image.max().y() - fs);
        right = x0 - fs;
    }
    double map_right = right;
    if (o.view3d)
    {
        const double w = (right - image.min().x()) * 0.4;
        layout.view3d_box = box(right - w, image.min().y(), right, image.max().y());
        map_right = right - w - fs;
    }
    layout.map_box = box(image.min().x(), image.min().y(), map_right, image.max().y());
    const Vec2 pad = label_padding(cr, input, o);
    Eigen::AlignedBox2d fit = shrink(layout.map_box, pad);
    if (o.caption.size() > 0)
        fit.min().y() = std::max(fit.min().y(), layout.map_box.min().y() + 1.6 * fs);
    if (o.scale_bar)
        fit.max().y() = std::min(fit.max().y(), layout.map_box.max().y() - scale_bar_strip(o));
    fit_map(layout, input.uv, fit);
    if (o.scale_bar)
        plan_scale_bar(layout, input.uv, pad.y(), o);
}

//! Writes (PNG) or finishes (SVG, PDF) \p tmp's file, then commits it to its target; a failed
//! write leaves no file behind (TempFile removes it).
void finish_file(CairoPtr<cairo_surface_t> surface, Format format, detail::TempFile& tmp)
{
    cairo_status_t status = CAIRO_STATUS_SUCCESS;
    if (format == Format::Png)
        status = cairo_surface_write_to_png(surface.get(), tmp.path().c_str());
    cairo_surface_finish(surface.get());
    if (status == CAIRO_STATUS_SUCCESS)
        status = cairo_surface_status(surface.get());
    surface.reset();
    if (status != CAIRO_STATUS_SUCCESS)
        throw IoError("render_map_image: cannot write " + tmp.path() + ": " +
                      cairo_status_to_string(status));
    tmp.commit();
}

}  // namespace

MapImageInput map_image_input(const FlattenResult& result)
{
    return {&result.mesh, result.uv, result.loops, {}};
}

MapImageInput map_image_input(const Mesh& mesh)
{
    OpenMesh::VPropHandleT<OpenMesh::Vec2d> uv;
    if (!mesh.get_property_handle(uv, prop::uv))
        throw InvalidInputError(std::string("map_image_input: the mesh has no '") + prop::uv +
                                "' vertex property; flatten it first or pass uv explicitly");
    MapImageInput input;
    input.mesh = &mesh;
    input.uv.resize(mesh.n_vertices(), 2);
    for (auto v : mesh.vertices())
        input.uv.row(v.idx()) << mesh.property(uv, v)[0], mesh.property(uv, v)[1];
    return input;
}

MapImageLayout render_map_image(const std::string& path, const MapImageInput& input,
                                const Eigen::VectorXd& values, const MapImageOptions& options)
{
    const Format format = format_of(path);
    check_input(input, values, options.per_face);
    MapImageLayout layout = map_image_range(values, options);
    MapImageOptions o = options;
    if (format != Format::Png)
        o.max_color_step = options.vector_max_color_step;
    detail::TempFile tmp(path, "render_map_image");
    auto surface = make_surface(format, tmp.path(), o.width_px, o.height_px);
    CairoPtr<cairo_t> context(cairo_create(surface.get()));
    cairo_t* cr = context.get();
    set_rgb(cr, o.background);
    cairo_paint(cr);
    cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_font_size(cr, o.font_size_px);

    plan_panels(cr, input, o, layout);

    const Mesh& mesh = *input.mesh;
    std::vector<Vec2> px(mesh.n_vertices());
    Eigen::AlignedBox2d drawn;
    for (auto v : mesh.vertices())
        drawn.extend(px[v.idx()] = layout.to_pixel(input.uv.row(v.idx()).transpose()));
    const Shader shader{&layout, o.nan_color};
    {
        CairoPtr<cairo_pattern_t> pattern(cairo_pattern_create_mesh());
        draw_map(cr, mesh, px, values, o.per_face,
                 TrianglePainter(shader, o.max_color_step, pattern.get()), pattern.get(),
                 layout.map_box);
    }
    if (input.vectors.rows() > 0)
        draw_arrows(cr, input, layout, o);
    if (o.outline)
        draw_outline(cr, mesh, px, o.outline_width_px);
    if (o.loop_labels)
        draw_loop_labels(cr, input.loops, px, o, drawn, layout.map_box);
    if (o.view3d)
        draw_view3d(cr, input, values, o, shader, layout.view3d_box);
    if (o.colorbar)
        draw_colorbar(cr, layout, o);
    if (!layout.scale_bar_box.isEmpty())
        draw_scale_bar(cr, layout, o);
    if (!o.caption.empty())
    {
        cairo_set_source_rgb(cr, 0, 0, 0);
        draw_text(cr, o.caption, layout.map_box.min(), 0.0, 0.0);
    }

    context.reset();
    finish_file(std::move(surface), format, tmp);
    return layout;
}

}  // namespace vessel
