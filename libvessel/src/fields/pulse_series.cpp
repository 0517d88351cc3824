#include "vessel/fields/pulse_series.h"

#include "vessel/cut/boundary.h"
#include "vessel/core/errors.h"
#include "vessel/core/operators.h"
#include "vessel/direction/geodesic.h"

#include <cmath>

namespace vessel {

void PulseSeriesOptions::validate() const
{
    const auto require = [](bool ok, const std::string& what) {
        if (!ok)
            throw InvalidInputError("PulseSeriesOptions: " + what);
    };
    require(!name.empty(), "name must not be empty");
    require(duration_s > 0 && std::isfinite(duration_s), "duration_s must be positive");
    require(steps >= 1, "steps must be at least 1");
    require(period_s > 0 && std::isfinite(period_s), "period_s must be positive");
    require(width > 0 && width < 1, "width must be in (0, 1)");
    require(std::isfinite(base_pa) && std::isfinite(peak_pa), "base_pa and peak_pa must be finite");
}

TimeSeries travelling_pulse(const Mesh& mesh, const PulseSeriesOptions& options)
{
    options.validate();
    const auto loops = boundary_loops(mesh);
    if (loops.empty())
        throw InvalidInputError("travelling_pulse: the mesh has no open end to start from");
    Eigen::VectorXd s = heat_geodesic_distance(mesh, loops[0].vertices);
    const double longest = s.maxCoeff();
    if (!(longest > 0) || !std::isfinite(longest))
        throw InvalidInputError("travelling_pulse: the mesh is not one connected piece");
    s /= longest;
    Eigen::MatrixX3d direction = Eigen::MatrixX3d::Ones(s.size(), 3);  // unused by a scalar
    if (options.vector)
    {
        direction = vertex_gradient(mesh, s);
        for (Eigen::Index i = 0; i < direction.rows(); ++i)
        {
            const double norm = direction.row(i).norm();
            direction.row(i) = norm > 0.0 ? Eigen::RowVector3d(direction.row(i) / norm)
                                          : Eigen::RowVector3d::Zero();
        }
    }
    TimeSeries series;
    for (int k = 0; k < options.steps; ++k)
    {
        const double t = k * options.duration_s / options.steps;
        const double phase = t / options.period_s - std::floor(t / options.period_s);
        const double c = (1 + 6 * options.width) * phase - 3 * options.width;
        const int components = options.vector ? 3 : 1;
        Field f{options.name, FieldLocation::Point, FieldType::Float64,
                Eigen::MatrixXd(s.size(), components)};
        for (Eigen::Index i = 0; i < s.size(); ++i)
        {
            const double d = (s[i] - c) / options.width;
            const double value = options.base_pa + options.peak_pa * std::exp(-0.5 * d * d);
            f.values.row(i) = value * direction.row(i).head(components);
        }
        series.times.push_back(t);
        series.steps.push_back({std::move(f)});
        series.sources.push_back("travelling_pulse step " + std::to_string(k));
    }
    return series;
}

}  // namespace vessel
