#include "detail/tree_distance.h"

namespace vessel::detail {

void TreeDistance::reset(std::size_t nv)
{
    nv_ = nv;
    grown_.clear();
    points_.clear();
}

void TreeDistance::defer(const Mesh& mesh, const std::vector<VertexHandle>& seeds,
                         const std::vector<int>& loop_of)
{
    grown_.push_back(seeds);
    for (auto s : seeds)
        if (loop_of[s.idx()] < 0)
            points_.push_back(to_eigen(mesh.point(s)));
}

const EdgeDistance& TreeDistance::near_zones(const CutGraph& graph, const std::vector<int>& loop_of,
                                             const std::vector<ReadZone>& zones, double tolerance)
{
    const Mesh& mesh = graph.mesh();
    scratch_.clear(nv_);
    // Each vertex's bound once (memo_, NaN = not yet), as it is asked for at every visit.
    if (memo_.size() != nv_)
        memo_.assign(nv_, std::numeric_limits<double>::quiet_NaN());
    for (int v : memoised_)
        memo_[v] = std::numeric_limits<double>::quiet_NaN();
    memoised_.clear();
    // A vertex farther from all the zones' box than the largest read is entered by none:
    // one box distance instead of one per zone for most of the tree's vertices.
    Eigen::AlignedBox3d all;
    double largest = -std::numeric_limits<double>::infinity();
    for (const auto& zone : zones)
    {
        all.extend(zone.box);
        largest = std::max(largest, zone.read);
    }
    const auto bound_at = [&](int v) {
        double& bound = memo_[v];
        if (std::isnan(bound))
        {
            const Eigen::Vector3d p = to_eigen(mesh.point(VertexHandle(v)));
            bound = -std::numeric_limits<double>::infinity();
            if (largest + tolerance - all.exteriorDistance(p) >= 0.0)
                for (const auto& zone : zones)
                    bound = std::max(bound, std::min(zone.read, zone.read + tolerance -
                                                                    zone.box.exteriorDistance(p)));
            memoised_.push_back(v);
        }
        return bound;
    };
    const auto enter = [&](int v) { return loop_of[v] < 0 && bound_at(v) >= 0.0; };
    for (const auto& seeds : grown_)
        scratch_.grow_within(mesh, seeds, graph_neighbours(graph), enter, bound_at);
    return scratch_;
}

}  // namespace vessel::detail
