#pragma once

// Multi-source Dijkstra along a mesh's edges (3D edge lengths), used by beside_length()
// (cut_metrics.cpp). The cut planner's distance to the cut tree (cut_plan.cpp, TreeDistance)
// computes the same field on its CutGraph's arcs with the 4-ary heap of detail/quad_heap.h
// and reused arrays, settling vertices in the same order; a change to one is a change to both.

#include "vessel/mesh.h"

#include <functional>
#include <limits>
#include <queue>
#include <utility>
#include <vector>

namespace vessel::detail {

// Lowers \p dist (one entry per vertex) from \p seeds, which get 0, and records in \p via the
// neighbour one step closer to a seed (-1 on a seed). A vertex is a seed or is entered only if
// \p enter(index) allows it, and only while its distance stays <= \p bound. Shorter distances
// already in \p dist are kept, so repeated calls grow one field as seeds are added.
template <class Enter>
void grow_edge_distance(const Mesh& mesh, const std::vector<VertexHandle>& seeds,
                        std::vector<double>& dist, std::vector<int>& via, Enter enter,
                        double bound = std::numeric_limits<double>::infinity())
{
    using Item = std::pair<double, int>;
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> heap;
    for (auto v : seeds)
        if (enter(v.idx()))
        {
            dist[v.idx()] = 0.0;
            via[v.idx()] = -1;
            heap.push({0.0, v.idx()});
        }
    while (!heap.empty())
    {
        const auto [d, v] = heap.top();
        heap.pop();
        if (d > dist[v])
            continue;
        for (auto h : mesh.voh_range(VertexHandle(v)))
        {
            const int w = h.to().idx();
            const double nd = d + mesh.calc_edge_length(h);
            if (nd <= bound && nd < dist[w] && enter(w))
            {
                dist[w] = nd;
                via[w] = v;
                heap.push({nd, w});
            }
        }
    }
}

}  // namespace vessel::detail
