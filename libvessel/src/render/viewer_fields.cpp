#include "vessel/core/errors.h"
#include "vessel/core/properties.h"
#include "vessel/render/viewer.h"

#include <cmath>

namespace vessel {

namespace {

Eigen::VectorXd geodesic_distance(const FlattenResult& result, const char* caller)
{
    OpenMesh::VPropHandleT<double> geodesic;
    if (!result.mesh.get_property_handle(geodesic, prop::geodesic))
        throw InvalidInputError(std::string(caller) + ": the mesh has no '" + prop::geodesic +
                                "' property; pass the result of flatten()");
    Eigen::VectorXd d(result.mesh.n_vertices());
    for (auto v : result.mesh.vertices())
        d[v.idx()] = result.mesh.property(geodesic, v);
    return d;
}

}  // namespace

void PulseOptions::validate() const
{
    if (steps < 2)
        throw InvalidInputError("PulseOptions::steps must be at least 2, got " +
                                std::to_string(steps));
    if (!(period_s > 0) || !std::isfinite(period_s))
        throw InvalidInputError("PulseOptions::period_s must be positive, got " +
                                std::to_string(period_s));
    if (!(wavelengths > 0) || !std::isfinite(wavelengths))
        throw InvalidInputError("PulseOptions::wavelengths must be positive, got " +
                                std::to_string(wavelengths));
}

ViewerField geodesic_field(const FlattenResult& result, const std::string& unit)
{
    ViewerField field;
    field.name = "geodesic distance from inlet";
    field.unit = unit;
    field.times = {0.0};
    field.steps = {geodesic_distance(result, "geodesic_field").cast<float>()};
    return field;
}

ViewerField pulse_field(const FlattenResult& result, const PulseOptions& options)
{
    options.validate();
    const Eigen::VectorXd d = geodesic_distance(result, "pulse_field");
    const double d_max = std::max(d.maxCoeff(), 1e-300);
    ViewerField field;
    field.name = "demo pulse (synthetic)";
    field.diverging = true;
    for (int i = 0; i < options.steps; ++i)
    {
        const double t = options.period_s * i / options.steps;
        field.times.push_back(t);
        const Eigen::ArrayXd phase = t / options.period_s - options.wavelengths * d.array() / d_max;
        field.steps.push_back((2 * M_PI * phase).sin().cast<float>().matrix());
    }
    return field;
}

}  // namespace vessel
