#include "vessel/cut/cut_cost.h"

#include "vessel/core/errors.h"

#include <algorithm>
#include <cmath>

namespace vessel {

void CostOptions::validate() const
{
    if (!(blend >= 0.0 && blend <= 1.0))
        throw InvalidInputError("CostOptions: blend must be in [0, 1], got " +
                                std::to_string(blend));
    if (viewpoint && !viewpoint->allFinite())
        throw InvalidInputError("CostOptions: the viewpoint must have 3 finite coordinates");
    if (viewpoint && face_on)
        throw InvalidInputError("CostOptions: give a viewpoint or face_on, not both");
    if (!(facing_weight >= 0.0) || !std::isfinite(facing_weight))
        throw InvalidInputError("CostOptions: facing_weight must be finite and >= 0, got " +
                                std::to_string(facing_weight));
}

void price_facing(const Mesh& mesh, const Eigen::Vector3d& viewpoint, double weight,
                  HalfedgeWeights& weights)
{
    if (weights.size() != mesh.n_halfedges())
        throw InvalidInputError("price_facing: " + std::to_string(weights.size()) +
                                " costs for " + std::to_string(mesh.n_halfedges()) +
                                " halfedges; pass one per halfedge, indexed by h.idx()");
    if (!viewpoint.allFinite())
        throw InvalidInputError("price_facing: the viewpoint must have 3 finite coordinates");
    if (!(weight >= 0.0) || !std::isfinite(weight))
        throw InvalidInputError("price_facing: the weight must be finite and >= 0, got " +
                                std::to_string(weight));
    for (auto e : mesh.edges())
    {
        Eigen::Vector3d normal = Eigen::Vector3d::Zero();
        for (auto f : {e.h0().face(), e.h1().face()})
            if (f.is_valid())
            {
                const Eigen::Vector3d n = to_eigen(mesh.calc_face_normal(f));
                if (n.allFinite())
                    normal += n;
            }
        const Eigen::Vector3d mid =
            0.5 * (to_eigen(mesh.point(e.v0())) + to_eigen(mesh.point(e.v1())));
        const Eigen::Vector3d to_view = viewpoint - mid;
        const double lengths = normal.norm() * to_view.norm();
        const double facing = lengths > 0.0 ? std::max(0.0, normal.dot(to_view) / lengths) : 0.0;
        for (auto h : {e.h0(), e.h1()})
            weights[static_cast<std::size_t>(h.idx())] *= 1.0 + weight * facing;
    }
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
