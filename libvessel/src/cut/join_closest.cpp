#include "vessel/cut/cut_join.h"

#include "vessel/core/errors.h"

#include <functional>
#include <limits>
#include <queue>
#include <string>
#include <utility>

namespace vessel {

namespace {

// The cut-tree vertices within (1 + slack) x the edge-path distance from \p loop to the nearest
// one, plus \p extra, found by a Dijkstra from the loop that neither enters other loops nor
// passes the tree.
std::vector<VertexHandle> near_tree_vertices(const Mesh& mesh, const std::vector<char>& on_tree,
                                             const std::vector<int>& loop_of, int loop,
                                             const std::vector<VertexHandle>& sources, double slack,
                                             double extra)
{
    using Item = std::pair<double, int>;
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> heap;
    std::vector<double> dist(mesh.n_vertices(), std::numeric_limits<double>::infinity());
    for (auto v : sources)
    {
        dist[v.idx()] = 0.0;
        heap.push({0.0, v.idx()});
    }
    std::vector<VertexHandle> near;
    double limit = std::numeric_limits<double>::infinity();
    while (!heap.empty())
    {
        const auto [d, v] = heap.top();
        heap.pop();
        if (d > dist[v])
            continue;
        if (d > limit)
            break;
        if (on_tree[v])
        {
            if (near.empty())
                limit = d * (1.0 + slack) + extra;
            near.push_back(VertexHandle(v));
            continue;
        }
        for (auto h : mesh.voh_range(VertexHandle(v)))
        {
            const int w = h.to().idx();
            const double nd = d + mesh.calc_edge_length(h);
            if ((loop_of[w] < 0 || loop_of[w] == loop) && nd < dist[w])
            {
                dist[w] = nd;
                heap.push({nd, w});
            }
        }
    }
    if (near.empty())
        throw InvalidInputError("plan_cuts: outlet " + std::to_string(loop) +
                                " cannot reach the cut tree; is the mesh one connected surface?");
    return near;
}

class ClosestJoiner : public CutJoiner
{
public:
    std::vector<VertexHandle> ends(const CutStep& step) override
    {
        const CutPlanContext& context = step.context();
        const std::size_t l = step.outlet();
        const BoundaryLoop& loop = (*context.loops)[l];
        return near_tree_vertices(context.mesh(), step.query().is_target, *context.loop_of,
                                  static_cast<int>(l), loop.vertices, context.options->join_slack,
                                  loop.arc_length);
    }
};

}  // namespace

std::unique_ptr<CutJoiner> ClosestJoin::start(const CutPlanContext&) const
{
    return std::make_unique<ClosestJoiner>();
}

}  // namespace vessel
