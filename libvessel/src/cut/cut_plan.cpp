#include "vessel/cut/cut_plan.h"

#include "vessel/core/errors.h"
#include "vessel/cut/cut_join.h"
#include "vessel/cut/cut_route.h"
#include "vessel/cut/cut_winding.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <memory>
#include <optional>
#include <string>
#include <utility>

namespace vessel {

void CutPlanOptions::validate() const
{
    if (!(tie_tolerance >= 0.0) || !std::isfinite(tie_tolerance))
        throw InvalidInputError("CutPlanOptions: tie_tolerance must be finite and >= 0");
    if (band_rings < 0)
        throw InvalidInputError("CutPlanOptions: band_rings must be >= 0");
    if (!(join_slack >= 0.0) || !std::isfinite(join_slack))
        throw InvalidInputError("CutPlanOptions: join_slack must be finite and >= 0");
    if (!(join_reach >= 0.0) || !std::isfinite(join_reach))
        throw InvalidInputError("CutPlanOptions: join_reach must be finite and >= 0");
    if (!(join_excess >= 0.0) || !std::isfinite(join_excess))
        throw InvalidInputError("CutPlanOptions: join_excess must be finite and >= 0");
    if (!(join_held_excess >= 0.0) || !std::isfinite(join_held_excess))
        throw InvalidInputError("CutPlanOptions: join_held_excess must be finite and >= 0");
    if (join_rings < 0)
        throw InvalidInputError("CutPlanOptions: join_rings must be >= 0");
    if (!(aligned_min_gain >= 0.0) || !std::isfinite(aligned_min_gain))
        throw InvalidInputError("CutPlanOptions: aligned_min_gain must be finite and >= 0");
    if (!(winding_min_gain_deg >= 0.0) || !std::isfinite(winding_min_gain_deg))
        throw InvalidInputError("CutPlanOptions: winding_min_gain_deg must be finite and >= 0");
    if (!(winding_max_alignment_loss >= 0.0) || !std::isfinite(winding_max_alignment_loss))
        throw InvalidInputError(
            "CutPlanOptions: winding_max_alignment_loss must be finite and >= 0");
    if (!(winding_target_deg >= 0.0) || !std::isfinite(winding_target_deg))
        throw InvalidInputError("CutPlanOptions: winding_target_deg must be finite and >= 0");
    if (!(winding_limit_deg >= 0.0) || !std::isfinite(winding_limit_deg))
        throw InvalidInputError("CutPlanOptions: winding_limit_deg must be finite and >= 0");
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

// The planner's CutStep: the step's query and plan are plan_cuts()' own; cheapest() narrows
// the targets to the joiner's ends for the search only.
class PlanStep final : public CutStep
{
public:
    PlanStep(const CutPlanContext& context, PathQuery& query, const CutPlan& plan,
             CutJoiner& joiner, const CutJoinPolicy& join)
        : context_(context), query_(query), plan_(plan), joiner_(joiner), join_(join)
    {}

    void begin(std::size_t outlet)
    {
        outlet_ = outlet;
        cheapest_.reset();
    }

    const CutPlanContext& context() const override { return context_; }
    std::size_t outlet() const override { return outlet_; }
    const PathQuery& query() const override { return query_; }
    const CutPlan& plan() const override { return plan_; }
    bool join_narrows_ends() const override { return join_.narrows_ends(); }

    const GraphPath& cheapest() override
    {
        if (cheapest_)
            return *cheapest_;
        CutGraph& graph = *context_.graph;
        const Eigen::MatrixX3d& winding_rate = *context_.winding_rate;
        if (first())
            return cheapest_.emplace(graph.shortest_path(query_, winding_rate));
        const std::vector<VertexHandle> ends = joiner_.ends(*this);
        if (ends.empty())
            return cheapest_.emplace(
                joiner_.finish(*this, graph.shortest_path(query_, winding_rate)));
        // The tree vertices not allowed as ends are blocked, or the path could cross the tree
        // there (then the cut mesh is no disk); restored after the search.
        const std::size_t nv = query_.is_target.size();
        std::vector<VertexHandle> tree;
        for (std::size_t v = 0; v < nv; ++v)
            if (query_.is_target[v])
                tree.push_back(VertexHandle(static_cast<int>(v)));
        for (auto v : ends)
            if (!v.is_valid() || static_cast<std::size_t>(v.idx()) >= nv ||
                !query_.is_target[v.idx()])
                throw InvalidInputError("plan_cuts: the join policy '" + join_.name() +
                                        "' allowed vertex " + std::to_string(v.idx()) +
                                        ", which is not on the cut tree; it must return "
                                        "targets of CutStep::query()");
        for (auto v : tree)
        {
            query_.is_target[v.idx()] = 0;
            query_.is_blocked[v.idx()] = 1;
        }
        for (auto v : ends)
        {
            query_.is_target[v.idx()] = 1;
            query_.is_blocked[v.idx()] = 0;
        }
        std::optional<GraphPath> found;
        std::exception_ptr failed;
        try
        {
            found = graph.shortest_path(query_, winding_rate);
        }
        catch (...)
        {
            failed = std::current_exception();
        }
        query_.is_target.assign(nv, 0);
        for (auto v : tree)
        {
            query_.is_target[v.idx()] = 1;
            query_.is_blocked[v.idx()] = 0;
        }
        if (failed)
            std::rethrow_exception(failed);
        return cheapest_.emplace(joiner_.finish(*this, std::move(*found)));
    }

    GraphPath join(GraphPath path) override
    {
        return first() ? path : joiner_.finish(*this, std::move(path));
    }

    GraphPath join_held(GraphPath path, const PathTest& keeps) override
    {
        return first() ? path : joiner_.finish_held(*this, std::move(path), keeps);
    }

private:
    const CutPlanContext& context_;
    PathQuery& query_;
    const CutPlan& plan_;
    CutJoiner& joiner_;
    const CutJoinPolicy& join_;
    std::size_t outlet_ = 1;
    std::optional<GraphPath> cheapest_;
};

// \throw InvalidInputError unless \p path is a chain of halfedges from one of \p query's
// sources to one of its targets (what a route must return).
void check_route(const Mesh& mesh, const PathQuery& query, const GraphPath& path,
                 const std::string& policy, std::size_t outlet)
{
    const std::string who = "plan_cuts: the cut route '" + policy + "' returned, for outlet " +
                            std::to_string(outlet) + ", ";
    if (path.halfedges.empty())
        throw InvalidInputError(who + "an empty path; a cut needs at least one edge");
    const std::size_t nh = mesh.n_halfedges();
    for (std::size_t i = 0; i < path.halfedges.size(); ++i)
    {
        const HalfedgeHandle h = path.halfedges[i];
        if (!h.is_valid() || static_cast<std::size_t>(h.idx()) >= nh)
            throw InvalidInputError(who + "halfedge " + std::to_string(h.idx()) +
                                    ", which is not in the mesh");
        if (i > 0 && mesh.from_vertex_handle(h) != mesh.to_vertex_handle(path.halfedges[i - 1]))
            throw InvalidInputError(who + "a broken chain at halfedge " + std::to_string(i) +
                                    "; each halfedge must start where the one before ends");
    }
    const VertexHandle start = mesh.from_vertex_handle(path.halfedges.front());
    if (std::find(query.sources.begin(), query.sources.end(), start) == query.sources.end())
        throw InvalidInputError(who + "a path from vertex " + std::to_string(start.idx()) +
                                ", which is not one of CutStep::query()'s sources");
    const VertexHandle end = mesh.to_vertex_handle(path.halfedges.back());
    if (!query.is_target[end.idx()])
        throw InvalidInputError(who + "a path to vertex " + std::to_string(end.idx()) +
                                ", which is not one of CutStep::query()'s targets");
}

}  // namespace

CutPlan plan_cuts(const Mesh& mesh, const std::vector<BoundaryLoop>& loops,
                  const HalfedgeWeights& weights, const Eigen::MatrixX3d& winding_rate,
                  const CutPlanOptions& options, const Eigen::MatrixX3d& stream_field,
                  const Eigen::VectorXd& longitudinal, const Eigen::MatrixX3d& direction)
{
    options.validate();
    CutGraph graph(mesh, weights);
    return plan_cuts(graph, loops, winding_rate, options, stream_field, longitudinal, direction);
}

namespace {

// An endpoint policy with the inlet's end left to the cut (its cheapest point) and the
// outlets' as \p fixed gives them.
class InletFreeEndpoints : public EndpointPolicy
{
public:
    explicit InletFreeEndpoints(std::shared_ptr<const EndpointPolicy> fixed)
        : fixed_(std::move(fixed))
    {
    }
    std::string name() const override { return fixed_->name() + ", inlet free"; }
    std::vector<VertexHandle> allowed(const Mesh& mesh, const BoundaryLoop& loop,
                                      std::size_t loop_index) const override
    {
        return loop_index == 0 ? loop.vertices : fixed_->allowed(mesh, loop, loop_index);
    }

private:
    std::shared_ptr<const EndpointPolicy> fixed_;
};

// The largest winding or span (degrees) of \p plan's cuts by \p meter.
double widest_turn(const WindingMeter& meter, const CutPlan& plan)
{
    double widest = 0.0;
    for (const CutPath& path : plan.paths)
    {
        const PathWinding w = meter.measure(path);
        widest = std::max({widest, std::abs(w.winding_deg), w.span_deg});
    }
    return widest;
}

// plan_cuts() with the policy's ends as given.
CutPlan plan_with_ends(CutGraph& graph, const std::vector<BoundaryLoop>& loops,
                       const Eigen::MatrixX3d& winding_rate, const CutPlanOptions& options,
                       const Eigen::MatrixX3d& stream_field, const Eigen::VectorXd& longitudinal,
                       const Eigen::MatrixX3d& direction);

}  // namespace

CutPlan plan_cuts(CutGraph& graph, const std::vector<BoundaryLoop>& loops,
                  const Eigen::MatrixX3d& winding_rate, const CutPlanOptions& options,
                  const Eigen::MatrixX3d& stream_field, const Eigen::VectorXd& longitudinal,
                  const Eigen::MatrixX3d& direction)
{
    CutPlan plan =
        plan_with_ends(graph, loops, winding_rate, options, stream_field, longitudinal, direction);
    // An endpoint policy that fixes the first cut's end on the inlet fixes that cut's side at
    // both ends; where the vessel turns round the view between them (a far side that moves
    // round the tube) no natural route joins them, as the bound chooses among routes between
    // the ends it is given. The plan is then made again with the inlet's end free.
    const Mesh& mesh = graph.mesh();
    if (!options.endpoints || !options.natural_cuts ||
        longitudinal.size() != static_cast<Eigen::Index>(mesh.n_vertices()) ||
        options.endpoints->allowed(mesh, loops[0], 0).size() != 1)
        return plan;
    const WindingMeter meter(mesh, longitudinal);
    const double widest = widest_turn(meter, plan);
    if (!(widest > options.winding_limit_deg))
        return plan;
    CutPlanOptions freed = options;
    freed.endpoints = std::make_shared<InletFreeEndpoints>(options.endpoints);
    CutPlan again =
        plan_with_ends(graph, loops, winding_rate, freed, stream_field, longitudinal, direction);
    return widest_turn(meter, again) < widest ? again : plan;
}

namespace {

CutPlan plan_with_ends(CutGraph& graph, const std::vector<BoundaryLoop>& loops,
                       const Eigen::MatrixX3d& winding_rate, const CutPlanOptions& options,
                       const Eigen::MatrixX3d& stream_field, const Eigen::VectorXd& longitudinal,
                       const Eigen::MatrixX3d& direction)
{
    options.validate();
    const Mesh& mesh = graph.mesh();
    if (loops.size() < 2)
        throw InvalidInputError("plan_cuts: " + std::to_string(loops.size()) +
                                " boundary loop(s); a vessel tree needs an inlet and an outlet");
    const std::size_t nv = mesh.n_vertices();
    const std::shared_ptr<const CutRoutePolicy> route =
        options.router ? options.router : route_policy(options.route);
    const std::shared_ptr<const CutJoinPolicy> join =
        options.joiner ? options.joiner : join_policy(options.join);
    if (route->needs_stream_field() && static_cast<std::size_t>(stream_field.rows()) != nv)
        throw InvalidInputError("plan_cuts: the cut route '" + route->name() +
                                "' needs a stream field with one row per vertex (" +
                                std::to_string(nv) + "), got " +
                                std::to_string(stream_field.rows()));
    if (direction.rows() != 0 && static_cast<std::size_t>(direction.rows()) != nv)
        throw InvalidInputError("plan_cuts: " + std::to_string(direction.rows()) +
                                " direction rows for " + std::to_string(nv) +
                                " vertices; pass the vessel direction z of the same mesh, or none");

    // path_of[v]: first cut through v (-1 if none); loop_of[v]: boundary loop of v (-1 if none).
    std::vector<int> path_of(nv, -1), loop_of(nv, -1);
    for (std::size_t l = 0; l < loops.size(); ++l)
        for (auto v : loops[l].vertices)
            loop_of[v.idx()] = static_cast<int>(l);
    // Where each loop's cut may start (outlets) or end (the inlet).
    const ImaginaryNodeEndpoints whole_loop;
    const EndpointPolicy& endpoints = options.endpoints ? *options.endpoints : whole_loop;
    const auto ends_on = [&](std::size_t l) {
        std::vector<VertexHandle> ends = endpoints.allowed(mesh, loops[l], l);
        if (ends.empty())
            throw InvalidInputError("plan_cuts: the endpoint policy '" + endpoints.name() +
                                    "' allows no vertex of loop " + std::to_string(l) +
                                    "; it must return at least one of the loop's vertices");
        for (auto v : ends)
            if (!v.is_valid() || static_cast<std::size_t>(v.idx()) >= nv ||
                loop_of[v.idx()] != static_cast<int>(l))
                throw InvalidInputError("plan_cuts: the endpoint policy '" + endpoints.name() +
                                        "' returned vertex " + std::to_string(v.idx()) +
                                        ", which is not on loop " + std::to_string(l) +
                                        "; it must return vertices of the loop it is given");
        return ends;
    };

    // One graph and one query for all outlets; the flags change only on loops and new cuts.
    // Query l: targets are the inlet (l = 1) or the interior vertices of earlier cuts (l > 1);
    // blocked are the loops' vertices but the sources (on loop l) and the targets.
    PathQuery query;
    // The |V| x 3 winding field is passed to each search by reference, not copied in.
    query.tie_tolerance = options.tie_tolerance;
    query.is_target.assign(nv, 0);
    query.is_blocked.assign(nv, 0);
    const auto set_blocked = [&](std::size_t l, char value) {
        for (auto v : loops[l].vertices)
            query.is_blocked[v.idx()] = value;
    };
    for (std::size_t l = 0; l < loops.size(); ++l)
        set_blocked(l, 1);
    const std::vector<VertexHandle> inlet_targets = ends_on(0);
    for (auto v : inlet_targets)
    {
        query.is_target[v.idx()] = 1;
        query.is_blocked[v.idx()] = 0;
    }

    const CutPlanContext context{&graph,        &loops,        &loop_of,      &options,
                                 &winding_rate, &stream_field, &longitudinal, &direction};
    const std::unique_ptr<CutRouter> router = route->start(context);
    const std::unique_ptr<CutJoiner> joiner = join->start(context);
    CutPlan plan;
    PlanStep step(context, query, plan, *joiner, *join);
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
        // The cut leaves its loop at one of the policy's vertices and passes no other vertex of
        // the loop (it would open the loop twice: no disk); with the whole loop allowed the
        // cheapest path never comes back to it anyway.
        query.sources = ends_on(l);
        for (auto v : query.sources)
            query.is_blocked[v.idx()] = 0;

        step.begin(l);
        RoutedCut routed = router->route(step);
        check_route(mesh, query, routed.path, route->name(), l);
        CutPath cut;
        cut.traced = routed.traced;
        cut.outlet = static_cast<int>(l);
        cut.halfedges = std::move(routed.path.halfedges);
        cut.cost = routed.path.cost;
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
        router->added(step, plan.paths.back());
        joiner->added(step, plan.paths.back());
    }
    return plan;
}

}  // namespace

}  // namespace vessel
