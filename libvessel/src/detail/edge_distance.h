#pragma once

// Multi-source Dijkstra along a mesh's edges (3D edge lengths): the cut planner's distance to
// the cut tree (tree_distance.h, TreeDistance, on its CutGraph's arcs) and beside_length()
// (cut_metrics.cpp, on the mesh's halfedges) both grow this one field. mesh_neighbours() and
// graph_neighbours() give the neighbour walk over either (the winding meter's rings too).

#include "detail/quad_heap.h"
#include "vessel/cut/cut_graph.h"
#include "vessel/core/mesh.h"

#include <limits>
#include <vector>

namespace vessel::detail {

// Distance along edges to a growing set of seeds (0 on them) and the neighbour one step closer
// (`via`, -1 on a seed or unreached). Vertices settle by (distance, index) from a 4-ary heap
// with decrease-key whose arrays are kept between grows, so equal distances pick the same `via`
// whatever the neighbour order's source, as long as it visits neighbours in the same order.
class EdgeDistance
{
public:
    std::vector<double> dist;
    std::vector<int> via;

    //! Every vertex of a mesh with \p n_vertices unreached.
    void reset(std::size_t n_vertices)
    {
        dist.assign(n_vertices, std::numeric_limits<double>::infinity());
        via.assign(n_vertices, -1);
        slot_.assign(n_vertices, -1);
        heap_.clear();
        reached_.clear();
    }

    //! reset(\p n_vertices), but writing only the vertices reached since the last reset (a grow
    //! leaves every slot free): for a field grown over a small part of a large mesh.
    void clear(std::size_t n_vertices)
    {
        if (dist.size() != n_vertices || !heap_.empty())
        {
            reset(n_vertices);
            return;
        }
        for (int v : reached_)
        {
            dist[v] = std::numeric_limits<double>::infinity();
            via[v] = -1;
        }
        reached_.clear();
    }

    // Lowers the field from \p seeds (0). A vertex is a seed or is entered only if
    // \p enter(index) allows it, and only while its distance stays <= \p bound; shorter
    // distances already there are kept, so repeated grows build one field as seeds are added.
    // \p neighbours(v, visit) calls visit(w) for each neighbour w of vertex v (see
    // mesh_neighbours()).
    template <class Neighbours, class Enter>
    void grow(const Mesh& mesh, const std::vector<VertexHandle>& seeds, Neighbours neighbours,
              Enter enter, double bound = std::numeric_limits<double>::infinity())
    {
        grow_within(mesh, seeds, neighbours, enter, [bound](int) { return bound; });
    }

    // grow() with a bound per vertex: w is lowered to nd only while nd <= \p bound_at(w).
    template <class Neighbours, class Enter, class Bound>
    void grow_within(const Mesh& mesh, const std::vector<VertexHandle>& seeds,
                     Neighbours neighbours, Enter enter, Bound bound_at)
    {
        for (auto s : seeds)
            if (enter(s.idx()))
            {
                via[s.idx()] = -1;
                lower(s.idx(), 0.0);
            }
        while (!heap_.empty())
        {
            const auto [d, v] = heap_pop(heap_, slot_, Before{});
            const auto& p = mesh.point(VertexHandle(v));
            neighbours(v, [&](int w) {
                // d + length >= d >= dist[w] would fail the test below: skip the length.
                if (dist[w] <= d || !enter(w))
                    return;
                const double nd = d + (mesh.point(VertexHandle(w)) - p).norm();
                if (nd < dist[w] && nd <= bound_at(w))
                {
                    via[w] = v;
                    lower(w, nd);
                }
            });
        }
    }

private:
    // By (distance, index), as std::pair compares.
    struct Before
    {
        bool operator()(const HeapItem& a, const HeapItem& b) const { return a < b; }
    };

    void lower(int v, double d)
    {
        if (dist[v] == std::numeric_limits<double>::infinity())
            reached_.push_back(v);
        dist[v] = d;
        heap_lower(heap_, slot_, v, d, Before{});
    }

    std::vector<int> slot_;  // place in heap_, -1 if not there
    std::vector<HeapItem> heap_;
    std::vector<int> reached_;  // vertices with a finite distance since the last reset
};

// EdgeDistance's neighbours over the mesh's outgoing halfedges, in voh_range() order.
inline auto mesh_neighbours(const Mesh& mesh)
{
    return [&mesh](int v, auto&& visit) {
        for (auto h : mesh.voh_range(VertexHandle(v)))
            visit(h.to().idx());
    };
}

// The same neighbours in the same order over a CutGraph's arcs (which keep voh_range() order):
// visit(w) for each neighbour w of vertex v.
inline auto graph_neighbours(const CutGraph& graph)
{
    return [&graph](int v, auto&& visit) {
        const auto [first, last] = graph.arcs(v);
        for (const CutGraph::Arc* a = first; a != last; ++a)
            visit(a->to);
    };
}

}  // namespace vessel::detail
