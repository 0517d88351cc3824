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
    Eigen::MatrixX3d normals = Eigen::MatrixX3d::Zero(mesh.n_vertices(), 3);
    for (auto f : mesh.faces())
    {
        auto h = f.halfedge();
        const Eigen::Vector3d a = to_eigen(mesh.point(h.from()));
        const Eigen::Vector3d b = to_eigen(mesh.point(h.to()));
        const Eigen::Vector3d c = to_eigen(mesh.point(h.next().to()));
        const Eigen::Vector3d n = (b - a).cross(c - a);  // area-weighted
        for (auto v : f.vertices())
            normals.row(v.idx()) += n.transpose();
    }
    Eigen::MatrixX3d rate(mesh.n_vertices(), 3);
    for (Eigen::Index i = 0; i < rate.rows(); ++i)
    {
        const Eigen::Vector3d n = normals.row(i).normalized();
        const Eigen::Vector3d z = direction.row(i);
        rate.row(i) = std::abs(k_max[i]) * n.cross(z).normalized().transpose();
        if (!rate.row(i).allFinite())
            rate.row(i).setZero();
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

    CutPlan plan;
    for (std::size_t l = 1; l < loops.size(); ++l)
    {
        PathQuery query;
        query.winding_rate = winding_rate;
        query.tie_tolerance = options.tie_tolerance;
        query.sources = nearest_point
                            ? std::vector<VertexHandle>{nearest(mesh, loops[l].vertices,
                                                                options.viewpoint)}
                            : loops[l].vertices;
        query.is_target.assign(nv, 0);
        query.is_blocked.assign(nv, 0);
        if (l == 1)
        {
            if (nearest_point)
                query.is_target[nearest(mesh, loops[0].vertices, options.viewpoint).idx()] = 1;
            else
                for (auto v : loops[0].vertices)
                    query.is_target[v.idx()] = 1;
        }
        else
            // Interior cut vertices only: a cut ending on a loop would open that loop twice.
            for (std::size_t v = 0; v < nv; ++v)
                query.is_target[v] = path_of[v] >= 0 && loop_of[v] < 0;
        for (std::size_t v = 0; v < nv; ++v)
            query.is_blocked[v] = loop_of[v] >= 0 && loop_of[v] != static_cast<int>(l) &&
                                  !query.is_target[v];

        GraphPath found = shortest_path(mesh, weights, query);
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
            if (path_of[mesh.to_vertex_handle(h).idx()] < 0)
                path_of[mesh.to_vertex_handle(h).idx()] = index;
        plan.paths.push_back(std::move(cut));
    }
    return plan;
}

}  // namespace vessel
