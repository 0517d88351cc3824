#include "images.h"

#include "field_input.h"
#include "vessel/core/errors.h"
#include "vessel/fields/map_vectors.h"
#include "vessel/render/map_frames.h"
#include "vessel/render/map_image.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace vessel::cli {

namespace {

// One value per cut vertex: the scalar itself, a vector's length, or its chosen component.
Eigen::VectorXd scalar_values(const Field& field, int component)
{
    if (field.location != FieldLocation::Point)
        throw InvalidInputError("--image/--frames draw point fields; '" + field.name +
                                "' is a cell field");
    if (component >= field.components())
        throw InvalidInputError("--field " + field.name + ":" + "xyz"[component] + ": '" +
                                field.name + "' has " + std::to_string(field.components()) +
                                (field.components() == 1 ? " component" : " components"));
    if (component >= 0)
        return field.values.col(component);
    return field.components() == 1 ? Eigen::VectorXd(field.values.col(0))
                                   : Eigen::VectorXd(field.values.rowwise().norm());
}

// The figure controls of the request (range, colormap, size); validate() says what is wrong.
MapImageOptions figure_options(const ImageRequest& request)
{
    MapImageOptions options;
    options.colormap = request.colormap;
    if (!request.range.empty())
    {
        options.auto_range = false;
        options.range_min = request.range.at(0);
        options.range_max = request.range.at(1);
    }
    if (!request.size.empty())
    {
        options.width_px = request.size.at(0);
        options.height_px = request.size.at(1);
    }
    options.units = request.units;
    options.labels = request.labels;
    if (request.max_color_step)
        options.max_color_step = *request.max_color_step;
    return options;
}

// The field to draw: --field NAME, else the series' first point field, else the input's.
const Field& chosen(const std::string& name, const std::vector<Field>& candidates)
{
    if (!name.empty())
        return find_field(candidates, name);
    for (const auto& f : candidates)
        if (f.location == FieldLocation::Point)
            return f;
    throw InvalidInputError("--image/--frames: no point field to draw; give --fields");
}

// True if \p name is a field of a series of several steps.
bool in_series(const TimeSeries& series, const std::string& name)
{
    return series.size() > 1 &&
           std::any_of(series.steps[0].begin(), series.steps[0].end(),
                       [&](const Field& f) { return f.name == name; });
}

std::string seconds(double t)
{
    char text[32];
    std::snprintf(text, sizeof text, "%g s", t);
    return text;
}

// The values --image draws from a series, and the colorbar title's "at t = ..." suffix.
std::pair<Eigen::VectorXd, std::string> series_moment(const ImageRequest& request,
                                                      const FieldSeries& values)
{
    const auto& times = values.times;
    if (request.time)
    {
        const double t = *request.time;
        if (!(t >= times.front() && t <= times.back()))
            throw InvalidInputError("--image-time " + seconds(t) + " is outside the series (" +
                                    seconds(times.front()) + " to " + seconds(times.back()) +
                                    ")");
        return {interpolate_series(values, t), " at t = " + seconds(t)};
    }
    const int k = request.step.value_or(0);
    if (k < 0 || k >= static_cast<int>(times.size()))
        throw InvalidInputError("--image-step " + std::to_string(k) + ": the series has steps 0 to " +
                                std::to_string(times.size() - 1));
    return {values.values[k], " at t = " + seconds(times[k])};
}

// The fields --field and --image-arrows choose from: the series' (step 0) first, then the
// static ones.
std::vector<Field> candidates_of(const std::vector<Field>& fields, const TimeSeries& series)
{
    std::vector<Field> candidates = series.size() > 0 ? series.steps[0] : std::vector<Field>{};
    candidates.insert(candidates.end(), fields.begin(), fields.end());
    return candidates;
}

// The field to draw (a copy: the candidates are a local list) and whether it changes over time;
// throws if the request cannot be drawn.
std::pair<Field, bool> requested_field(const ImageRequest& request,
                                       const std::vector<Field>& fields, const TimeSeries& series)
{
    const std::vector<Field> candidates = candidates_of(fields, series);
    const Field& field = chosen(parse_field_choice(request.field).name, candidates);
    const bool over_time = in_series(series, field.name);
    if ((request.step || request.time) && !over_time)
        throw InvalidInputError("--image-step/--image-time choose a moment of a time series; '" +
                                field.name + "' is not one (give --fields with a series)");
    scalar_values(field, parse_field_choice(request.field).component);  // refuses a cell field
    if (!request.frames.empty() && !over_time)
        throw InvalidInputError("--frames needs a time series with several steps (--fields); '" +
                                field.name + "' has one");
    return {field, over_time};
}

// The --image-arrows array among the candidates; throws unless it is a 3-component point array.
const Field& arrows_field(const std::string& name, const std::vector<Field>& candidates)
{
    const Field& field = find_field(candidates, name);
    if (field.location != FieldLocation::Point || field.components() != 3)
        throw InvalidInputError("--image-arrows " + name + ": arrows need a 3-component point "
                                "array (a vector per vertex, e.g. WSS); '" + name + "' is a " +
                                std::to_string(field.components()) + "-component " +
                                (field.location == FieldLocation::Point ? "point" : "cell") +
                                " array");
    return field;
}

// The 3D vectors of --image-arrows: a static array as it is; a series' at the moment --image
// draws (step or time), or with `average` its time average (trapezoid rule over the steps).
Eigen::MatrixXd arrow_vectors(const ImageRequest& request, const std::vector<Field>& fields,
                              const TimeSeries& series, bool average)
{
    const std::vector<Field> candidates = candidates_of(fields, series);
    const Field& field = arrows_field(request.arrows, candidates);
    if (!in_series(series, field.name))
        return field.values;
    const auto at = [&](int k) -> const Eigen::MatrixXd& {
        return find_field(series.steps[k], field.name).values;
    };
    const auto& t = series.times;
    if (average)
    {
        Eigen::MatrixXd sum = Eigen::MatrixXd::Zero(field.rows(), 3);
        for (int k = 0; k + 1 < series.size(); ++k)
            sum += 0.5 * (t[k + 1] - t[k]) * (at(k) + at(k + 1));
        return sum / (t.back() - t.front());
    }
    if (request.time)  // within the series: series_moment() checked it for the colours
    {
        const auto upper = std::upper_bound(t.begin(), t.end(), *request.time);
        const int k = std::clamp(static_cast<int>(upper - t.begin()) - 1, 0, series.size() - 2);
        const double w = (*request.time - t[k]) / (t[k + 1] - t[k]);
        return (1.0 - w) * at(k) + w * at(k + 1);
    }
    return at(request.step.value_or(0));
}

// 3D vectors per cut vertex as map vectors (map_fields(): the part along the wall, pushed
// through the map).
Eigen::MatrixX2d map_arrows(const FlattenResult& result, Eigen::MatrixXd vectors)
{
    const Field field{"arrows", FieldLocation::Point, FieldType::Float64, std::move(vectors)};
    return map_fields({field}, result.mesh, result.uv).front().values.leftCols(2);
}

}  // namespace

void check_images(const ImageRequest& request, const std::vector<Field>& fields,
                  const TimeSeries& series)
{
    if (request.images.empty() && request.frames.empty())
        return;
    requested_field(request, fields, series);
    if (!request.arrows.empty())
        arrows_field(request.arrows, candidates_of(fields, series));
    if (!request.range.empty() && !(std::isfinite(request.range[0]) &&
                                    std::isfinite(request.range[1]) &&
                                    request.range[0] < request.range[1]))
        throw InvalidInputError("--image-range: LO must be below HI, both finite (got " +
                                std::to_string(request.range[0]) + " " +
                                std::to_string(request.range[1]) + ")");
    for (int side : request.size)
        if (side < 64 || side > 16384)
            throw InvalidInputError("--image-size: W and H must be in [64, 16384] pixels (got " +
                                    std::to_string(side) + ")");
    if (!(request.fps > 0 && request.fps <= 240))
        throw InvalidInputError("--fps must be in (0, 240] (got " + std::to_string(request.fps) +
                                ")");
    figure_options(request).validate();  // what the above does not cover (e.g. the margins)
}

void render_images(const ImageRequest& request, const FlattenResult& result,
                   const std::vector<Field>& fields, const TimeSeries& series)
{
    if (request.images.empty() && request.frames.empty())
        return;
    const auto [field, over_time] = requested_field(request, fields, series);
    const FieldChoice choice = parse_field_choice(request.field);
    MapImageInput input = map_image_input(result);
    MapImageOptions options = figure_options(request);
    options.field_name = request.title.empty()
                             ? FieldChoice{field.name, choice.component}.title(field.components())
                             : request.title;
    FieldSeries values;
    if (over_time)
    {
        values.times = series.times;
        for (const auto& step : series.steps)
            values.values.push_back(
                scalar_values(find_field(step, field.name), choice.component));
    }
    if (!request.images.empty())
    {
        MapImageOptions image_options = options;
        Eigen::VectorXd shown;
        if (over_time)
        {
            std::string when;
            std::tie(shown, when) = series_moment(request, values);
            image_options = series_range_options(values, options);
            image_options.field_name += when;
        }
        else
            shown = scalar_values(field, choice.component);
        image_options.view3d = request.view3d;
        MapImageInput with_arrows = input;
        if (!request.arrows.empty())
            with_arrows.vectors = map_arrows(result, arrow_vectors(request, fields, series, false));
        for (const auto& path : request.images)
        {
            render_map_image(path, with_arrows, shown, image_options);
            if (!request.quiet)
                std::fprintf(stderr, "[  ] image of %s -> %s\n",
                             image_options.field_name.c_str(), path.c_str());
        }
    }
    if (request.frames.empty())
        return;
    if (!request.arrows.empty())
        input.vectors = map_arrows(result, arrow_vectors(request, fields, series, true));
    FrameOptions frames;
    frames.fps = request.fps;
    const FramesSummary s = render_frames(request.frames, input, values, options, frames);
    if (!request.quiet)
        std::fprintf(stderr, "[  ] %d frames of %s -> %s\n", s.frames, field.name.c_str(),
                     request.frames.c_str());
}

}  // namespace vessel::cli
