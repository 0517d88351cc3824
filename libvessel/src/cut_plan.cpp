#include "vessel/cut_plan.h"

#include "vessel/errors.h"

#include <cmath>
#include <limits>

namespace vessel {

void CutPlanOptions::validate() const
{
    if (!(tie_tolerance >= 0.0) || !std::isfinite(tie_tolerance))
        throw InvalidInputError("CutPlanOptions: tie_tolerance must be finite and >= 0");
    if (!viewpoint.allFinite())
        throw InvalidInputError("CutPlanOptions: viewpoint must be finite");
}

std::vector<EdgeHandle> CutPlan::seam_edges(const Mesh& mesh) const
{
    std::vector<char> seen(mesh.n_edges(), 0);
    std::vector<EdgeHandle> edges;
    for (const auto* list : {&paths, &relief})
        for (const auto& path : *list)
            for (auto h : path.halfedges)
            {
                const auto e = mesh.edge_handle(h);
                if (!seen[e.idx()])
                {
                    seen[e.idx()] = 1;
                    edges.push_back(e);
                }
            }
    return edges;
}

Eigen::MatrixX3d winding_rate(const Mesh& mesh, const Eigen::MatrixX3d& direction,
                              const Eigen::VectorXd& k_max)
{
    const std::size_t nv = mesh.n_vertices();
    std::vector<Eigen::Vector3d> normals(nv, Eigen::Vector3d::Zero());
    for (std::size_t f = 0; f < mesh.n_faces(); ++f)
    {
        const HalfedgeHandle h = mesh.halfedge_handle(FaceHandle(static_cast<int>(f)));
        const HalfedgeHandle g = mesh.next_halfedge_handle(h);
        const int corner[3] = {mesh.from_vertex_handle(h).idx(), mesh.to_vertex_handle(h).idx(),
                               mesh.to_vertex_handle(g).idx()};
        const Eigen::Vector3d a = to_eigen(mesh.point(VertexHandle(corner[0])));
        const Eigen::Vector3d b = to_eigen(mesh.point(VertexHandle(corner[1])));
        const Eigen::Vector3d c = to_eigen(mesh.point(VertexHandle(corner[2])));
        const Eigen::Vector3d n = (b - a).cross(c - a);  // area-weighted
        for (int v : corner)
            normals[v] += n;
    }
    Eigen::MatrixX3d rate(nv, 3);
    for (std::size_t i = 0; i < nv; ++i)
    {
        const Eigen::Index r = static_cast<Eigen::Index>(i);
        const Eigen::Vector3d z(direction(r, 0), direction(r, 1), direction(r, 2));
        Eigen::Vector3d w = std::abs(k_max[r]) * normals[i].normalized().cross(z).normalized();
        if (!w.allFinite())
            w.setZero();
        rate(r, 0) = w.x();
        rate(r, 1) = w.y();
        rate(r, 2) = w.z();
    }
    return rate;
}

namespace {

VertexHandle nearest(const Mesh& mesh, const std::vector<VertexHandle>& candidates,
                     const Eigen::Vector3d& point)
{
    VertexHandle best;
    double best_d = std::numeric_limits<double>::infinity();
    for (auto v : candidates)
    {
        const double d = (to_eigen(mesh.point(v)) - point).squaredNorm();
        if (d < best_d)
        {
            best_d = d;
            best = v;
        }
    }
    return best;
}

}  // namespace

CutPlan plan_cuts(const Mesh& mesh, const std::vector<BoundaryLoop>& loops,
                  const HalfedgeWeights& weights, const Eigen::MatrixX3d& winding_rate,
                  const CutPlanOptions& options)
{
    options.validate();
    CutGraph graph(mesh, weights);
    return plan_cuts(graph, loops, winding_rate, options);
}

CutPlan plan_cuts(CutGraph& graph, const std::vector<BoundaryLoop>& loops,
                  const Eigen::MatrixX3d& winding_rate, const CutPlanOptions& options)
{
    options.validate();
    const Mesh& mesh = graph.mesh();
    if (loops.size() < 2)
        throw InvalidInputError("plan_cuts: " + std::to_string(loops.size()) +
                                " boundary loop(s); a vessel tree needs an inlet and an outlet");
    const std::size_t nv = mesh.n_vertices();
    const bool nearest_point = options.endpoints == EndpointPolicy::NearestToPoint;

    // path_of[v]: first cut through v (-1 if none); loop_of[v]: boundary loop of v (-1 if none).
    std::vector<int> path_of(nv, -1), loop_of(nv, -1);
    for (std::size_t l = 0; l < loops.size(); ++l)
        for (auto v : loops[l].vertices)
            loop_of[v.idx()] = static_cast<int>(l);

    // One graph and one query for all outlets; the flags change only on loops and new cuts.
    // Query l: targets are the inlet (l = 1) or the interior vertices of earlier cuts (l > 1);
    // blocked are the vertices of every loop but l that are not targets.
    PathQuery query;
    query.winding_rate = winding_rate;
    query.tie_tolerance = options.tie_tolerance;
    query.is_target.assign(nv, 0);
    query.is_blocked.assign(nv, 0);
    const auto set_blocked = [&](std::size_t l, char value) {
        for (auto v : loops[l].vertices)
            query.is_blocked[v.idx()] = value;
    };
    for (std::size_t l = 0; l < loops.size(); ++l)
        set_blocked(l, 1);
    const std::vector<VertexHandle> inlet_targets =
        nearest_point ? std::vector<VertexHandle>{nearest(mesh, loops[0].vertices,
                                                          options.viewpoint)}
                      : loops[0].vertices;
    for (auto v : inlet_targets)
    {
        query.is_target[v.idx()] = 1;
        query.is_blocked[v.idx()] = 0;
    }

    CutPlan plan;
    for (std::size_t l = 1; l < loops.size(); ++l)
    {
        if (l == 2)
        {
            // Interior cut vertices only: a cut ending on a loop would open that loop twice.
            for (auto v : inlet_targets)
                query.is_target[v.idx()] = 0;
            set_blocked(0, 1);
            for (auto h : plan.paths.front().halfedges)
                for (auto v : {mesh.from_vertex_handle(h), mesh.to_vertex_handle(h)})
                    query.is_target[v.idx()] = loop_of[v.idx()] < 0;
        }
        if (l >= 2)
            set_blocked(l - 1, 1);
        set_blocked(l, 0);
        query.sources = nearest_point
                            ? std::vector<VertexHandle>{nearest(mesh, loops[l].vertices,
                                                                options.viewpoint)}
                            : loops[l].vertices;

        GraphPath found = graph.shortest_path(query);
        CutPath cut;
        cut.outlet = static_cast<int>(l);
        cut.halfedges = std::move(found.halfedges);
        cut.cost = found.cost;
        cut.winding_deg = found.winding_rad * 180.0 / M_PI;
        cut.start = mesh.from_vertex_handle(cut.halfedges.front());
        cut.end = mesh.to_vertex_handle(cut.halfedges.back());
        cut.parent = l == 1 ? -1 : path_of[cut.end.idx()];
        const int index = static_cast<int>(plan.paths.size());
        path_of[cut.start.idx()] = index;
        for (auto h : cut.halfedges)
        {
            const int w = mesh.to_vertex_handle(h).idx();
            if (path_of[w] < 0)
                path_of[w] = index;
            if (l >= 2 && loop_of[w] < 0)
                query.is_target[w] = 1;  // later outlets may end on this cut
        }
        if (l >= 2 && loop_of[cut.start.idx()] < 0)
            query.is_target[cut.start.idx()] = 1;
        plan.paths.push_back(std::move(cut));
    }
    return plan;
}

}  // namespace vessel
