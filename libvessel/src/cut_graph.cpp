#include "vessel/cut_graph.h"

#include "vessel/errors.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace vessel {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

void check_query(const Mesh& mesh, const HalfedgeWeights& weights, const PathQuery& query)
{
    const std::size_t nv = mesh.n_vertices();
    if (weights.size() != mesh.n_halfedges())
        throw InvalidInputError("shortest_path: " + std::to_string(weights.size()) +
                                " weights for " + std::to_string(mesh.n_halfedges()) +
                                " halfedges; evaluate the cost on this mesh");
    if (query.sources.empty())
        throw InvalidInputError("shortest_path: no source vertices");
    if (query.is_target.size() != nv)
        throw InvalidInputError("shortest_path: is_target needs one flag per vertex");
    if (!query.is_blocked.empty() && query.is_blocked.size() != nv)
        throw InvalidInputError("shortest_path: is_blocked needs one flag per vertex (or none)");
    if (query.winding_rate.rows() != 0 && static_cast<std::size_t>(query.winding_rate.rows()) != nv)
        throw InvalidInputError("shortest_path: winding_rate needs one row per vertex (or none)");
    for (auto v : query.sources)
        if (!mesh.is_valid_handle(v))
            throw InvalidInputError("shortest_path: invalid source vertex handle");
}

// Angle around the vessel gained walking along h.
double winding_step(const Mesh& mesh, const Eigen::MatrixX3d& rate, HalfedgeHandle h)
{
    const auto from = mesh.from_vertex_handle(h);
    const Eigen::Vector3d d = to_eigen(mesh.point(mesh.to_vertex_handle(h)) - mesh.point(from));
    return rate.row(from.idx()).dot(d);
}

}  // namespace

GraphPath shortest_path(const Mesh& mesh, const HalfedgeWeights& weights, const PathQuery& query)
{
    check_query(mesh, weights, query);
    const std::size_t nv = mesh.n_vertices();
    const auto blocked = [&](int v) { return !query.is_blocked.empty() && query.is_blocked[v]; };

    std::vector<double> dist(nv, kInfinity);
    std::vector<int> parent(nv, -1);  // halfedge entering the vertex on the Dijkstra tree
    std::vector<char> settled(nv, 0), is_source(nv, 0);
    using Entry = std::pair<double, int>;
    std::vector<Entry> heap;
    const auto later = [](const Entry& a, const Entry& b) { return a.first > b.first; };
    for (auto s : query.sources)
    {
        dist[s.idx()] = 0.0;
        is_source[s.idx()] = 1;
        heap.emplace_back(0.0, s.idx());
    }
    std::make_heap(heap.begin(), heap.end(), later);

    int target = -1;
    while (!heap.empty())
    {
        std::pop_heap(heap.begin(), heap.end(), later);
        const auto [d, v] = heap.back();
        heap.pop_back();
        if (settled[v] || d > dist[v])
            continue;
        settled[v] = 1;
        if (query.is_target[v])
        {
            target = v;
            break;
        }
        for (auto h : mesh.voh_range(VertexHandle(v)))
        {
            const int w = mesh.to_vertex_handle(h).idx();
            if (settled[w] || blocked(w))
                continue;
            const double nd = d + weights[h.idx()];
            if (nd < dist[w])
            {
                dist[w] = nd;
                parent[w] = h.idx();
                heap.emplace_back(nd, w);
                std::push_heap(heap.begin(), heap.end(), later);
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
    const bool control = query.winding_rate.rows() != 0 && query.tie_tolerance > 0.0;
    double slack = 0.0;
    if (control)
    {
        const double mean = std::accumulate(weights.begin(), weights.end(), 0.0) /
                            static_cast<double>(std::max<std::size_t>(1, weights.size()));
        slack = query.tie_tolerance * mean;
    }
    GraphPath path;
    int v = target;
    while (!is_source[v])
    {
        int chosen = parent[v];
        if (control)
        {
            double best = std::abs(path.winding_rad + winding_step(mesh, query.winding_rate,
                                                                   HalfedgeHandle(chosen)));
            for (auto h : mesh.vih_range(VertexHandle(v)))
            {
                const int u = mesh.from_vertex_handle(h).idx();
                if (!settled[u] || query.is_target[u] || dist[u] >= dist[v] ||
                    dist[u] + weights[h.idx()] > dist[v] + slack)
                    continue;
                const double w = std::abs(path.winding_rad +
                                          winding_step(mesh, query.winding_rate, h));
                if (w < best - 1e-12)
                {
                    best = w;
                    chosen = h.idx();
                }
            }
        }
        const HalfedgeHandle h(chosen);
        path.halfedges.push_back(h);
        path.cost += weights[chosen];
        if (query.winding_rate.rows() != 0)
            path.winding_rad += winding_step(mesh, query.winding_rate, h);
        v = mesh.from_vertex_handle(h).idx();
    }
    std::reverse(path.halfedges.begin(), path.halfedges.end());
    return path;
}

}  // namespace vessel
