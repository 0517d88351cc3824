#include <doctest/doctest.h>

#include "detail/cost_to_tree.h"
#include "vessel/cut/boundary.h"
#include "vessel/cut/cut_cost.h"
#include "vessel/cut/cut_graph.h"
#include "vessel/cut/cut_metrics.h"
#include "vessel/cut/cut_winding.h"
#include "vessel/cut/winding_bound.h"
#include "vessel/core/errors.h"
#include "vessel/direction/direction.h"
#include "vessel/direction/geodesic.h"
#include "vessel/phantom/phantom.h"

#include <cmath>
#include <set>
#include <vector>

using namespace vessel;

namespace {

// A straight tube (rings of 24, staggered) whose arcs turning one way around it cost three
// times their length and the others their length: the cheapest path up the tube takes only
// the cheap slanted edges and winds round and round.
struct TwistedTube
{
    HelicalTubeOptions options;
    Mesh mesh;
    std::vector<BoundaryLoop> loops;
    Eigen::VectorXd u;
    HalfedgeWeights weights;

    TwistedTube()
    {
        options.helix_radius = 0.0;
        options.pitch = 12.0;
        options.n_around = 24;
        mesh = helical_tube(options);
        loops = boundary_loops(mesh);
        u = harmonic_longitudinal(mesh, loops, heat_geodesic_distance(mesh, loops[0].vertices));
        weights = evaluate_cost(mesh, LengthCost{1.0});
        for (auto h : mesh.halfedges())
        {
            const double turn = std::remainder(
                helical_tube_angle(options, to_eigen(mesh.point(mesh.to_vertex_handle(h)))) -
                    helical_tube_angle(options, to_eigen(mesh.point(mesh.from_vertex_handle(h)))),
                2.0 * M_PI);
            if (turn < -1e-9)
                weights[h.idx()] *= 3.0;
        }
    }

    // From one vertex of the first loop to any vertex of the second.
    PathQuery up() const
    {
        PathQuery query;
        query.sources = {loops[0].vertices.front()};
        query.is_target.assign(mesh.n_vertices(), 0);
        for (auto v : loops[1].vertices)
            query.is_target[v.idx()] = 1;
        return query;
    }
};

std::vector<VertexHandle> vertices_of(const Mesh& mesh, const GraphPath& path)
{
    std::vector<VertexHandle> vertices{mesh.from_vertex_handle(path.halfedges.front())};
    for (auto h : path.halfedges)
        vertices.push_back(mesh.to_vertex_handle(h));
    return vertices;
}

}  // namespace

TEST_CASE("winding_bound: the cheapest path within the bound, as the meter reads it")
{
    const TwistedTube tube;
    CutGraph graph(tube.mesh, tube.weights);
    const WindingMeter meter(tube.mesh, tube.u);
    const PathQuery query = tube.up();
    const GraphPath free = graph.shortest_path(query);
    const PathWinding free_winding = meter.measure(vertices_of(tube.mesh, free));
    MESSAGE("cheapest path: cost " << free.cost << ", winds " << free_winding.winding_deg
                                   << " deg");
    REQUIRE(std::abs(free_winding.winding_deg) > 180.0);  // the case is exercised

    const auto turn = [&meter](VertexHandle last, VertexHandle w, bool gap) {
        return meter.step(last, w, gap);
    };
    for (double limit : {10.0, 30.0, 90.0})
    {
        CAPTURE(limit);
        WindingBoundOptions options;
        options.limit_deg = limit;
        const std::optional<GraphPath> bounded = winding_bounded_path(graph, query, turn, options);
        REQUIRE(bounded);
        const std::vector<VertexHandle> vertices = vertices_of(tube.mesh, *bounded);
        const PathWinding w = meter.measure(vertices);
        MESSAGE("bound " << limit << ": cost " << bounded->cost << ", winds " << w.winding_deg
                         << " deg, span " << w.span_deg);
        // The meter is the sum of its steps, so the bound holds as the meter reads it, at
        // every vertex (the span) and end to end.
        CHECK(bounded->winding_rad * 180.0 / M_PI == doctest::Approx(w.winding_deg).epsilon(1e-9));
        CHECK(std::abs(w.winding_deg) <= limit + 1e-9);
        CHECK(w.span_deg <= 2.0 * limit + 1e-9);
        CHECK(w.measured == w.vertices);  // a tube: every vertex on a clean ring
        // No cheaper than the free path, and a route from the source to a target that visits
        // no vertex twice.
        CHECK(bounded->cost >= free.cost - 1e-9);
        CHECK(vertices.front() == query.sources.front());
        CHECK(query.is_target[vertices.back().idx()]);
        CHECK(std::set<VertexHandle>(vertices.begin(), vertices.end()).size() == vertices.size());
        for (std::size_t k = 1; k < vertices.size(); ++k)
            CHECK(tube.mesh.find_halfedge(vertices[k - 1], vertices[k]) ==
                  bounded->halfedges[k - 1]);
    }
}

TEST_CASE("winding_bound: no route within the bound, a loose bound, and what is refused")
{
    const TwistedTube tube;
    CutGraph graph(tube.mesh, tube.weights);
    const WindingMeter meter(tube.mesh, tube.u);
    const auto turn = [&meter](VertexHandle last, VertexHandle w, bool gap) {
        return meter.step(last, w, gap);
    };

    // Targets only on the far side of the tube's far end: any route turns about half a turn.
    PathQuery query = tube.up();
    const double start = helical_tube_angle(tube.options,
                                            to_eigen(tube.mesh.point(query.sources.front())));
    for (auto v : tube.loops[1].vertices)
    {
        const double a = std::remainder(
            helical_tube_angle(tube.options, to_eigen(tube.mesh.point(v))) - start, 2.0 * M_PI);
        query.is_target[v.idx()] = std::abs(a) > 0.8 * M_PI;
    }
    WindingBoundOptions tight;
    tight.limit_deg = 45.0;
    CHECK_FALSE(winding_bounded_path(graph, query, turn, tight));

    // With the plain length cost the cheapest path keeps to its side; a bound it keeps
    // changes nothing: the bounded route costs the same.
    const HalfedgeWeights length = evaluate_cost(tube.mesh, LengthCost{1.0});
    CutGraph plain(tube.mesh, length);
    query = tube.up();
    const GraphPath straight = plain.shortest_path(query);
    const PathWinding straight_winding = meter.measure(vertices_of(tube.mesh, straight));
    WindingBoundOptions loose;
    loose.limit_deg = 60.0;
    REQUIRE(straight_winding.span_deg < loose.limit_deg);
    const auto bounded = winding_bounded_path(plain, query, turn, loose);
    REQUIRE(bounded);
    CHECK(bounded->cost == doctest::Approx(straight.cost));

    WindingBoundOptions bad;
    bad.limit_deg = 0.0;
    CHECK_THROWS_AS(winding_bounded_path(graph, query, turn, bad), InvalidInputError);
    bad = WindingBoundOptions{};
    bad.bins = 0;
    CHECK_THROWS_AS(winding_bounded_path(graph, query, turn, bad), InvalidInputError);
    PathQuery empty = query;
    empty.sources.clear();
    CHECK_THROWS_AS(winding_bounded_path(graph, empty, turn), InvalidInputError);
    PathQuery short_targets = query;
    short_targets.is_target.resize(3);
    CHECK_THROWS_AS(winding_bounded_path(graph, short_targets, turn), InvalidInputError);
}

TEST_CASE("winding_bound: the planner's cost to the tree, grown or made at once, leads the search "
          "to the same path")
{
    // The cut planner keeps one A* bound over its searches (detail::CostToTree), grown as cuts
    // add targets. Grown from half the targets to all of them it must equal the field made
    // from all of them at once (a decrease-only Dijkstra), be consistent on every arc, and lead
    // the search to the path it finds with its own bound.
    const TwistedTube tube;
    CutGraph graph(tube.mesh, tube.weights);
    const WindingMeter meter(tube.mesh, tube.u);
    const auto turn = [&meter](VertexHandle last, VertexHandle w, bool gap) {
        return meter.step(last, w, gap);
    };
    const PathQuery query = tube.up();
    std::vector<char> half = query.is_target;
    const std::vector<VertexHandle>& top = tube.loops[1].vertices;
    for (std::size_t i = 0; i < top.size(); i += 2)
        half[top[i].idx()] = 0;

    detail::CostToTree grown(graph);
    const std::vector<double> before = grown.to(half);
    const std::vector<double>& after = grown.to(query.is_target);
    detail::CostToTree at_once(graph);
    CHECK(after == at_once.to(query.is_target));
    int lowered = 0, reached = 0;
    for (std::size_t v = 0; v < after.size(); ++v)
    {
        lowered += after[v] < before[v] ? 1 : 0;
        reached += std::isfinite(after[v]) ? 1 : 0;
        CHECK(after[v] <= before[v]);
    }
    CHECK(lowered > 0);
    CHECK(reached == static_cast<int>(tube.mesh.n_vertices()));
    for (auto h : tube.mesh.halfedges())
        CHECK(after[tube.mesh.from_vertex_handle(h).idx()] <=
              graph.weight(h) + after[tube.mesh.to_vertex_handle(h).idx()]);
    // Dropping a target (the planner moving from the inlet to the tree) makes it again.
    CHECK(grown.to(half) == before);

    for (double limit : {10.0, 30.0})
    {
        CAPTURE(limit);
        WindingBoundOptions options;
        options.limit_deg = limit;
        const auto own = winding_bounded_path(graph, query, turn, options);
        const auto given = winding_bounded_path(graph, query, turn, options, {}, &after);
        REQUIRE(own);
        REQUIRE(given);
        CHECK(given->halfedges == own->halfedges);
        CHECK(given->cost == own->cost);
        CHECK(given->winding_rad == own->winding_rad);
    }
    const std::vector<double> short_field(3, 0.0);
    CHECK_THROWS_AS(winding_bounded_path(graph, query, turn, {}, {}, &short_field),
                    InvalidInputError);
}

TEST_CASE("winding_bound: the rings fitted ahead on a second thread give the same path")
{
    // WindingMeter::Prefetch fits rings on another thread while the search runs: the path, its
    // winding and the meter's later readings must be the same bits as without it.
    const TwistedTube tube;
    CutGraph graph(tube.mesh, tube.weights);
    const Eigen::MatrixX3d axis = -descent_direction(tube.mesh, tube.u);
    const double edge = mean_edge_length(tube.mesh);
    const WindingMeter alone(graph, tube.u, edge, axis);
    const WindingMeter helped(graph, tube.u, edge, axis);
    const PathQuery query = tube.up();
    for (double limit : {10.0, 30.0})
    {
        CAPTURE(limit);
        WindingBoundOptions options;
        options.limit_deg = limit;
        const std::optional<GraphPath> plain = winding_bounded_path(
            graph, query,
            [&alone](VertexHandle last, VertexHandle w, bool gap) {
                return alone.step(last, w, gap);
            },
            options);
        int hints = 0;
        std::optional<GraphPath> ahead;
        {
            WindingMeter::Prefetch prefetch(helped);
            ahead = winding_bounded_path(
                graph, query,
                [&helped](VertexHandle last, VertexHandle w, bool gap) {
                    return helped.step(last, w, gap);
                },
                options,
                [&](VertexHandle v) {
                    ++hints;
                    prefetch.hint(v);
                });
        }
        REQUIRE(plain);
        REQUIRE(ahead);
        CHECK(hints > 0);
        CHECK(ahead->halfedges == plain->halfedges);
        CHECK(ahead->cost == plain->cost);
        CHECK(ahead->winding_rad == plain->winding_rad);
        const PathWinding a = alone.measure(vertices_of(tube.mesh, *plain));
        const PathWinding b = helped.measure(vertices_of(tube.mesh, *ahead));
        CHECK(a.winding_deg == b.winding_deg);
        CHECK(a.span_deg == b.span_deg);
        CHECK(std::abs(b.winding_deg) <= limit + 1e-9);
    }
}
