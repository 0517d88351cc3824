#include "vessel/cut/cut_graph.h"

#include "vessel/core/errors.h"
#include "detail/path_query.h"
#include "detail/quad_heap.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace vessel {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

void check_weights(const Mesh& mesh, const HalfedgeWeights& weights)
{
    if (weights.size() != mesh.n_halfedges())
        throw InvalidInputError("shortest_path: " + std::to_string(weights.size()) +
                                " weights for " + std::to_string(mesh.n_halfedges()) +
                                " halfedges; evaluate the cost on this mesh");
}

void check_query(const Mesh& mesh, const PathQuery& query, const Eigen::MatrixX3d& winding_rate)
{
    detail::check_path_query(mesh, query, "shortest_path");
    if (winding_rate.rows() != 0 &&
        static_cast<std::size_t>(winding_rate.rows()) != mesh.n_vertices())
        throw InvalidInputError("shortest_path: winding_rate needs one row per vertex (or none)");
    if (!std::isfinite(query.steer_weight))
        throw InvalidInputError("shortest_path: steer_weight must be finite");
}

// PathQuery::steer_rate: a steered arc keeps at least this fraction of its weight, so no arc
// is free and the search stays a Dijkstra on positive weights.
constexpr double kSteerFloor = 0.1;

constexpr char kSettled = 1;
constexpr char kSource = 2;

// Angle around the vessel gained walking along h.
double winding_step(const Mesh& mesh, const Eigen::MatrixX3d& rate, HalfedgeHandle h)
{
    const auto from = mesh.from_vertex_handle(h);
    const Eigen::Vector3d d = to_eigen(mesh.point(mesh.to_vertex_handle(h)) - mesh.point(from));
    return rate.row(from.idx()).dot(d);
}

}  // namespace

CutGraph::CutGraph(const Mesh& mesh, const HalfedgeWeights& weights)
    : mesh_(mesh), weights_(weights)
{
    check_weights(mesh, weights);
    const std::size_t nv = mesh.n_vertices();
    mean_weight_ = std::accumulate(weights.begin(), weights.end(), 0.0) /
                   static_cast<double>(std::max<std::size_t>(1, weights.size()));
    first_.assign(nv + 1, 0);
    arcs_.reserve(mesh.n_halfedges());
    // Outgoing halfedges clockwise from the vertex's halfedge, as voh_range() visits them (the
    // order decides between exactly equal routes), without the circulator's overhead. Arcs
    // along the boundary weigh infinity, so no search takes them: a seam is made of interior
    // edges (cut_along_edges()), and a route whose end is fixed on a loop (FarSideEndpoints)
    // would otherwise walk along the loop to it.
    for (std::size_t v = 0; v < nv; ++v)
    {
        const HalfedgeHandle start = mesh.halfedge_handle(VertexHandle(static_cast<int>(v)));
        if (start.is_valid())
        {
            HalfedgeHandle h = start;
            do
            {
                arcs_.push_back({mesh.to_vertex_handle(h).idx(), h.idx(),
                                 mesh.is_boundary(mesh.edge_handle(h)) ? kInfinity
                                                                       : weights[h.idx()]});
                h = mesh.cw_rotated_halfedge_handle(h);
            } while (h != start);
        }
        first_[v + 1] = static_cast<int>(arcs_.size());
    }
    dist_.assign(nv, kInfinity);
    parent_.assign(nv, -1);
    state_.assign(nv, 0);
    slot_.assign(nv, -1);
}

// The heap is 4-ary over vertices with their distance as key (detail::heap_lower); of two equal
// distances the one placed first stays above.
namespace {
struct Closer
{
    bool operator()(const detail::HeapItem& a, const detail::HeapItem& b) const
    {
        return a.first < b.first;
    }
};
}  // namespace

void CutGraph::relax(int v, double d, int parent)
{
    dist_[v] = d;
    parent_[v] = parent;
    detail::heap_lower(heap_, slot_, v, d, Closer{});
}

int CutGraph::pop_min()
{
    return detail::heap_pop(heap_, slot_, Closer{}).second;
}

GraphPath CutGraph::shortest_path(const PathQuery& query)
{
    return shortest_path(query, query.winding_rate);
}

GraphPath CutGraph::shortest_path(const PathQuery& query, const Eigen::MatrixX3d& winding_rate)
{
    check_query(mesh_, query, winding_rate);
    for (int v : touched_)
    {
        dist_[v] = kInfinity;
        parent_[v] = -1;
        state_[v] = 0;
        slot_[v] = -1;
    }
    touched_.clear();
    heap_.clear();
    const bool any_blocked = !query.is_blocked.empty();
    const bool steered = query.steer_rate && query.steer_weight != 0.0;
    // The weight of an arc from v to w of unsteered weight `weight` (PathQuery::steer_rate),
    // given v's rate.
    const auto steer = [&](const Eigen::Vector3d& rate, int v, int w, double weight) {
        const Eigen::Vector3d d = to_eigen(mesh_.point(VertexHandle(w)) -
                                           mesh_.point(VertexHandle(v)));
        return std::max(weight + query.steer_weight * rate.dot(d), kSteerFloor * weight);
    };
    for (auto s : query.sources)
        if (dist_[s.idx()] == kInfinity)
        {
            touched_.push_back(s.idx());
            state_[s.idx()] |= kSource;
            relax(s.idx(), 0.0, -1);
        }

    int target = -1;
    while (!heap_.empty())
    {
        const int v = pop_min();
        // The likely next vertex's arcs load while v's are relaxed.
        if (!heap_.empty())
            __builtin_prefetch(arcs_.data() + first_[heap_.front().second]);
        state_[v] |= kSettled;
        if (query.is_target[v])
        {
            target = v;
            break;
        }
        const double d = dist_[v];
        // v's steering rate, asked once per vertex (not per arc) and only when an arc needs it:
        // the rates' cache fills in the order they are asked (WindingMeter::angular_rate).
        Eigen::Vector3d rate;
        bool rate_known = false;
        const auto [first, last] = arcs(v);
        for (const Arc* a = first; a != last; ++a)
        {
            const int w = a->to;
            if ((state_[w] & kSettled) || (any_blocked && query.is_blocked[w]))
                continue;
            if (steered && !rate_known)
            {
                rate = query.steer_rate(v);
                rate_known = true;
            }
            const double nd = d + (steered ? steer(rate, v, w, a->weight) : a->weight);
            if (nd < dist_[w])
            {
                if (dist_[w] == kInfinity)
                {
                    touched_.push_back(w);
                    // w's arcs are read when it settles, soon if it is close: fetch them now
                    // (on large meshes the arc array is far beyond the caches).
                    __builtin_prefetch(arcs_.data() + first_[w]);
                }
                relax(w, nd, a->halfedge);
            }
        }
    }
    if (target < 0)
        throw InvalidInputError("shortest_path: no target reachable from the " +
                                std::to_string(query.sources.size()) +
                                " source vertices; the mesh may be disconnected between them");

    // Walk back from the target. Without a winding field this is the Dijkstra tree; with one,
    // every step may take any settled predecessor whose route is within the slack of optimal,
    // choosing the one that keeps the accumulated winding closest to zero. Each step strictly
    // lowers the distance, so the walk ends at a source.
    const bool control = winding_rate.rows() != 0 && query.tie_tolerance > 0.0;
    const double slack = control ? query.tie_tolerance * mean_weight_ : 0.0;
    GraphPath path;
    int v = target;
    while (!(state_[v] & kSource))
    {
        int chosen = parent_[v];
        if (control)
        {
            double best = std::abs(path.winding_rad + winding_step(mesh_, winding_rate,
                                                                   HalfedgeHandle(chosen)));
            for (auto h : mesh_.vih_range(VertexHandle(v)))
            {
                if (mesh_.is_boundary(mesh_.edge_handle(h)))  // as its arc's infinite weight
                    continue;
                const int u = mesh_.from_vertex_handle(h).idx();
                const double weight = steered
                                          ? steer(query.steer_rate(u), u, v, weights_[h.idx()])
                                          : weights_[h.idx()];
                if (!(state_[u] & kSettled) || query.is_target[u] || dist_[u] >= dist_[v] ||
                    dist_[u] + weight > dist_[v] + slack)
                    continue;
                const double w = std::abs(path.winding_rad +
                                          winding_step(mesh_, winding_rate, h));
                if (w < best - 1e-12)
                {
                    best = w;
                    chosen = h.idx();
                }
            }
        }
        const HalfedgeHandle h(chosen);
        path.halfedges.push_back(h);
        path.cost += weights_[chosen];
        if (winding_rate.rows() != 0)
            path.winding_rad += winding_step(mesh_, winding_rate, h);
        v = mesh_.from_vertex_handle(h).idx();
    }
    std::reverse(path.halfedges.begin(), path.halfedges.end());
    return path;
}

GraphPath CutGraph::path_of(std::vector<HalfedgeHandle> halfedges) const
{
    GraphPath path;
    for (auto h : halfedges)
        path.cost += weights_[h.idx()];
    path.halfedges = std::move(halfedges);
    return path;
}

GraphPath shortest_path(const Mesh& mesh, const HalfedgeWeights& weights, const PathQuery& query)
{
    return CutGraph(mesh, weights).shortest_path(query);
}

}  // namespace vessel
