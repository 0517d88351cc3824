// vessel-render: flatten a vessel surface and draw a field on the map (PNG, SVG or PDF): a
// built-in one, a CSV column, an array of the input (.vtp/.vtk) or of --fields as vessel-flatten
// reads them; or frames of a series (synthetic pulse or --fields) (+ GIF/MP4 with ffmpeg).
#include "common/restart.h"
#include "common/stage_status.h"
#include "flat_obj.h"
#include "vessel/check/validation.h"
#include "vessel/core/errors.h"
#include "vessel/core/properties.h"
#include "vessel/fields/field_series.h"
#include "vessel/io/vtk_io.h"  // inputs may be .vtp/.vtk
#include "vessel/pipeline.h"
#include "vessel/render/map_frames.h"
#include "vessel/render/map_image.h"
#include "vessel_flatten/field_input.h"
#include "vessel_flatten/images.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace {

using vessel::InvalidInputError;

//! First column of a CSV (or one number per line), one row per input-file vertex; a header line
//! that does not parse as a number is skipped.
std::vector<double> read_column(const std::string& path)
{
    std::ifstream in(path);
    if (!in)
        throw vessel::IoError("cannot open " + path);
    std::vector<double> column;
    std::string line;
    for (int row = 0; std::getline(in, line); ++row)
    {
        std::istringstream cell(line.substr(0, line.find(',')));
        double x;
        if (cell >> x)
            column.push_back(x);
        else if (row > 0 && !line.empty())
            throw InvalidInputError(path + ": line " + std::to_string(row + 1) +
                                    " does not start with a number: '" + line + "'");
    }
    return column;
}

//! True for an OBJ with `vt` lines: a map written by vessel-flatten, drawn without flattening.
bool is_flat_obj(const std::string& path)
{
    std::string ext = path.size() >= 4 ? path.substr(path.size() - 4) : "";
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return std::tolower(c); });
    if (ext != ".obj")
        return false;
    std::ifstream in(path);
    std::string line;
    while (std::getline(in, line))
        if (line.rfind("vt ", 0) == 0)
            return true;
    return false;
}

//! A named vertex property as one entry per vertex, indexed by `v.idx()`.
template <class T>
std::vector<T> vertex_property(const vessel::Mesh& mesh, const char* name)
{
    OpenMesh::VPropHandleT<T> handle;
    if (!mesh.get_property_handle(handle, name))
        throw InvalidInputError(std::string("the flattened mesh has no '") + name + "' property");
    std::vector<T> column(mesh.n_vertices());
    for (auto v : mesh.vertices())
        column[v.idx()] = mesh.property(handle, v);
    return column;
}

//! Value per cut-mesh vertex of a named field, with its title and units.
Eigen::VectorXd field_values(const vessel::Mesh& mesh, const std::string& field,
                             const std::string& csv, std::string& title, std::string& units,
                             double& clip_max)
{
    Eigen::VectorXd values(mesh.n_vertices());
    if (!csv.empty())
    {
        const std::vector<double> column = read_column(csv);
        title = "value";
        const auto index = vertex_property<int>(mesh, vessel::prop::input_index);
        for (auto v : mesh.vertices())
        {
            const int i = index[v.idx()];
            if (i < 0 || i >= static_cast<int>(column.size()))
                throw InvalidInputError(csv + " has " + std::to_string(column.size()) +
                                        " values but the mesh has input vertex " +
                                        std::to_string(i) + "; give one row per input vertex");
            values[v.idx()] = column[i];
        }
        return values;
    }
    if (field == "geodesic")
    {
        const auto g = vertex_property<double>(mesh, vessel::prop::geodesic);
        for (auto v : mesh.vertices())
            values[v.idx()] = g[v.idx()];
        title = "geodesic distance from the inlet";
        return values;
    }
    if (field == "wss")
    {
        // Poiseuille flow through a tube of radius r = 1 / kmax: WSS grows as 1 / r^3. Scaled
        // by the median so that 1 = a typical section; a picture of where narrowings are.
        const auto k = vertex_property<double>(mesh, vessel::prop::kmax);
        std::vector<double> cubes;
        for (auto v : mesh.vertices())
            cubes.push_back(values[v.idx()] = std::pow(k[v.idx()], 3));
        std::nth_element(cubes.begin(), cubes.begin() + cubes.size() / 2, cubes.end());
        const double median = cubes[cubes.size() / 2];
        values /= median;
        title = "synthetic WSS ~ 1/r^3";
        // kmax is noisy and cubed: a few vertices reach far above the rest; clip the colour
        // range at the 99th percentile so the field's pattern stays visible.
        std::nth_element(cubes.begin(), cubes.begin() + cubes.size() * 99 / 100, cubes.end());
        clip_max = cubes[cubes.size() * 99 / 100] / median;
        units = "x median";
        return values;
    }
    const int axis = field == "x" ? 0 : field == "y" ? 1 : 2;
    for (auto v : mesh.vertices())
        values[v.idx()] = mesh.point(v)[axis];
    title = field;
    return values;
}

//! A Gaussian pulse travelling from the inlet along the geodesic distance: `steps` steps over
//! `period` seconds, as a CFD export of one heart cycle would give.
vessel::FieldSeries pulse_series(const vessel::Mesh& mesh, int steps, double period)
{
    const auto g = vertex_property<double>(mesh, vessel::prop::geodesic);
    double g_max = 0;
    for (auto v : mesh.vertices())
        g_max = std::max(g_max, g[v.idx()]);
    vessel::FieldSeries series;
    for (int k = 0; k < steps; ++k)
    {
        const double t = period * k / steps;
        const double centre = g_max * (1.2 * t / period - 0.1);
        Eigen::VectorXd v(mesh.n_vertices());
        for (auto vh : mesh.vertices())
            v[vh.idx()] = std::exp(-std::pow((g[vh.idx()] - centre) / (0.12 * g_max), 2));
        series.times.push_back(t);
        series.values.push_back(v);
    }
    return series;
}

}  // namespace

int main(int argc, char** argv)
{
    CLI::App app{
        "vessel-render: flatten a vessel surface and draw a field on the map.\n"
        "Fields: geodesic (distance from the inlet), wss (synthetic 1/r^3), x, y, z, "
        "--values FILE.csv (one row per input vertex), or a point array of a .vtp/.vtk input "
        "or of --fields (NAME[:magnitude|x|y|z], as vessel-flatten --field).",
        "vessel-render"};
    std::string input, output, field = "geodesic", csv, title, units, frames, animation;
    std::vector<std::string> labels;
    std::vector<double> range;
    vessel::MapImageOptions image;
    vessel::FrameOptions frame_options;
    int steps = 90;
    double period = 1.8;
    app.add_option("input", input,
                   "Vessel surface (.obj, .off, .ply, .stl, .vtp, .vtk), or a map written "
                   "by vessel-flatten (.obj with vt lines)")
        ->required()
        ->check(CLI::ExistingFile);
    app.add_option("output", output, "Image (.png, .svg or .pdf)")->required();
    app.add_option("--field", field,
                   "Field to draw: geodesic, wss, x, y, z, or an array of the input or of "
                   "--fields, NAME[:magnitude|x|y|z]")
        ->capture_default_str();
    vessel::cli::FieldArgs field_args;
    vessel::cli::add_field_options(app, field_args, "to draw (their --field array)", false);
    app.add_option("--values", csv, "CSV whose first column gives one value per input vertex");
    app.add_option("--title", title, "Colorbar title (default: the field's name)");
    app.add_option("--units", units, "Units shown after the title");
    app.add_option("--range", range, "Fixed colour range LO HI")->expected(2);
    app.add_option("--labels", labels,
                   "Labels of the inlet and outlets, in loop order "
                   "(longest loop first)");
    app.add_flag("--view3d", image.view3d, "Draw the 3D mesh beside the map");
    std::string arrows;
    app.add_option("--arrows", arrows,
                   "Arrows of this 3-component point array of the input or of --fields (its "
                   "direction along the wall) over the colours; --frames: its time average")
        ->option_text("NAME");
    app.add_option("--size", image.width_px, "Image width in pixels")->capture_default_str();
    app.add_option("--height", image.height_px, "Image height in pixels")->capture_default_str();
    app.add_option("--color-step", image.max_color_step,
                   "Split triangles whose values span more than this fraction of the range")
        ->capture_default_str();
    app.add_option("--frames", frames,
                   "Instead of one image: frames of a series written to DIR: the --fields "
                   "series' --field, else a synthetic pulse travelling from the inlet");
    app.add_option("--steps", steps, "Time steps of the pulse series")->capture_default_str();
    app.add_option("--period", period, "Seconds the series spans")->capture_default_str();
    app.add_option("--fps", frame_options.fps, "Frames per second")->capture_default_str();
    app.add_option("--slowdown", frame_options.slowdown, "Animation seconds per series second")
        ->capture_default_str();
    app.add_option("--animation", frame_options.animation, "Also write a .gif or .mp4 (ffmpeg)");
    try
    {
        app.parse(argc, argv);
    }
    catch (const CLI::ParseError& e)
    {
        return app.exit(e) == 0 ? 0 : 1;
    }
    // The map is made as vessel-flatten makes it: with huge pages for a large input and the
    // same BLAS kernels (the process starts again with them if it must, before any output).
    vessel::cli::restart_for_run(argv, input);
    try
    {
        // A surface is flattened as vessel-flatten flattens it, the step running named on a
        // status line on a terminal (erased before any other output, an error's included).
        vessel::cli::LiveLine live = vessel::cli::LiveLine::on_terminal(false);
        const auto flatten = [&live](const vessel::Mesh& mesh) {
            vessel::FlattenOptions options;
            vessel::cli::show_stages(options, live, false);
            vessel::FlattenResult result = vessel::flatten(mesh, options);
            live.hide();
            return result;
        };
        const bool builtin = field == "geodesic" || field == "wss" || field == "x" ||
                             field == "y" || field == "z";
        const bool arrays = !field_args.spec.empty() || (!builtin && csv.empty());
        if (!arrows.empty() && !arrays)
            throw InvalidInputError("--arrows " + arrows + " draws over an array of the input or "
                                    "of --fields; give --field NAME of an array, not " +
                                    (csv.empty() ? "the built-in '" + field + "'" : "--values"));
        if (arrays)
        {
            // An array of the input or of --fields, read, checked, carried and drawn as
            // vessel-flatten --image/--frames does.
            if (is_flat_obj(input))
                throw InvalidInputError(input + " is a flattened map: arrays (--field " + field +
                                        ", --fields) need the surface they belong to");
            if (!csv.empty())
                throw InvalidInputError("--values and --fields: give one source of values");
            field_args.name = builtin ? std::string() : field;
            vessel::cli::ImageRequest request;
            if (frames.empty())
                request.images = {output};
            request.frames = frames;
            request.field = field_args.name;
            request.units = units;
            request.title = title;
            request.labels = labels;
            request.max_color_step = image.max_color_step;
            request.range = range;
            request.size = {image.width_px, image.height_px};
            request.fps = frame_options.fps;
            request.view3d = image.view3d;
            request.arrows = arrows;
            const vessel::cli::FieldInput in = vessel::cli::read_field_input(input, field_args);
            vessel::cli::check_images(request, in.fields, in.series);
            const vessel::FlattenResult flat =
                flatten(vessel::make_tree_surface(in.data.mesh).mesh);  // read once
            for (const auto& note : flat.notes)
                std::fprintf(stderr, "note: %s\n", note.c_str());
            vessel::cli::render_images(request, flat, vessel::transfer_fields(in.fields, flat.mesh),
                                       vessel::transfer_series(in.series, flat.mesh));
            return 0;
        }
        // Either a map written by vessel-flatten, or a surface flattened here.
        vessel::FlattenResult flat;
        if (is_flat_obj(input))
        {
            vessel::cli::FlatObj obj = vessel::cli::read_flat_obj(input);
            if (!csv.empty() || field == "x" || field == "y" || field == "z")
            {
                flat.mesh = std::move(obj.mesh);
                flat.uv = std::move(obj.uv);
                flat.loops = std::move(obj.loops);
            }
            else
                throw InvalidInputError(input +
                                        " is a flattened map: draw --field x, y or z or "
                                        "--values FILE.csv; geodesic, wss and --frames "
                                        "need the surface");
        }
        else
        {
            flat = flatten(vessel::load_tree_surface(input).mesh);
            for (const auto& note : flat.notes)
                std::fprintf(stderr, "note: %s\n", note.c_str());
        }
        const vessel::MapImageInput map = vessel::map_image_input(flat);
        image.labels = labels;
        if (range.size() == 2)
        {
            image.auto_range = false;
            image.range_min = range[0];
            image.range_max = range[1];
        }
        if (!frames.empty())
        {
            image.field_name = title.empty() ? "pulse" : title;
            image.units = units;
            const vessel::FramesSummary s = vessel::render_frames(
                frames, map, pulse_series(flat.mesh, steps, period), image, frame_options);
            std::printf("%d frames in %s, range [%g, %g]\n", s.frames, frames.c_str(), s.range_min,
                        s.range_max);
            if (!s.message.empty())
                std::fprintf(stderr, "note: %s\n", s.message.c_str());
            return 0;
        }
        std::string field_title, field_units;
        double clip_max = 0;
        const Eigen::VectorXd values =
            field_values(flat.mesh, field, csv, field_title, field_units, clip_max);
        if (clip_max > 0 && range.empty())
        {
            image.auto_range = false;
            image.range_min = 0;
            image.range_max = clip_max;
            std::printf("colour range clipped at the 99th percentile, %g\n", clip_max);
        }
        image.field_name = title.empty() ? field_title : title;
        image.units = units.empty() ? field_units : units;
        const auto start = std::chrono::steady_clock::now();
        const vessel::MapImageLayout layout = vessel::render_map_image(output, map, values, image);
        const double seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        std::printf("wrote %s: %zu triangles, range [%g, %g], %s colormap, %.2f s\n",
                    output.c_str(), flat.mesh.n_faces(), layout.range_min, layout.range_max,
                    layout.colormap == vessel::Colormap::Diverging ? "diverging" : "viridis",
                    seconds);
    }
    catch (const std::exception& e)
    {
        std::fprintf(stderr, "vessel-render: %s\n", e.what());
        return 1;
    }
    return 0;
}
