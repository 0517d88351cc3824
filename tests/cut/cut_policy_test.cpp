#include <doctest/doctest.h>

#include "support/checks.h"

#include "vessel/check/validation.h"
#include "vessel/core/errors.h"
#include "vessel/cut/boundary.h"
#include "vessel/cut/cut_cost.h"
#include "vessel/cut/cut_join.h"
#include "vessel/cut/cut_route.h"
#include "vessel/cut/endpoints.h"
#include "vessel/direction/curvature.h"
#include "vessel/direction/direction.h"
#include "vessel/direction/geodesic.h"
#include "vessel/phantom/phantom.h"
#include "vessel/pipeline.h"

#include <functional>
#include <limits>
#include <queue>
#include <string>
#include <vector>

using namespace vessel;

namespace {

// A four-outlet tree with the paper's E_c weights and the winding rate, as flatten() makes them.
struct Tree
{
    Mesh mesh = Mesh(tree_phantom({4, 3.0, 0.6, 7}));
    std::vector<BoundaryLoop> loops = boundary_loops(mesh);
    Eigen::MatrixX3d z, rate;
    HalfedgeWeights weights;

    Tree()
    {
        const auto curvature = principal_curvature(mesh);
        const Eigen::VectorXd G = heat_geodesic_distance(mesh, loops[0].vertices);
        DirectionOptions paper;
        paper.confident_anisotropy = 0.0;
        z = vessel_direction(mesh, curvature, loops, G, paper);
        rate = winding_rate(mesh, z, curvature.k_max.cwiseAbs());
        weights = evaluate_cost(mesh, CurvatureCost{&z});
    }

    CutPlan plan(const CutPlanOptions& options) const
    {
        return plan_cuts(mesh, loops, weights, rate, options);
    }

    double length(const CutPath& cut) const
    {
        double total = 0.0;
        for (auto h : cut.halfedges)
            total += mesh.calc_edge_length(h);
        return total;
    }
};

CutPlanOptions shortest_route()
{
    CutPlanOptions options;
    options.route = CutRoute::ShortestPath;
    return options;
}

// A researcher's route: the path of least 3D length (edge lengths, not the travel cost) from the
// outlet to the query's targets, through no blocked vertex.
class ShortestLengthRoute : public CutRoutePolicy
{
public:
    std::string name() const override { return "shortest-length"; }
    std::unique_ptr<CutRouter> start(const CutPlanContext&) const override
    {
        struct Router : CutRouter
        {
            RoutedCut route(CutStep& step) override
            {
                const Mesh& mesh = step.context().mesh();
                const PathQuery& query = step.query();
                std::vector<double> dist(mesh.n_vertices(),
                                         std::numeric_limits<double>::infinity());
                std::vector<HalfedgeHandle> parent(mesh.n_vertices());
                using Item = std::pair<double, int>;
                std::priority_queue<Item, std::vector<Item>, std::greater<Item>> heap;
                for (auto s : query.sources)
                {
                    dist[s.idx()] = 0.0;
                    heap.push({0.0, s.idx()});
                }
                while (!heap.empty())
                {
                    const auto [d, v] = heap.top();
                    heap.pop();
                    if (d > dist[v])
                        continue;
                    if (query.is_target[v])
                    {
                        std::vector<HalfedgeHandle> path;
                        for (int u = v; parent[u].is_valid();
                             u = mesh.from_vertex_handle(parent[u]).idx())
                            path.insert(path.begin(), parent[u]);
                        return {step.context().graph->path_of(std::move(path)), false};
                    }
                    for (auto h : mesh.voh_range(VertexHandle(v)))
                    {
                        const int w = mesh.to_vertex_handle(h).idx();
                        const double nd = d + mesh.calc_edge_length(h);
                        if (!mesh.is_boundary(mesh.edge_handle(h)) && !query.is_blocked[w] &&
                            nd < dist[w])
                        {
                            dist[w] = nd;
                            parent[w] = h;
                            heap.push({nd, w});
                        }
                    }
                }
                throw InvalidInputError("shortest-length: no target reached");
            }
        };
        return std::make_unique<Router>();
    }
};

// A researcher's join: every later cut ends on the tree vertex nearest (straight distance) to
// its outlet's centre; records what it was asked.
class NearestToCentreJoin : public CutJoinPolicy
{
public:
    std::string name() const override { return "nearest-to-centre"; }
    bool narrows_ends() const override { return true; }
    std::unique_ptr<CutJoiner> start(const CutPlanContext&) const override
    {
        struct Joiner : CutJoiner
        {
            const NearestToCentreJoin* policy = nullptr;
            std::vector<VertexHandle> ends(const CutStep& step) override
            {
                const Mesh& mesh = step.context().mesh();
                const BoundaryLoop& loop = (*step.context().loops)[step.outlet()];
                Eigen::Vector3d centre = Eigen::Vector3d::Zero();
                for (auto v : loop.vertices)
                    centre += to_eigen(mesh.point(v));
                centre /= static_cast<double>(loop.vertices.size());
                VertexHandle best;
                double nearest = std::numeric_limits<double>::infinity();
                for (auto v : mesh.vertices())
                    if (step.query().is_target[v.idx()] &&
                        (to_eigen(mesh.point(v)) - centre).norm() < nearest)
                    {
                        nearest = (to_eigen(mesh.point(v)) - centre).norm();
                        best = v;
                    }
                policy->chosen.push_back(best);
                return {best};
            }
            void added(const CutStep& step, const CutPath& cut) override
            {
                policy->added.push_back(static_cast<int>(step.plan().paths.size()));
                CHECK(&cut == &step.plan().paths.back());
            }
        };
        auto joiner = std::make_unique<Joiner>();
        joiner->policy = this;
        return joiner;
    }
    mutable std::vector<VertexHandle> chosen;
    mutable std::vector<int> added;
};

// Routes that break the contract: an empty path, or the cheapest path without its last edge.
class BrokenRoute : public CutRoutePolicy
{
public:
    bool empty = true;
    std::string name() const override { return "broken"; }
    std::unique_ptr<CutRouter> start(const CutPlanContext&) const override
    {
        struct Router : CutRouter
        {
            bool empty = true;
            RoutedCut route(CutStep& step) override
            {
                GraphPath path = step.cheapest();
                if (empty)
                    path.halfedges.clear();
                else
                    path.halfedges.pop_back();
                return {path, false};
            }
        };
        auto router = std::make_unique<Router>();
        router->empty = empty;
        return router;
    }
};

// A join that allows a vertex off the tree (the outlet's own first vertex).
class OffTreeJoin : public CutJoinPolicy
{
public:
    std::string name() const override { return "off-tree"; }
    std::unique_ptr<CutJoiner> start(const CutPlanContext&) const override
    {
        struct Joiner : CutJoiner
        {
            std::vector<VertexHandle> ends(const CutStep& step) override
            {
                return {(*step.context().loops)[step.outlet()].vertices.front()};
            }
        };
        return std::make_unique<Joiner>();
    }
};

// One vertex per loop: the farthest along the loop centre's offset from the mesh's vertex mean,
// perpendicular to the loop's plane (the outer side of each vessel).
class OuterSideEndpoints : public EndpointPolicy
{
public:
    std::string name() const override { return "outer-side"; }
    std::vector<VertexHandle> allowed(const Mesh& mesh, const BoundaryLoop& loop,
                                      std::size_t) const override
    {
        Eigen::Vector3d mean = Eigen::Vector3d::Zero();
        for (auto v : mesh.vertices())
            mean += to_eigen(mesh.point(v));
        mean /= static_cast<double>(mesh.n_vertices());
        Eigen::Vector3d centre = Eigen::Vector3d::Zero();
        for (auto v : loop.vertices)
            centre += to_eigen(mesh.point(v));
        centre /= static_cast<double>(loop.vertices.size());
        Eigen::Vector3d normal = Eigen::Vector3d::Zero();
        for (std::size_t i = 0; i < loop.vertices.size(); ++i)
            normal += (to_eigen(mesh.point(loop.vertices[i])) - centre)
                          .cross(to_eigen(mesh.point(loop.vertices[(i + 1) % loop.vertices.size()])) -
                                 centre);
        normal.normalize();
        Eigen::Vector3d outward = centre - mean;
        outward -= outward.dot(normal) * normal;
        VertexHandle best = loop.vertices.front();
        for (auto v : loop.vertices)
            if ((to_eigen(mesh.point(v)) - centre).dot(outward) >
                (to_eigen(mesh.point(best)) - centre).dot(outward))
                best = v;
        return {best};
    }
};

bool same_plan(const CutPlan& a, const CutPlan& b)
{
    if (a.paths.size() != b.paths.size())
        return false;
    for (std::size_t i = 0; i < a.paths.size(); ++i)
        if (a.paths[i].halfedges != b.paths[i].halfedges ||
            a.paths[i].parent != b.paths[i].parent || a.paths[i].traced != b.paths[i].traced)
            return false;
    return true;
}

}  // namespace

TEST_CASE("cut_policy: the built-in policies given as objects plan what their enums plan")
{
    // flatten() with the default route and join (aligned, approach), the paper's (shortest,
    // cheapest) and the closest join: the same cuts from the enum and from the policy object.
    const Mesh tree = tree_phantom({4, 3.0, 0.6, 7});
    struct Pair
    {
        CutRoute route;
        CutJoin join;
    };
    for (const Pair pair : {Pair{CutRoute::Aligned, CutJoin::Approach},
                            Pair{CutRoute::ShortestPath, CutJoin::Cheapest},
                            Pair{CutRoute::Streamline, CutJoin::Approach},
                            Pair{CutRoute::ShortestPath, CutJoin::Closest}})
    {
        CAPTURE(route_policy(pair.route)->name());
        CAPTURE(join_policy(pair.join)->name());
        FlattenOptions by_enum;
        by_enum.refinement = Refinement::None;  // the cuts are the point here
        by_enum.cuts.route = pair.route;
        by_enum.cuts.join = pair.join;
        FlattenOptions by_object = by_enum;
        // The enums are set to other values: the objects replace them.
        by_object.cuts.route =
            pair.route == CutRoute::Aligned ? CutRoute::ShortestPath : CutRoute::Aligned;
        by_object.cuts.join = pair.join == CutJoin::Cheapest ? CutJoin::Closest : CutJoin::Cheapest;
        by_object.cuts.router = route_policy(pair.route);
        by_object.cuts.joiner = join_policy(pair.join);
        const FlattenResult a = flatten(tree, by_enum);
        const FlattenResult b = flatten(tree, by_object);
        REQUIRE(a.plan.paths.size() == 4);
        CHECK(same_plan(a.plan, b.plan));
    }
}

TEST_CASE("cut_policy: a researcher's route and join plug into plan_cuts() and flatten()")
{
    const Tree t;
    REQUIRE(t.loops.size() == 5);
    CutPlanOptions options = shortest_route();
    options.router = std::make_shared<ShortestLengthRoute>();
    const CutPlan own = t.plan(options);
    const CutPlan cheapest = t.plan(shortest_route());
    REQUIRE(own.paths.size() == 4);
    // The first cut is the shortest route to the inlet: no longer than the cheapest path
    // (which ends on the same targets), and a different cut (the travel cost is not length).
    CHECK(t.length(own.paths[0]) <= t.length(cheapest.paths[0]) * (1.0 + 1e-12));
    CHECK(!same_plan(own, cheapest));
    for (const CutPath& cut : own.paths)
    {
        CHECK(cut.outlet >= 1);
        CHECK(!cut.traced);
    }

    // The join: every later cut ends on the vertex the policy chose; the joiner is told of
    // every cut once it is in the plan.
    auto join = std::make_shared<NearestToCentreJoin>();
    options = shortest_route();
    options.joiner = join;
    const CutPlan joined = t.plan(options);
    REQUIRE(joined.paths.size() == 4);
    REQUIRE(join->chosen.size() == 3);
    for (std::size_t i = 1; i < joined.paths.size(); ++i)
        CHECK(joined.paths[i].end == join->chosen[i - 1]);
    CHECK(join->added == std::vector<int>{1, 2, 3, 4});
    CHECK(!same_plan(joined, cheapest));

    // Through flatten(): the route needs no stream field, and the default one-to-one map is
    // made on its cuts.
    FlattenOptions flat;
    flat.cuts.router = std::make_shared<ShortestLengthRoute>();
    flat.cuts.joiner = std::make_shared<NearestToCentreJoin>();
    const FlattenResult r = flatten(t.mesh, flat);
    REQUIRE(r.plan.paths.size() == 4);
    CHECK(r.uv.rows() == static_cast<Eigen::Index>(r.mesh.n_vertices()));
    CHECK(r.quality.flipped_triangles == 0);
}

TEST_CASE("cut_policy: a route or join that breaks its contract is refused, naming it")
{
    const Tree t;
    CutPlanOptions options = shortest_route();
    auto broken = std::make_shared<BrokenRoute>();
    options.router = broken;
    const auto plan = [&] { t.plan(options); };
    CHECK_THROWS_AS(plan(), InvalidInputError);
    std::string message = test::error_of(plan);
    CHECK_MESSAGE(message.find("cut route 'broken' returned, for outlet 1, an empty path") !=
                      std::string::npos,
                  message);
    broken->empty = false;
    message = test::error_of(plan);
    CHECK_MESSAGE(message.find("cut route 'broken'") != std::string::npos, message);
    CHECK_MESSAGE(message.find("not one of CutStep::query()'s targets") != std::string::npos,
                  message);

    options = shortest_route();
    options.joiner = std::make_shared<OffTreeJoin>();
    CHECK_THROWS_AS(plan(), InvalidInputError);
    message = test::error_of(plan);
    CHECK_MESSAGE(message.find("join policy 'off-tree' allowed vertex") != std::string::npos,
                  message);
}

TEST_CASE("cut_policy: a cut leaves its loop at the endpoint policy's vertex only")
{
    // With one allowed vertex per loop the cheapest path from it may come back to its own loop
    // at another vertex (through interior edges) before it leaves: the loop would be opened twice
    // and the cut mesh would fall apart. On the coarse VaMPy artery the outer-side start did so
    // (a cut mesh of two pieces, refused by the layout circle) until the planner blocked the
    // loop's other vertices.
    const TreeSurface surface =
        load_tree_surface(std::string(VESSEL_SHARED_DATA) + "/vampy/artery-coarse.ply");
    FlattenOptions options;
    options.cuts.endpoints = std::make_shared<OuterSideEndpoints>();
    const FlattenResult r = flatten(surface.mesh, options);
    REQUIRE(r.plan.paths.size() == 2);
    std::vector<int> loop_of(surface.mesh.n_vertices(), -1);
    for (std::size_t l = 0; l < r.loops.size(); ++l)
        for (auto v : r.loops[l].vertices)
            loop_of[v.idx()] = static_cast<int>(l);
    for (const CutPath& cut : r.plan.paths)
    {
        CAPTURE(cut.outlet);
        CHECK(loop_of[cut.start.idx()] == cut.outlet);
        // No vertex after the start lies on a loop, but the first cut's end on the inlet.
        for (std::size_t i = 0; i < cut.halfedges.size(); ++i)
        {
            const int w = surface.mesh.to_vertex_handle(cut.halfedges[i]).idx();
            const bool inlet_end = cut.parent < 0 && i + 1 == cut.halfedges.size();
            CHECK(loop_of[w] == (inlet_end ? 0 : -1));
        }
    }
    // The cut mesh is one disk and the default map one-to-one.
    CHECK(boundary_loops(r.mesh).size() == 1);
    CHECK(r.quality.flipped_triangles == 0);
}
