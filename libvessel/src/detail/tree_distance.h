#pragma once

// The cut planner's distance to the cut tree, shared by the streamline routes
// (route_streamline.cpp, route_aligned.cpp: where a later cut's trace stops) and
// CutJoin::Approach (join_approach.cpp: where a later cut is cut back), and the ring distance
// of the streamline routes' join rings and bands.

#include "detail/edge_distance.h"
#include "vessel/cut/cut_graph.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace vessel::detail {

// Breadth-first ring distance from \p seeds (0) out to \p max_rings edges into \p ring (-1 =
// farther), keeping smaller values already there; vertices \p skip(index) names are not
// entered. Each vertex whose value it lowers is appended to \p lowered, when given.
template <class Skip>
void grow_rings(const CutGraph& graph, const std::vector<VertexHandle>& seeds, int max_rings,
                Skip skip, std::vector<int>& ring, std::vector<int>* lowered = nullptr)
{
    std::vector<VertexHandle> front;
    const auto set = [&](int v, int r) {
        if (lowered && ring[v] < 0)
            lowered->push_back(v);
        ring[v] = r;
    };
    for (auto v : seeds)
        if (!skip(v.idx()))
        {
            if (ring[v.idx()] != 0)
                set(v.idx(), 0);
            front.push_back(v);
        }
    const auto neighbours = graph_neighbours(graph);
    for (int r = 1; r <= max_rings && !front.empty(); ++r)
    {
        std::vector<VertexHandle> next;
        for (auto v : front)
            neighbours(v.idx(), [&](int w) {
                if (!skip(w) && (ring[w] < 0 || ring[w] > r))
                {
                    set(w, r);
                    next.push_back(VertexHandle(w));
                }
            });
        front.swap(next);
    }
}

// A part of a path that reads the tree distance (cut_back(), StreamlineTracer::trace()): the
// box of its vertices and the largest read among them.
struct ReadZone
{
    Eigen::AlignedBox3d box;
    double read = 0.0;
};

// cut_back() and StreamlineTracer::trace() split their reading vertices into this many zones
// at most: a closer bound than their one box, for a few box distances per vertex visited.
constexpr std::size_t kReadZones = 8;

// \p count reading items, in order, split into at most kReadZones runs of consecutive items:
// a zone per run, its box grown by \p add(item, box) for each item and its read that of the
// run's first item, \p read_of(item).
template <class Add, class ReadOf>
std::vector<ReadZone> zones_along(std::size_t count, Add add, ReadOf read_of)
{
    const std::size_t n_zones = std::min(kReadZones, count);
    const std::size_t per_zone = (count + n_zones - 1) / n_zones;
    std::vector<ReadZone> zones;
    for (std::size_t k = 0; k < count; k += per_zone)
    {
        ReadZone zone;
        zone.read = read_of(k);
        for (std::size_t j = k; j < std::min(count, k + per_zone); ++j)
            add(j, zone.box);
        zones.push_back(zone);
    }
    return zones;
}

// Distance along edges to the cut tree (0 on it) and the next vertex toward it
// (EdgeDistance on the graph's arcs, which keep voh_range() order, with reused arrays),
// grown only near where a reader reads it (near_zones()); loop vertices (loop_of >= 0) are
// neither seeds nor passed through. The field is defined as the grows from each cut's vertices
// in turn (defer()), each lowering the distances it improves: the via of a vertex that two
// cuts reach at the same distance is the earlier cut's.
class TreeDistance
{
public:
    // Every vertex of a mesh with \p nv vertices off the tree.
    void reset(std::size_t nv);

    // Adds \p seeds to the tree (their grow runs at each near_zones()).
    void defer(const Mesh& mesh, const std::vector<VertexHandle>& seeds,
               const std::vector<int>& loop_of);

    // The field, exact (distance and via, as unbounded grows give them) at every vertex that
    // can lie on a shortest route from the tree to a point of a zone's box no longer than the
    // zone's read: all grows replayed into a scratch field in order, a vertex entered only while its
    // distance stays within its bound, the largest over the zones of
    // min(read, read + tolerance - straight distance to the zone's box) (\p tolerance for
    // rounding). Such a vertex's predecessors pass the same test (the straight distance to a
    // box drops by at most an edge's length), and the pops left are in the same (distance,
    // index) order, so they pick the same `via`; a vertex it does not reach lies farther than
    // every zone's read, or on no such route, and a value beyond a zone's read may be too high.
    // Valid until the next call.
    const EdgeDistance& near_zones(const CutGraph& graph, const std::vector<int>& loop_of,
                                   const std::vector<ReadZone>& zones, double tolerance);

    // The points of the tree's vertices (the seeds off the loops), deferred ones included.
    const std::vector<Eigen::Vector3d>& points() const { return points_; }

private:
    EdgeDistance scratch_;       // near_zones()
    std::vector<double> memo_;   // near_zones(): each vertex's bound
    std::vector<int> memoised_;  // the vertices with a bound in memo_
    std::size_t nv_ = 0;
    std::vector<std::vector<VertexHandle>> grown_;  // the seeds of each grow, in order
    std::vector<Eigen::Vector3d> points_;           // see points()
};

}  // namespace vessel::detail
