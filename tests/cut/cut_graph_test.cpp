#include <doctest/doctest.h>

#include "vessel/cut/cut_cost.h"
#include "vessel/cut/cut_graph.h"
#include "vessel/core/errors.h"
#include "vessel/phantom/phantom.h"

using namespace vessel;

namespace {

// Vertex (i, j) of plane_grid(size, n).
VertexHandle grid_vertex(int n, int i, int j) { return VertexHandle(j * (n + 1) + i); }

// A query on \p grid from vertex \p from to vertex \p to.
PathQuery grid_query(const Mesh& grid, VertexHandle from, VertexHandle to)
{
    PathQuery q;
    q.sources = {from};
    q.is_target.assign(grid.n_vertices(), 0);
    q.is_target[to.idx()] = 1;
    return q;
}

}  // namespace

TEST_CASE("cut_graph: Dijkstra with the length cost finds the straight grid line")
{
    const int n = 10;
    const Mesh grid = plane_grid(10.0, n);
    const HalfedgeWeights w = evaluate_cost(grid, LengthCost{1.0});
    PathQuery q = grid_query(grid, grid_vertex(n, 3, 0), grid_vertex(n, 3, n));
    const GraphPath path = shortest_path(grid, w, q);
    CHECK(path.halfedges.size() == static_cast<std::size_t>(n));
    CHECK(path.cost == doctest::Approx(10.0));
    CHECK(grid.from_vertex_handle(path.halfedges.front()) == grid_vertex(n, 3, 0));
    CHECK(grid.to_vertex_handle(path.halfedges.back()) == grid_vertex(n, 3, n));
    for (std::size_t i = 0; i + 1 < path.halfedges.size(); ++i)
        CHECK(grid.to_vertex_handle(path.halfedges[i]) ==
              grid.from_vertex_handle(path.halfedges[i + 1]));
}

TEST_CASE("cut_graph: a route between two boundary vertices goes through the interior")
{
    // A seam is made of interior edges: along the grid's bottom edge the route would cost 2,
    // through the interior it costs 3 (up one row, across, down).
    const int n = 10;
    const Mesh grid = plane_grid(10.0, n);
    const HalfedgeWeights w = evaluate_cost(grid, LengthCost{1.0});
    PathQuery q = grid_query(grid, grid_vertex(n, 3, 0), grid_vertex(n, 5, 0));
    const GraphPath path = shortest_path(grid, w, q);
    REQUIRE_FALSE(path.halfedges.empty());
    CHECK(grid.to_vertex_handle(path.halfedges.back()) == grid_vertex(n, 5, 0));
    for (const HalfedgeHandle h : path.halfedges)
        CHECK_FALSE(grid.is_boundary(grid.edge_handle(h)));
    CHECK(path.cost > 2.0 + 1e-9);
    q.tie_tolerance = 0.5;  // the tie walk may not take them either
    Eigen::MatrixX3d rate = Eigen::MatrixX3d::Zero(static_cast<Eigen::Index>(grid.n_vertices()), 3);
    rate.col(0).setOnes();
    for (const HalfedgeHandle h : CutGraph(grid, w).shortest_path(q, rate).halfedges)
        CHECK_FALSE(grid.is_boundary(grid.edge_handle(h)));
}

TEST_CASE("cut_graph: the imaginary source starts at the cheapest source vertex")
{
    const int n = 10;
    const Mesh grid = plane_grid(10.0, n);
    const HalfedgeWeights w = evaluate_cost(grid, LengthCost{1.0});
    PathQuery q;
    for (int i = 0; i <= n; ++i)  // the whole bottom row joined to one zero-cost node
        q.sources.push_back(grid_vertex(n, i, 0));
    q.is_target.assign(grid.n_vertices(), 0);
    q.is_target[grid_vertex(n, 7, 4).idx()] = 1;
    const GraphPath path = shortest_path(grid, w, q);
    CHECK(path.cost == doctest::Approx(4.0));
    CHECK(grid.from_vertex_handle(path.halfedges.front()) == grid_vertex(n, 7, 0));
}

TEST_CASE("cut_graph: blocked vertices are avoided and unreachable targets throw")
{
    const int n = 6;
    const Mesh grid = plane_grid(6.0, n);
    const HalfedgeWeights w = evaluate_cost(grid, LengthCost{1.0});
    PathQuery q = grid_query(grid, grid_vertex(n, 0, 3), grid_vertex(n, 6, 3));
    q.is_blocked.assign(grid.n_vertices(), 0);
    for (int j = 0; j <= 4; ++j)  // a wall at i = 3 with a gap at the top
        q.is_blocked[grid_vertex(n, 3, j).idx()] = 1;
    const GraphPath path = shortest_path(grid, w, q);
    for (auto h : path.halfedges)
        CHECK_FALSE(q.is_blocked[grid.to_vertex_handle(h).idx()]);
    CHECK(path.cost > 6.0);
    for (int j = 5; j <= n; ++j)
        q.is_blocked[grid_vertex(n, 3, j).idx()] = 1;
    CHECK_THROWS_AS(shortest_path(grid, w, q), InvalidInputError);
    q.sources.clear();
    CHECK_THROWS_AS(shortest_path(grid, w, q), InvalidInputError);
}

TEST_CASE("cut_graph: costs are non-negative, E_c is zero along z, and bad costs are refused")
{
    const Mesh grid = plane_grid(1.0, 4);
    Eigen::MatrixX3d z(grid.n_vertices(), 3);
    z.rowwise() = Eigen::RowVector3d(0, 1, 0);
    const HalfedgeWeights ec = evaluate_cost(grid, CurvatureCost{&z});
    const HalfedgeWeights blend = evaluate_cost(grid, BlendCost{{&z}, {0.25}, 0.5});
    for (auto h : grid.halfedges())
    {
        const auto d = grid.point(h.to()) - grid.point(h.from());
        const double expected = 1.0 - d[1] / d.norm();
        CHECK(ec[h.idx()] == doctest::Approx(expected).epsilon(1e-12));
        CHECK(blend[h.idx()] == doctest::Approx(0.5 * expected + 0.5 * d.norm() / 0.25));
    }
    const AnyCost negative = [](const Mesh&, SmartHalfedgeHandle) { return -1.0; };
    CHECK_THROWS_AS(evaluate_cost(grid, negative), InvalidInputError);
}

TEST_CASE("cut_graph: a winding field passed by reference gives the path of the same field in the query")
{
    const int n = 8;
    const Mesh grid = plane_grid(8.0, n);
    const HalfedgeWeights w = evaluate_cost(grid, LengthCost{1.0});
    // Against the grid's diagonals every staircase between two vertices next to opposite
    // corners costs the same: the winding field picks one. (Not the corners themselves: arcs
    // along the boundary weigh infinity, and a corner may have no other edge.)
    Eigen::MatrixX3d rate(static_cast<Eigen::Index>(grid.n_vertices()), 3);
    for (Eigen::Index v = 0; v < rate.rows(); ++v)
        rate.row(v) << 1.0, -0.5, 0.0;
    PathQuery q = grid_query(grid, grid_vertex(n, n - 1, 1), grid_vertex(n, 1, n - 1));
    q.tie_tolerance = 0.1;
    CutGraph graph(grid, w);
    const GraphPath by_reference = graph.shortest_path(q, rate);
    PathQuery copied = q;
    copied.winding_rate = rate;
    const GraphPath in_query = graph.shortest_path(copied);
    CHECK(by_reference.halfedges == in_query.halfedges);
    CHECK(by_reference.winding_rad == in_query.winding_rad);
    CHECK(by_reference.cost == doctest::Approx(2.0 * (n - 2)));
    // The field steers the walk: the path without it winds at least as far along the field.
    const GraphPath plain = graph.shortest_path(q);
    double plain_winding = 0.0;
    for (auto h : plain.halfedges)
    {
        const auto d = grid.point(grid.to_vertex_handle(h)) - grid.point(grid.from_vertex_handle(h));
        plain_winding += rate.row(grid.from_vertex_handle(h).idx()).dot(Eigen::Vector3d(d[0], d[1], d[2]));
    }
    CHECK(std::abs(by_reference.winding_rad) <= std::abs(plain_winding) + 1e-12);
    CHECK_THROWS_AS(graph.shortest_path(q, Eigen::MatrixX3d::Zero(3, 3)), InvalidInputError);
}
