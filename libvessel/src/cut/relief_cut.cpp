#include "vessel/cut/relief_cut.h"

#include "vessel/cut/cut_cost.h"
#include "vessel/core/errors.h"
#include "vessel/quality/metrics.h"
#include "vessel/core/properties.h"
#include "detail/uv_rows.h"

#include <cmath>
#include <limits>

namespace vessel {

void ReliefCutOptions::validate() const
{
    if (!(target_mean_abs_log_area >= 0.0) || !std::isfinite(target_mean_abs_log_area))
        throw InvalidInputError("ReliefCutOptions: target_mean_abs_log_area must be finite and "
                                ">= 0, got " + std::to_string(target_mean_abs_log_area));
    if (max_cuts < 0)
        throw InvalidInputError("ReliefCutOptions: max_cuts must be >= 0 (0 = no relief cuts)");
    if (smoothing_passes < 0)
        throw InvalidInputError("ReliefCutOptions: smoothing_passes must be >= 0");
    if (min_rings < 1)
        throw InvalidInputError("ReliefCutOptions: min_rings must be >= 1");
}

Eigen::VectorXd vertex_log_area_ratio(const Mesh& uncut, const Mesh& cut,
                                      const Eigen::MatrixX2d& uv, int smoothing_passes)
{
    detail::require_uv_rows(cut, uv, "vertex_log_area_ratio");
    OpenMesh::VPropHandleT<int> origin_handle;
    if (!cut.get_property_handle(origin_handle, prop::origin))
        throw InvalidInputError(std::string("vertex_log_area_ratio: the cut mesh has no ") +
                                prop::origin + " property (pass the mesh cut_along_edges() made)");
    const Eigen::Index n = static_cast<Eigen::Index>(uncut.n_vertices());
    Eigen::VectorXd sum = Eigen::VectorXd::Zero(n), weight = Eigen::VectorXd::Zero(n);
    for (auto f : cut.faces())
    {
        const double a3 = cut.calc_face_area(f);
        const double a2 = signed_uv_area(cut, uv, f);
        if (!(a3 > 0.0) || !(a2 > 0.0))
            continue;
        const double value = std::log(a2 / a3);
        for (auto v : f.vertices())
        {
            const int o = cut.property(origin_handle, v);
            if (o < 0 || o >= n)
                throw InvalidInputError("vertex_log_area_ratio: the cut mesh's origin ids do not "
                                        "index the uncut mesh (pass the mesh before the cut)");
            sum[o] += a3 * value;
            weight[o] += a3;
        }
    }
    Eigen::VectorXd value = (weight.array() > 0.0).select(sum.cwiseQuotient(weight), 0.0);
    for (int pass = 0; pass < smoothing_passes; ++pass)
    {
        Eigen::VectorXd next = value;
        for (auto v : uncut.vertices())
        {
            double total = value[v.idx()];
            int count = 1;
            for (auto w : v.vertices())
            {
                total += value[w.idx()];
                ++count;
            }
            next[v.idx()] = total / count;
        }
        value.swap(next);
    }
    return value;
}

std::optional<CutPath> plan_relief_cut(const Mesh& uncut, const std::vector<BoundaryLoop>& loops,
                                       const CutPlan& plan, const Eigen::VectorXd& log_area,
                                       int min_rings)
{
    const std::size_t nv = uncut.n_vertices();
    if (log_area.size() != static_cast<Eigen::Index>(nv))
        throw InvalidInputError("plan_relief_cut: log_area has " +
                                std::to_string(log_area.size()) + " values for " +
                                std::to_string(nv) + " vertices");
    // path_of[v]: the cut through v; -1: none, -2: a boundary loop, -3: a relief cut. A slit
    // ends on a cut's interior (a loop opened twice would no longer be one strip end).
    constexpr int kNone = -1, kLoop = -2, kRelief = -3;
    std::vector<int> path_of(nv, kNone);
    for (const auto& loop : loops)
        for (auto v : loop.vertices)
            path_of[v.idx()] = kLoop;
    auto mark = [&](const CutPath& path, int index) {
        for (auto v : {path.start, path.end})
            if (path_of[v.idx()] == kNone)
                path_of[v.idx()] = index;
        for (auto h : path.halfedges)
            if (path_of[uncut.to_vertex_handle(h).idx()] == kNone)
                path_of[uncut.to_vertex_handle(h).idx()] = index;
    };
    for (std::size_t k = 0; k < plan.paths.size(); ++k)
        mark(plan.paths[k], static_cast<int>(k));
    for (const auto& path : plan.relief)
        mark(path, kRelief);

    // Rings from the seam and the loops (breadth-first): a tip right beside the seam would only
    // nick it.
    std::vector<int> rings(nv, -1);
    std::vector<VertexHandle> front;
    for (auto v : uncut.vertices())
        if (path_of[v.idx()] != kNone)
        {
            rings[v.idx()] = 0;
            front.push_back(v);
        }
    for (std::size_t head = 0; head < front.size(); ++head)
        for (auto w : uncut.vv_range(front[head]))
            if (rings[w.idx()] < 0)
            {
                rings[w.idx()] = rings[front[head].idx()] + 1;
                front.push_back(w);
            }
    VertexHandle tip;
    double lowest = std::numeric_limits<double>::infinity();
    for (auto v : uncut.vertices())
        if (rings[v.idx()] >= min_rings && log_area[v.idx()] < lowest)
        {
            lowest = log_area[v.idx()];
            tip = v;
        }
    if (!tip.is_valid())
        return std::nullopt;

    PathQuery query;
    query.sources = {tip};
    query.is_target.assign(nv, 0);
    query.is_blocked.assign(nv, 0);
    for (std::size_t v = 0; v < nv; ++v)
    {
        query.is_target[v] = path_of[v] >= 0 || path_of[v] == kRelief;
        query.is_blocked[v] = path_of[v] == kLoop;
    }
    const HalfedgeWeights lengths = evaluate_cost(uncut, LengthCost{});
    GraphPath found = shortest_path(uncut, lengths, query);

    CutPath relief;
    relief.halfedges = std::move(found.halfedges);
    relief.cost = found.cost;
    relief.start = tip;
    relief.end = uncut.to_vertex_handle(relief.halfedges.back());
    relief.parent = std::max(path_of[relief.end.idx()], -1);  // -1: on a relief cut
    return relief;
}

}  // namespace vessel
