#include "viewer_fields.h"

namespace vessel::cli {

namespace {

Eigen::VectorXf scalar_values(const Field& field)
{
    return field.components() == 1 ? Eigen::VectorXf(field.values.col(0).cast<float>())
                                   : Eigen::VectorXf(field.values.rowwise().norm().cast<float>());
}

ViewerField start(const Field& field)
{
    ViewerField out;
    out.name = field.components() == 1 ? field.name : "|" + field.name + "|";
    return out;
}

}  // namespace

std::vector<ViewerField> viewer_fields(const std::vector<Field>& fields, const TimeSeries& series)
{
    std::vector<ViewerField> out;
    for (const auto& f : fields)
        if (f.location == FieldLocation::Point)
        {
            ViewerField v = start(f);
            v.times = {0.0};
            v.steps = {scalar_values(f)};
            out.push_back(std::move(v));
        }
    if (series.size() == 0)
        return out;
    for (std::size_t i = 0; i < series.steps[0].size(); ++i)
    {
        if (series.steps[0][i].location != FieldLocation::Point)
            continue;
        ViewerField v = start(series.steps[0][i]);
        v.times = series.times;
        for (const auto& step : series.steps)
            v.steps.push_back(scalar_values(step[i]));
        out.push_back(std::move(v));
    }
    return out;
}

}  // namespace vessel::cli
