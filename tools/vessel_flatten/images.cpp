#include "images.h"

#include "vessel/errors.h"
#include "vessel/map_frames.h"
#include "vessel/map_image.h"

#include <cstdio>

namespace vessel::cli {

namespace {

// One value per cut vertex: the scalar itself, or a vector's length.
Eigen::VectorXd scalar_values(const Field& field)
{
    if (field.location != FieldLocation::Point)
        throw InvalidInputError("--image/--frames draw point fields; '" + field.name +
                                "' is a cell field");
    return field.components() == 1 ? Eigen::VectorXd(field.values.col(0))
                                   : Eigen::VectorXd(field.values.rowwise().norm());
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

}  // namespace

void render_images(const ImageRequest& request, const FlattenResult& result,
                   const std::vector<Field>& fields, const TimeSeries& series)
{
    if (request.image.empty() && request.frames.empty())
        return;
    std::vector<Field> candidates = series.size() > 0 ? series.steps[0] : std::vector<Field>{};
    candidates.insert(candidates.end(), fields.begin(), fields.end());
    const Field& field = chosen(request.field, candidates);
    const MapImageInput input = map_image_input(result);
    MapImageOptions options;
    options.field_name = field.components() == 1 ? field.name : "|" + field.name + "|";
    if (!request.image.empty())
    {
        render_map_image(request.image, input, scalar_values(field), options);
        if (!request.quiet)
            std::fprintf(stderr, "[  ] image of %s -> %s\n", field.name.c_str(),
                         request.image.c_str());
    }
    if (request.frames.empty())
        return;
    if (series.size() < 2)
        throw InvalidInputError("--frames needs a time series with several steps (--fields)");
    FieldSeries values;
    values.times = series.times;
    for (const auto& step : series.steps)
        values.values.push_back(scalar_values(find_field(step, field.name)));
    const FramesSummary s = render_frames(request.frames, input, values, options);
    if (!request.quiet)
        std::fprintf(stderr, "[  ] %d frames of %s -> %s\n", s.frames, field.name.c_str(),
                     request.frames.c_str());
}

}  // namespace vessel::cli
