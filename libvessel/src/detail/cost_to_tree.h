#pragma once

// The A* bound of the cut planner's bounded searches (winding_bound.h): the unconstrained cost
// from every vertex to the cut tree, kept up to date as the tree grows, and the Dijkstra step
// it shares with the search's own bound.

#include "detail/quad_heap.h"
#include "vessel/cut/cut_graph.h"

#include <limits>
#include <vector>

namespace vessel::detail {

// The heap order of a cost-to-targets Dijkstra: by cost alone.
inline bool nearer_target(const HeapItem& a, const HeapItem& b) { return a.first < b.first; }

// One step of a Dijkstra from the targets over the cut graph's arcs walked backwards (the arc
// u -> x from x: the weight of the halfedge opposite x -> u): pops the vertex x nearest the
// targets, whose \p cost is then final, and lowers the cost of every u with an arc into x that
// \p skip(u) does not exclude. Returns x. Both the search's own bound (winding_bound.cpp,
// settled as far as the search asks, blocked vertices skipped) and CostToTree settle by it.
template <class Skip>
int settle_from_targets(const CutGraph& graph, std::vector<double>& cost, std::vector<int>& slot,
                        std::vector<HeapItem>& heap, Skip skip)
{
    const int x = heap_pop(heap, slot, nearer_target).second;
    const auto [first, last] = graph.arcs(x);
    for (const CutGraph::Arc* a = first; a != last; ++a)
    {
        const int u = a->to;
        if (skip(u))
            continue;
        const double d = cost[x] + graph.weight(HalfedgeHandle(a->halfedge ^ 1));
        if (d < cost[u])
        {
            cost[u] = d;
            heap_lower(heap, slot, u, d, nearer_target);
        }
    }
    return x;
}

// The cost from every vertex to the nearest target over the cut graph's arcs (the arc u -> x
// walked backwards from x: the weight of the halfedge opposite x -> u), no vertex blocked: a
// lower bound of every route a query with those targets allows, and a consistent one (for
// every arc v -> w, cost(v) <= weight + cost(w)), as winding_bounded_path()'s A* needs. Each
// later cut of a plan only adds targets, so the field is grown, not made again: the new
// targets are seeds at 0 and a Dijkstra visits only the vertices they bring closer (a
// decrease-only update, exact: the same costs as a Dijkstra from all the targets at once).
// One field per plan instead of one Dijkstra per search, each of which settles the part of
// the mesh nearer the tree than the search's source (most of it on the large trees).
class CostToTree
{
public:
    explicit CostToTree(const CutGraph& graph) : graph_(graph) {}

    // The costs to the targets flagged in \p is_target (|V| flags). Targets added since the
    // last call are grown in; if one of the last call's targets is no longer one (the planner
    // moved from the inlet to the tree), the field is made again from scratch.
    const std::vector<double>& to(const std::vector<char>& is_target)
    {
        const std::size_t n = is_target.size();
        bool dropped = cost_.size() != n;
        for (std::size_t v = 0; v < n && !dropped; ++v)
            dropped = target_[v] && !is_target[v];
        if (dropped)
        {
            cost_.assign(n, std::numeric_limits<double>::infinity());
            target_.assign(n, 0);
            slot_.assign(n, -1);
            heap_.clear();
        }
        for (std::size_t v = 0; v < n; ++v)
            if (is_target[v] && !target_[v])
            {
                target_[v] = 1;
                if (cost_[v] > 0.0)
                {
                    cost_[v] = 0.0;
                    heap_lower(heap_, slot_, static_cast<int>(v), 0.0, nearer_target);
                }
            }
        while (!heap_.empty())
            settle_from_targets(graph_, cost_, slot_, heap_, [](int) { return false; });
        return cost_;
    }

private:
    const CutGraph& graph_;
    std::vector<double> cost_;
    std::vector<char> target_;
    std::vector<int> slot_;
    std::vector<HeapItem> heap_;
};

}  // namespace vessel::detail
