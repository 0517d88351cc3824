#pragma once

// The A* bound of the cut planner's bounded searches (winding_bound.h): the unconstrained cost
// from every vertex to the cut tree, kept up to date as the tree grows.

#include "detail/quad_heap.h"
#include "vessel/cut/cut_graph.h"

#include <limits>
#include <vector>

namespace vessel::detail {

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
                    heap_lower(heap_, slot_, static_cast<int>(v), 0.0, closer);
                }
            }
        while (!heap_.empty())
        {
            const int x = heap_pop(heap_, slot_, closer).second;
            const auto [first, last] = graph_.arcs(x);
            for (const CutGraph::Arc* a = first; a != last; ++a)
            {
                const double d = cost_[x] + graph_.weight(HalfedgeHandle(a->halfedge ^ 1));
                if (d < cost_[a->to])
                {
                    cost_[a->to] = d;
                    heap_lower(heap_, slot_, a->to, d, closer);
                }
            }
        }
        return cost_;
    }

private:
    static bool closer(const HeapItem& a, const HeapItem& b) { return a.first < b.first; }

    const CutGraph& graph_;
    std::vector<double> cost_;
    std::vector<char> target_;
    std::vector<int> slot_;
    std::vector<HeapItem> heap_;
};

}  // namespace vessel::detail
