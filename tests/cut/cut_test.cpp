#include <doctest/doctest.h>

#include "vessel/cut/cut.h"
#include "vessel/core/errors.h"
#include "vessel/phantom/phantom.h"
#include "vessel/core/properties.h"

#include <OpenMesh/Core/Utils/PropertyManager.hh>
#include <OpenMesh/Tools/Utils/MeshCheckerT.hh>

#include <algorithm>
#include <array>
#include <map>
#include <numeric>
#include <queue>
#include <set>
#include <sstream>
#include <string>
#include <vector>

using namespace vessel;

namespace {

int euler_characteristic(const Mesh& mesh)
{
    return static_cast<int>(mesh.n_vertices()) - static_cast<int>(mesh.n_edges()) +
           static_cast<int>(mesh.n_faces());
}

// Boundary loops counted by following next() links, independently of boundary.cpp; also checks
// that every boundary halfedge's next is a boundary halfedge starting where it ends.
int count_boundary_loops(const Mesh& mesh)
{
    std::vector<char> seen(mesh.n_halfedges(), 0);
    int loops = 0;
    for (auto start : mesh.halfedges())
    {
        if (!start.is_boundary() || seen[start.idx()])
            continue;
        ++loops;
        auto h = start;
        std::size_t steps = 0;
        do
        {
            seen[h.idx()] = 1;
            REQUIRE(h.next().is_boundary());
            REQUIRE(h.to() == h.next().from());
            h = h.next();
            REQUIRE(++steps <= mesh.n_halfedges());
        } while (h != start);
    }
    return loops;
}

// MeshCheckerT plus what it does not look at: every vertex has exactly one fan (its circulator
// reaches every halfedge leaving it), at most one outgoing boundary halfedge, and is_boundary(v)
// agrees with the presence of one.
void check_mesh(const Mesh& mesh)
{
    std::ostringstream report;
    CHECK_MESSAGE(OpenMesh::Utils::MeshCheckerT<Mesh>(mesh).check(
                      OpenMesh::Utils::MeshCheckerT<Mesh>::CHECK_ALL, report),
                  report.str());

    std::vector<int> outgoing(mesh.n_vertices(), 0), outgoing_boundary(mesh.n_vertices(), 0);
    for (auto h : mesh.halfedges())
    {
        ++outgoing[h.from().idx()];
        outgoing_boundary[h.from().idx()] += h.is_boundary() ? 1 : 0;
    }
    int bad = 0;
    for (auto v : mesh.vertices())
    {
        int circulated = 0;
        for (auto h : v.outgoing_halfedges())
        {
            bad += h.from() != v;
            ++circulated;
        }
        bad += circulated != outgoing[v.idx()];
        bad += outgoing_boundary[v.idx()] > 1;
        bad += mesh.is_boundary(v) != (outgoing_boundary[v.idx()] == 1);
    }
    CHECK(bad == 0);
}

// `prop::origin` by vertex index; fails the test if missing.
std::vector<int> origin_map(const Mesh& mesh)
{
    OpenMesh::VPropHandleT<int> origin;
    REQUIRE(mesh.get_property_handle(origin, prop::origin));
    std::vector<int> map;
    for (auto v : mesh.vertices())
        map.push_back(mesh.property(origin, v));
    return map;
}

EdgeHandle edge_between(const Mesh& mesh, int a, int b)
{
    const HalfedgeHandle h = mesh.find_halfedge(VertexHandle(a), VertexHandle(b));
    REQUIRE(h.is_valid());
    return mesh.edge_handle(h);
}

// Edges of the polyline through vertex ids \p path.
std::vector<EdgeHandle> polyline(const Mesh& mesh, const std::vector<int>& path)
{
    std::vector<EdgeHandle> edges;
    for (std::size_t i = 0; i + 1 < path.size(); ++i)
        edges.push_back(edge_between(mesh, path[i], path[i + 1]));
    return edges;
}

int cylinder_id(int n_around, int j, int i)
{
    return j * n_around + ((i % n_around) + n_around) % n_around;
}
int grid_id(int n, int j, int i)
{
    return j * (n + 1) + i;
}

struct UnionFind
{
    std::vector<int> parent;
    explicit UnionFind(int n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
    int find(int x) { return parent[x] == x ? x : parent[x] = find(parent[x]); }
    void unite(int a, int b) { parent[find(a)] = find(b); }
};

// Test oracle: cut by rebuilding. Face corners are merged across every non-seam edge; each class
// of corners is one vertex of the cut surface, which is rebuilt from scratch with add_face. The
// in-place result must have the same vertex count, Euler characteristic and boundary loops, and
// its corners must be the same classes (a bijection between classes and vertices).
void check_against_rebuild(const Mesh& before, const std::vector<EdgeHandle>& seam,
                           const Mesh& after)
{
    auto corner = [&](FaceHandle f, VertexHandle v) {
        int k = 0;
        for (auto w : before.fv_range(f))
        {
            if (w == v)
                return 3 * f.idx() + k;
            ++k;
        }
        FAIL("vertex not in face");
        return -1;
    };
    std::set<int> seam_ids;
    for (auto e : seam)
        seam_ids.insert(e.idx());
    UnionFind classes(3 * static_cast<int>(before.n_faces()));
    for (auto e : before.edges())
    {
        if (e.is_boundary() || seam_ids.count(e.idx()))
            continue;
        const auto h0 = e.h0(), h1 = e.h1();
        for (auto v : {h0.from(), h0.to()})
            classes.unite(corner(h0.face(), v), corner(h1.face(), v));
    }
    std::map<int, int> class_id;
    std::vector<VertexHandle> class_origin;
    for (auto f : before.faces())
        for (auto v : f.vertices())
        {
            const int c = classes.find(corner(f, v));
            if (class_id.emplace(c, static_cast<int>(class_id.size())).second)
                class_origin.push_back(v);
        }
    // Isolated input vertices (none in our shapes) would stay as they are.
    Mesh rebuilt;
    for (auto v : class_origin)
        rebuilt.add_vertex(before.point(v));
    for (auto f : before.faces())
    {
        std::vector<VertexHandle> corners;
        for (auto v : f.vertices())
            corners.push_back(VertexHandle(class_id.at(classes.find(corner(f, v)))));
        REQUIRE(rebuilt.add_face(corners).is_valid());
    }

    CHECK(after.n_vertices() == rebuilt.n_vertices());
    CHECK(after.n_faces() == rebuilt.n_faces());
    CHECK(after.n_edges() == rebuilt.n_edges());
    CHECK(euler_characteristic(after) == euler_characteristic(rebuilt));
    CHECK(count_boundary_loops(after) == count_boundary_loops(rebuilt));

    auto origin = origin_map(after);
    std::map<int, int> vertex_of_class, class_of_vertex;
    int mismatches = 0;
    for (auto f : after.faces())
        for (auto w : f.vertices())
        {
            const int c = class_id.at(classes.find(corner(f, VertexHandle(origin[w.idx()]))));
            const auto a = vertex_of_class.emplace(c, w.idx());
            const auto b = class_of_vertex.emplace(w.idx(), c);
            mismatches += a.first->second != w.idx();
            mismatches += b.first->second != c;
        }
    CHECK(mismatches == 0);
}

// Everything a cut must preserve: faces modulo origin, positions, handles of input vertices.
void check_origin(const Mesh& before, const Mesh& after)
{
    auto origin = origin_map(after);
    REQUIRE(after.n_faces() == before.n_faces());
    auto canonical = [](std::array<int, 3> t) {
        std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
        return t;
    };
    int bad = 0;
    for (auto v : after.vertices())
    {
        bad += origin[v.idx()] < 0 || origin[v.idx()] >= static_cast<int>(before.n_vertices());
        if (v.idx() < static_cast<int>(before.n_vertices()))
            bad += origin[v.idx()] != v.idx();
        else
            bad += after.point(v) != before.point(VertexHandle(origin[v.idx()]));
    }
    for (auto f : after.faces())
    {
        std::array<int, 3> cut{}, input{};
        int k = 0;
        for (auto v : f.vertices())
            cut[k++] = origin[v.idx()];
        k = 0;
        for (auto v : before.fv_range(f))
            input[k++] = v.idx();
        bad += canonical(cut) != canonical(input);
    }
    CHECK(bad == 0);
}

// All checks of one cut; returns the cut mesh.
Mesh cut_and_check(const Mesh& input, const std::vector<EdgeHandle>& seam, int expected_euler,
                   int expected_loops, int expected_new_vertices)
{
    Mesh mesh = input;
    const CutSummary summary = cut_along_edges(mesh, seam);
    CHECK(summary.seam_edges == static_cast<int>(seam.size()));
    CHECK(summary.duplicated_vertices == expected_new_vertices);
    CHECK(mesh.n_vertices() == input.n_vertices() + expected_new_vertices);
    CHECK(mesh.n_edges() == input.n_edges() + seam.size());
    CHECK(mesh.n_faces() == input.n_faces());
    check_mesh(mesh);
    CHECK(euler_characteristic(mesh) == expected_euler);
    CHECK(count_boundary_loops(mesh) == expected_loops);
    for (auto e : seam)
        CHECK(mesh.is_boundary(e));
    check_origin(input, mesh);
    check_against_rebuild(input, seam, mesh);
    return mesh;
}

// Icosphere with the stars of the vertices nearest to \p directions removed: a sphere with holes.
Mesh sphere_with_holes(const std::vector<OpenMesh::Vec3d>& directions)
{
    const Mesh sphere = icosphere(1.0, 2);
    std::set<int> removed;
    for (const auto& d : directions)
    {
        auto best = *sphere.vertices().begin();
        for (auto v : sphere.vertices())
            if ((sphere.point(v) - d.normalized()).sqrnorm() <
                (sphere.point(best) - d.normalized()).sqrnorm())
                best = v;
        removed.insert(best.idx());
    }
    Mesh mesh;
    std::vector<VertexHandle> map(sphere.n_vertices());
    for (auto v : sphere.vertices())
        if (!removed.count(v.idx()))
            map[v.idx()] = mesh.add_vertex(sphere.point(v));
    for (auto f : sphere.faces())
    {
        std::vector<VertexHandle> corners;
        for (auto v : f.vertices())
            corners.push_back(map[v.idx()]);
        if (std::all_of(corners.begin(), corners.end(),
                        [](VertexHandle v) { return v.is_valid(); }))
            mesh.add_face(corners);
    }
    return mesh;
}

// Vertex ids of each boundary loop.
std::vector<std::set<int>> loop_vertices(const Mesh& mesh)
{
    std::vector<std::set<int>> loops;
    std::set<int> seen;
    for (auto start : mesh.halfedges())
    {
        if (!start.is_boundary() || seen.count(start.idx()))
            continue;
        std::set<int> loop;
        auto h = start;
        do
        {
            seen.insert(h.idx());
            loop.insert(h.to().idx());
            h = h.next();
        } while (h != start);
        loops.push_back(loop);
    }
    return loops;
}

// Breadth-first vertex path from \p sources to the first vertex in \p targets, avoiding
// \p blocked; returned as vertex ids, source first.
std::vector<int> bfs_path(const Mesh& mesh, const std::set<int>& sources,
                          const std::set<int>& targets, const std::set<int>& blocked)
{
    std::vector<int> parent(mesh.n_vertices(), -2);
    std::queue<int> queue;
    for (int s : sources)
    {
        parent[s] = -1;
        queue.push(s);
    }
    while (!queue.empty())
    {
        const int u = queue.front();
        queue.pop();
        if (targets.count(u))
        {
            std::vector<int> path;
            for (int x = u; x != -1; x = parent[x])
                path.push_back(x);
            std::reverse(path.begin(), path.end());
            return path;
        }
        for (auto w : OpenMesh::make_smart(VertexHandle(u), mesh).vertices())
            if (parent[w.idx()] == -2 && !blocked.count(w.idx()))
            {
                parent[w.idx()] = u;
                queue.push(w.idx());
            }
    }
    FAIL("no path");
    return {};
}

}  // namespace

TEST_CASE("cut: cylinder cut along an axial line becomes a disk")
{
    const int n_around = 12, n_along = 6;
    Mesh input = open_cylinder(1.0, 3.0, n_around, n_along);
    std::vector<int> line;
    for (int j = 0; j <= n_along; ++j)
        line.push_back(cylinder_id(n_around, j, 0));
    const auto seam = polyline(input, line);
    REQUIRE(euler_characteristic(input) == 0);
    cut_and_check(input, seam, 1, 1, n_along + 1);
}

TEST_CASE("cut: every vertex, edge and halfedge property reaches the duplicates")
{
    const int n_around = 10, n_along = 5;
    Mesh mesh = open_cylinder(1.0, 2.0, n_around, n_along);
    const Mesh input = mesh;
    std::vector<int> line;
    for (int j = 0; j <= n_along; ++j)
        line.push_back(cylinder_id(n_around, j, 3));
    const auto seam = polyline(mesh, line);
    const int n_vertices = static_cast<int>(mesh.n_vertices());
    const int n_edges = static_cast<int>(mesh.n_edges());

    auto named = OpenMesh::VProp<double>(mesh, "test:value");
    OpenMesh::VProp<int> unnamed(mesh);
    auto edge_id = OpenMesh::EProp<int>(mesh, "test:edge");
    auto halfedge_id = OpenMesh::HProp<int>(mesh, "test:halfedge");
    mesh.request_vertex_normals();
    mesh.request_face_normals();
    mesh.update_normals();
    for (auto v : mesh.vertices())
    {
        named[v] = 0.5 + v.idx() * 1.25;
        unnamed[v] = 1000 + 7 * v.idx();
    }
    for (auto e : mesh.edges())
        edge_id[e] = e.idx();
    for (auto h : mesh.halfedges())
        halfedge_id[h] = h.idx();

    const CutSummary summary = cut_along_edges(mesh, seam);
    CHECK(summary.duplicated_vertices == n_along + 1);
    check_mesh(mesh);
    auto origin = origin_map(mesh);
    int bad = 0;
    for (auto v : mesh.vertices())
    {
        const VertexHandle o(origin[v.idx()]);
        bad += named[v] != named[o];
        bad += unnamed[v] != unnamed[o];
        bad += mesh.normal(v) != mesh.normal(o);
        bad += mesh.point(v) != mesh.point(o);
        if (v.idx() >= n_vertices)
            bad += std::find(line.begin(), line.end(), o.idx()) == line.end();
    }
    CHECK(bad == 0);

    // Each new edge twins one seam edge; its halfedges carry the properties of the input halfedge
    // with the same direction, and the one inside a face sits in that halfedge's input face.
    std::set<int> twinned;
    for (auto e : mesh.edges())
    {
        if (e.idx() < n_edges)
            continue;
        CHECK(e.is_boundary());
        const SmartEdgeHandle source(edge_id[e], &input);
        twinned.insert(source.idx());
        CHECK(std::find(seam.begin(), seam.end(), EdgeHandle(source.idx())) != seam.end());
        for (auto h : {e.h0(), e.h1()})
        {
            const OpenMesh::SmartHalfedgeHandle h_in(halfedge_id[h], &input);
            CHECK(h_in.edge() == source);
            CHECK(origin[h.from().idx()] == h_in.from().idx());
            CHECK(origin[h.to().idx()] == h_in.to().idx());
            if (!h.is_boundary())
                CHECK(h.face() == h_in.face());
        }
    }
    CHECK(twinned.size() == seam.size());
}

TEST_CASE("cut: cylinder with an axial seam and a branching slit (3 paths at one vertex)")
{
    const int n_around = 12, n_along = 8, j0 = 4;
    Mesh input = open_cylinder(1.0, 3.0, n_around, n_along);
    std::vector<int> axis, branch;
    for (int j = 0; j <= n_along; ++j)
        axis.push_back(cylinder_id(n_around, j, 0));
    for (int i = 0; i <= 3; ++i)
        branch.push_back(cylinder_id(n_around, j0, i));
    auto seam = polyline(input, axis);
    const auto slit = polyline(input, branch);
    seam.insert(seam.end(), slit.begin(), slit.end());
    // Axis: every vertex gets one copy, except the junction which has 3 fans (2 copies); slit:
    // one copy for each of its 2 inner vertices, none for its tip.
    const Mesh mesh = cut_and_check(input, seam, 1, 1, (n_along + 1) + 1 + 2);
    const VertexHandle junction(cylinder_id(n_around, j0, 0));
    auto origin = origin_map(mesh);
    int copies = 0;
    for (auto v : mesh.vertices())
        copies += origin[v.idx()] == junction.idx();
    CHECK(copies == 3);
}

TEST_CASE("cut: sphere with three holes cut along a tree of paths becomes a disk")
{
    const Mesh input = sphere_with_holes({{0, 0, 1}, {1, 0, -0.6}, {-1, 0.2, -0.6}});
    check_mesh(input);
    REQUIRE(euler_characteristic(input) == -1);
    const auto loops = loop_vertices(input);
    REQUIRE(loops.size() == 3);
    std::set<int> all_boundary;
    for (const auto& loop : loops)
        all_boundary.insert(loop.begin(), loop.end());

    // Hole 0 to hole 1, then hole 2 to an inner vertex of that path: a Y with an interior junction.
    std::set<int> blocked = all_boundary;
    for (int v : loops[1])
        blocked.erase(v);
    const auto path01 = bfs_path(input, loops[0], loops[1], blocked);
    REQUIRE(path01.size() >= 3);
    const std::set<int> inner(path01.begin() + 1, path01.end() - 1);
    blocked = all_boundary;
    for (int v : loops[2])
        blocked.erase(v);
    const auto path2 = bfs_path(input, loops[2], inner, blocked);
    auto seam = polyline(input, path01);
    const auto branch = polyline(input, path2);
    seam.insert(seam.end(), branch.begin(), branch.end());

    // One copy per seam vertex (all ends are on holes), plus a second one for the junction, which
    // has 3 fans; the junction is the last vertex of path2 and also a vertex of path01.
    const int expected = static_cast<int>(path01.size() + path2.size());
    cut_and_check(input, seam, 1, 1, expected);
}

TEST_CASE("cut: interior slit on a plane grid opens into a hole")
{
    const int n = 8;
    const Mesh input = plane_grid(1.0, n);
    REQUIRE(euler_characteristic(input) == 1);
    std::vector<int> row;
    for (int i = 2; i <= 6; ++i)
        row.push_back(grid_id(n, 4, i));
    // 4 edges, 3 inner vertices duplicated, tips kept: V - E + F drops from 1 to 0 (an annulus).
    cut_and_check(input, polyline(input, row), 0, 2, 3);
}

TEST_CASE("cut: seam touching the boundary at one end only")
{
    const int n = 8;
    const Mesh input = plane_grid(1.0, n);
    std::vector<int> row;
    for (int i = 0; i <= 4; ++i)
        row.push_back(grid_id(n, 4, i));
    cut_and_check(input, polyline(input, row), 1, 1, 4);
}

TEST_CASE("cut: seam from boundary to boundary splits a grid in two")
{
    const int n = 6;
    const Mesh input = plane_grid(1.0, n);
    std::vector<int> row;
    for (int i = 0; i <= n; ++i)
        row.push_back(grid_id(n, 3, i));
    cut_and_check(input, polyline(input, row), 2, 2, n + 1);
}

TEST_CASE("cut: a single edge whose endpoints are both on the boundary")
{
    SUBCASE("one quad")
    {
        const Mesh input = plane_grid(1.0, 1);
        cut_and_check(input, {edge_between(input, grid_id(1, 0, 0), grid_id(1, 1, 1))}, 2, 2, 2);
    }
    SUBCASE("corner triangle of a larger grid")
    {
        const int n = 4;
        const Mesh input = plane_grid(1.0, n);
        const auto e = edge_between(input, grid_id(n, 0, n - 1), grid_id(n, 1, n));
        cut_and_check(input, {e}, 2, 2, 2);
    }
    SUBCASE("edge across a cylinder from rim to rim")
    {
        const Mesh input = open_cylinder(1.0, 1.0, 8, 1);
        const auto e = edge_between(input, cylinder_id(8, 0, 2), cylinder_id(8, 1, 2));
        cut_and_check(input, {e}, 1, 1, 2);
    }
}

TEST_CASE("cut: two seams meeting at a boundary vertex give it three fans")
{
    const int n = 8;
    const Mesh input = plane_grid(1.0, n);
    auto seam = polyline(input, {grid_id(n, 0, 4), grid_id(n, 1, 4), grid_id(n, 2, 4)});
    const auto diagonal = polyline(input, {grid_id(n, 0, 4), grid_id(n, 1, 5), grid_id(n, 2, 6)});
    seam.insert(seam.end(), diagonal.begin(), diagonal.end());
    // Boundary vertex: 3 fans (+2); inner path vertices +1 each; both tips +0.
    cut_and_check(input, seam, 1, 1, 4);
}

TEST_CASE("cut: torus cut along a meridian and a longitude becomes a disk")
{
    const int n_major = 10, n_minor = 6;
    const Mesh input = torus(3.0, 1.0, n_major, n_minor);
    REQUIRE(euler_characteristic(input) == 0);
    std::vector<int> meridian, longitude;
    for (int j = 0; j <= n_minor; ++j)
        meridian.push_back(j % n_minor);  // i = 0
    for (int i = 0; i <= n_major; ++i)
        longitude.push_back((i % n_major) * n_minor);  // j = 0
    auto seam = polyline(input, meridian);
    const auto other = polyline(input, longitude);
    seam.insert(seam.end(), other.begin(), other.end());
    // Closed seam loops: every vertex gets one copy, the crossing (4 fans) three.
    cut_and_check(input, seam, 1, 1, (n_minor - 1) + (n_major - 1) + 3);
}

TEST_CASE("cut: a second cut keeps the origin of the first input")
{
    const int n_around = 10, n_along = 6;
    const Mesh input = open_cylinder(1.0, 2.0, n_around, n_along);
    std::vector<int> line;
    for (int j = 0; j <= n_along; ++j)
        line.push_back(cylinder_id(n_around, j, 0));
    Mesh once = input;
    const auto seam = polyline(once, line);
    cut_along_edges(once, seam);
    // Slit on the ring j = 3, away from the first seam.
    const auto slit = polyline(once, {cylinder_id(n_around, 3, 3), cylinder_id(n_around, 3, 4),
                                      cylinder_id(n_around, 3, 5)});
    const CutSummary summary = cut_along_edges(once, slit);
    CHECK(summary.duplicated_vertices == 1);
    check_mesh(once);
    CHECK(euler_characteristic(once) == 0);
    CHECK(count_boundary_loops(once) == 2);
    check_origin(input, once);
    // Edges and vertices away from the first seam keep their ids, so the slit is also a seam of
    // the input and both cuts together must match one rebuild of the input.
    auto both = seam;
    both.insert(both.end(), slit.begin(), slit.end());
    check_against_rebuild(input, both, once);
}

TEST_CASE("cut: empty seam only creates the origin map")
{
    Mesh mesh = plane_grid(1.0, 2);
    const CutSummary summary = cut_along_edges(mesh, {});
    CHECK(summary.seam_edges == 0);
    CHECK(summary.duplicated_vertices == 0);
    auto origin = origin_map(mesh);
    for (auto v : mesh.vertices())
        CHECK(origin[v.idx()] == v.idx());
}

TEST_CASE("cut: invalid seams are rejected before the mesh changes")
{
    const int n = 4;
    Mesh mesh = plane_grid(1.0, n);
    const auto inner = edge_between(mesh, grid_id(n, 2, 1), grid_id(n, 2, 2));
    const auto border = edge_between(mesh, grid_id(n, 0, 1), grid_id(n, 0, 2));
    const auto n_edges = mesh.n_edges();

    CHECK_THROWS_AS(cut_along_edges(mesh, {EdgeHandle()}), InvalidInputError);
    CHECK_THROWS_AS(cut_along_edges(mesh, {EdgeHandle(static_cast<int>(n_edges))}),
                    InvalidInputError);
    CHECK_THROWS_AS(cut_along_edges(mesh, {inner, inner}), InvalidInputError);
    CHECK_THROWS_AS(cut_along_edges(mesh, {inner, border}), InvalidInputError);
    CHECK_THROWS_WITH_AS(cut_along_edges(mesh, {border}),
                         doctest::Contains("cut_along_edges: seam edge is already on the boundary"),
                         InvalidInputError);
    CHECK(mesh.n_edges() == n_edges);
    CHECK(mesh.n_vertices() == (n + 1) * (n + 1));
    CHECK_FALSE(OpenMesh::hasProperty<OpenMesh::VertexHandle, int>(mesh, prop::origin));

    SUBCASE("origin property of the wrong type")
    {
        auto wrong = OpenMesh::VProp<double>(mesh, prop::origin);
        CHECK_THROWS_AS(cut_along_edges(mesh, {inner}), InvalidInputError);
    }
    SUBCASE("an edge that a previous cut opened")
    {
        cut_along_edges(mesh, {inner});
        CHECK_THROWS_AS(cut_along_edges(mesh, {inner}), InvalidInputError);
    }
}
