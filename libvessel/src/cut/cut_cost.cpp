#include "vessel/cut/cut_cost.h"

#include "vessel/core/errors.h"

#include <cmath>

namespace vessel {

void CostOptions::validate() const
{
    if (!(blend >= 0.0 && blend <= 1.0))
        throw InvalidInputError("CostOptions: blend must be in [0, 1], got " +
                                std::to_string(blend));
}

void check_weight(double w, int halfedge)
{
    if (!(w >= 0.0) || !std::isfinite(w))
        throw InvalidInputError("evaluate_cost: the cost of halfedge " + std::to_string(halfedge) +
                                " is " + std::to_string(w) +
                                "; a travel cost must be finite and >= 0");
}

HalfedgeWeights evaluate_cost(const Mesh& mesh, const CustomCost& cost, const VesselFields& fields)
{
    if (!cost)
        throw InvalidInputError("evaluate_cost: the custom cost is empty");
    return evaluate_cost(mesh, [&](const Mesh& m, SmartHalfedgeHandle h) {
        return cost(m, h, fields);
    });
}

double CurvatureCost::operator()(const Mesh& mesh, SmartHalfedgeHandle h) const
{
    const Eigen::Vector3d e = to_eigen(mesh.point(h.to()) - mesh.point(h.from()));
    const double length = e.norm();
    if (length == 0.0)
        return 1.0;
    const Eigen::Vector3d z = direction->row(h.from().idx());
    // Clamp: the directions are unit only up to rounding.
    return std::max(0.0, 1.0 - e.dot(z) / length);
}

double LengthCost::operator()(const Mesh& mesh, SmartHalfedgeHandle h) const
{
    return mesh.calc_edge_length(h) / unit;
}

double BlendCost::operator()(const Mesh& mesh, SmartHalfedgeHandle h) const
{
    return a * curvature(mesh, h) + (1.0 - a) * length(mesh, h);
}

}  // namespace vessel
