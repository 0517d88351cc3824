#include "vessel/cut/winding_bound.h"

#include "detail/cost_to_tree.h"
#include "detail/path_query.h"
#include "detail/quad_heap.h"
#include "vessel/core/errors.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <queue>
#include <unordered_map>
#include <utility>
#include <vector>

namespace vessel {

void WindingBoundOptions::validate() const
{
    if (!(limit_deg > 0.0) || !(limit_deg < 180.0))
        throw InvalidInputError("WindingBoundOptions: limit_deg must lie in (0, 180)");
    if (bins < 1 || bins > 720)
        throw InvalidInputError("WindingBoundOptions: bins must lie in [1, 720]");
}

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

using Item = std::pair<double, int>;  // (key, index)
using MinHeap = std::priority_queue<Item, std::vector<Item>, std::greater<Item>>;

// The unconstrained cost from a vertex to the nearest target, over arcs into unblocked
// vertices only: Dijkstra from the targets over the reversed arcs (the arc u -> x is the
// opposite of the halfedge x -> u), on the cut graph's 4-ary heap. A lower bound of every
// constrained route's remaining cost (the search's A* heuristic). Settled on demand: a vertex's
// cost is final once Dijkstra pops it, and the search asks for the vertices near its route
// only, so the Dijkstra stops at the farthest of them instead of covering the whole mesh.
class CostToTargets
{
public:
    CostToTargets(const CutGraph& graph, const PathQuery& query)
        : graph_(graph), query_(query), any_blocked_(!query.is_blocked.empty()),
          cost_(graph.mesh().n_vertices(), kInfinity), slot_(graph.mesh().n_vertices(), -1),
          settled_(graph.mesh().n_vertices(), 0)
    {
        for (std::size_t v = 0; v < cost_.size(); ++v)
            if (query.is_target[v])
            {
                cost_[v] = 0.0;
                detail::heap_lower(heap_, slot_, static_cast<int>(v), 0.0,
                                   detail::nearer_target);
            }
    }

    //! The cost from \p v; infinite where no target is reached.
    double operator()(int v)
    {
        const auto blocked = [this](int u) { return any_blocked_ && query_.is_blocked[u]; };
        while (!settled_[static_cast<std::size_t>(v)] && !heap_.empty())
        {
            const int x = detail::settle_from_targets(graph_, cost_, slot_, heap_, blocked);
            settled_[static_cast<std::size_t>(x)] = 1;
        }
        return cost_[static_cast<std::size_t>(v)];
    }

private:
    const CutGraph& graph_;
    const PathQuery& query_;
    bool any_blocked_;
    std::vector<double> cost_;
    std::vector<int> slot_;
    std::vector<char> settled_;
    std::vector<detail::HeapItem> heap_;
};

}  // namespace

std::optional<GraphPath> winding_bounded_path(
    const CutGraph& graph, const PathQuery& query,
    const std::function<double(VertexHandle, VertexHandle, bool)>& turn,
    const WindingBoundOptions& options, const std::function<void(VertexHandle)>& settled,
    const std::vector<double>* cost_to_targets)
{
    options.validate();
    const Mesh& mesh = graph.mesh();
    const std::size_t nv = mesh.n_vertices();
    detail::check_path_query(mesh, query, "winding_bounded_path");
    if (cost_to_targets && cost_to_targets->size() != nv)
        throw InvalidInputError("winding_bounded_path: " +
                                std::to_string(cost_to_targets->size()) +
                                " costs to the targets for " + std::to_string(nv) +
                                " vertices; pass one per vertex, indexed by v.idx()");

    std::optional<CostToTargets> own;  // the bound, unless given
    if (!cost_to_targets)
        own.emplace(graph, query);
    const auto to_target = [&](int v) {
        return cost_to_targets ? (*cost_to_targets)[static_cast<std::size_t>(v)] : (*own)(v);
    };
    const bool any_blocked = !query.is_blocked.empty();
    const double limit = options.limit_deg * M_PI / 180.0;
    const double width = 2.0 * limit / options.bins;
    const auto bin_of = [&](double winding) {
        return std::min(options.bins - 1, static_cast<int>((winding + limit) / width));
    };

    // One label per (vertex, bin) reached: the cheapest route there so far.
    struct Label
    {
        double cost;
        double winding;
        int vertex;
        int last;      // the route's last vertex where `turn` gave an angle, -1 if none yet
        int parent;    // label it was reached from, -1 at a source
        int halfedge;  // entering halfedge, -1 at a source
        bool settled;
    };
    std::vector<Label> labels;
    // The label of each (vertex, bin), -1 = none yet: a block of `bins` slots per vertex the
    // search reaches, made at its first visit. Faster than a hash map once a search reaches a
    // fair part of the mesh (as it does where no route keeps the bound near the unconstrained
    // one), and no larger than the vertices reached.
    const auto bins = static_cast<std::size_t>(options.bins);
    std::vector<int> block_of(nv, -1);
    std::vector<int> label_of;
    const auto slot_of = [&](int v, int bin) -> int& {
        int& block = block_of[static_cast<std::size_t>(v)];
        if (block < 0)
        {
            block = static_cast<int>(label_of.size() / bins);
            label_of.resize(label_of.size() + bins, -1);
        }
        return label_of[static_cast<std::size_t>(block) * bins + static_cast<std::size_t>(bin)];
    };
    std::vector<char> is_source(nv, 0);
    MinHeap heap;  // (cost + lower bound to the targets, label)
    for (auto s : query.sources)
        if (!is_source[s.idx()] && std::isfinite(to_target(s.idx())))
        {
            is_source[s.idx()] = 1;
            slot_of(s.idx(), bin_of(0.0)) = static_cast<int>(labels.size());
            heap.push({to_target(s.idx()), static_cast<int>(labels.size())});
            const double first = turn(VertexHandle(), s, false);
            labels.push_back({0.0, 0.0, s.idx(), std::isnan(first) ? -1 : s.idx(), -1, -1, false});
        }

    // The turn onto an arc from its tail where the tail is the route's last measured vertex
    // depends on the arc alone, and a search settles a vertex in several bins of the winding
    // (about ten on Glenn split4): each is asked for once (per halfedge index).
    // Left uninitialized (read only where known): its pages are touched only where asked.
    const std::unique_ptr<double[]> own_turn(new double[mesh.n_halfedges()]);
    std::vector<char> own_known(mesh.n_halfedges(), 0);
    int found = -1;
    while (!heap.empty())
    {
        const auto [f, l] = heap.top();
        heap.pop();
        if (labels[l].settled || f > labels[l].cost + to_target(labels[l].vertex))
            continue;  // settled, or a stale key
        labels[l].settled = true;
        const int v = labels[l].vertex;
        if (query.is_target[v])
        {
            found = l;
            break;
        }
        if (settled)
            settled(VertexHandle(v));
        const double cost = labels[l].cost, winding = labels[l].winding;
        const int last_turned = labels[l].last;
        const auto [first, last] = graph.arcs(v);
        for (const CutGraph::Arc* a = first; a != last; ++a)
        {
            const int w = a->to;
            // A cut opens its loop at one vertex: it never comes back to a source.
            if (is_source[w] || (any_blocked && query.is_blocked[w]) ||
                !std::isfinite(to_target(w)))
                continue;
            double step;
            if (last_turned == v)
            {
                const auto h = static_cast<std::size_t>(a->halfedge);
                if (!own_known[h])
                {
                    own_turn[h] = turn(VertexHandle(v), VertexHandle(w), false);
                    own_known[h] = 1;
                }
                step = own_turn[h];
            }
            else
                step = turn(VertexHandle(last_turned), VertexHandle(w), true);
            const double turned = std::isnan(step) ? winding : winding + step;
            if (!(std::abs(turned) <= limit))
                continue;
            const int reached_last = std::isnan(step) ? last_turned : w;
            const double reached = cost + a->weight;
            int& slot = slot_of(w, bin_of(turned));
            if (slot < 0)
            {
                slot = static_cast<int>(labels.size());
                labels.push_back({reached, turned, w, reached_last, l, a->halfedge, false});
            }
            else
            {
                Label& old = labels[static_cast<std::size_t>(slot)];
                if (old.settled || !(reached < old.cost))
                    continue;
                old = {reached, turned, w, reached_last, l, a->halfedge, false};
            }
            heap.push({reached + to_target(w), slot});
        }
    }
    if (found < 0 || labels[found].parent < 0)
        return std::nullopt;  // no route, or a source that is a target (no path to take)

    std::vector<HalfedgeHandle> halfedges;
    for (int l = found; labels[l].parent >= 0; l = labels[l].parent)
        halfedges.push_back(HalfedgeHandle(labels[l].halfedge));
    std::reverse(halfedges.begin(), halfedges.end());
    // A route through one vertex twice (at two windings) loses the loop between the visits.
    std::unordered_map<int, std::size_t> position;  // vertex -> halfedges kept before it
    std::vector<HalfedgeHandle> simple;
    position[mesh.from_vertex_handle(halfedges.front()).idx()] = 0;
    for (auto h : halfedges)
    {
        const int to = mesh.to_vertex_handle(h).idx();
        const auto it = position.find(to);
        if (it != position.end())
        {
            for (std::size_t k = it->second; k < simple.size(); ++k)
                position.erase(mesh.to_vertex_handle(simple[k]).idx());
            simple.resize(it->second);
            position[to] = simple.size();
            continue;
        }
        simple.push_back(h);
        position[to] = simple.size();
    }
    GraphPath path = graph.path_of(std::move(simple));
    VertexHandle last, previous;
    for (std::size_t k = 0; k <= path.halfedges.size(); ++k)
    {
        const VertexHandle v = k == 0 ? mesh.from_vertex_handle(path.halfedges.front())
                                      : mesh.to_vertex_handle(path.halfedges[k - 1]);
        const double step = turn(last, v, previous != last);
        previous = v;
        if (!std::isnan(step))
        {
            path.winding_rad += step;
            last = v;
        }
    }
    return path;
}

}  // namespace vessel
