#include <doctest/doctest.h>

#include "detail/edge_groups.h"
#include "support/checks.h"
#include "support/meshes.h"
#include "vessel/check/validation.h"
#include "vessel/core/errors.h"
#include "vessel/core/properties.h"
#include "vessel/cut/boundary.h"
#include "vessel/io/io.h"
#include "vessel/phantom/phantom.h"

#include <algorithm>
#include <array>
#include <map>
#include <sstream>
#include <string>

using namespace vessel;
using namespace vessel::test;

TEST_CASE("validation: edge groups hold each corner once, under its edge, in edge order")
{
    // A real mesh (irregular valences, boundary and interior edges) and a non-manifold fin.
    const RawMesh raw =
        read_raw_mesh(std::string(VESSEL_SHARED_DATA) + "/simvascular-tests/demo-model-open.ply");
    std::vector<std::array<int, 3>> T;
    for (const auto& f : raw.faces)
        T.push_back({f[0], f[1], f[2]});
    T.push_back({T[100][1], T[100][0], static_cast<int>(raw.points.size()) - 1});
    const detail::EdgeGroups groups = detail::edge_groups(T, raw.points.size());
    std::map<std::array<int, 2>, std::vector<int>> expected;  // by (smaller, larger) vertex
    for (int c = 0; c < static_cast<int>(3 * T.size()); ++c)
    {
        const int a = T[c / 3][c % 3], b = T[c / 3][(c % 3 + 1) % 3];
        expected[{std::min(a, b), std::max(a, b)}].push_back(c);
    }
    REQUIRE(groups.size() == expected.size());
    REQUIRE(groups.start.size() == groups.size() + 1);
    std::size_t e = 0;
    int three = 0;
    for (const auto& [edge, corners] : expected)
    {
        CHECK(groups.edge[e] == edge);
        CHECK(std::vector<int>(groups.begin(e), groups.begin(e) + groups.count(e)) == corners);
        three += groups.count(e) == 3;
        ++e;
    }
    CHECK(three == 1);
}

TEST_CASE("validation: a tube is a valid tree surface and keeps input indices")
{
    const RawMesh raw = to_raw_mesh(open_cylinder(1.0, 4.0, 16, 8));
    const TreeSurface s = make_tree_surface(raw);
    CHECK(s.mesh.n_vertices() == raw.points.size());
    CHECK(s.mesh.n_faces() == raw.faces.size());
    CHECK(s.notes.empty());
    auto index = OpenMesh::VProp<int>(const_cast<Mesh&>(s.mesh), prop::input_index);
    for (auto v : s.mesh.vertices())
        CHECK((to_eigen(s.mesh.point(v)) - raw.points[index[v]]).norm() == 0.0);
}

TEST_CASE("validation: an inward-wound surface is turned outward with a note")
{
    RawMesh raw = to_raw_mesh(open_cylinder(1.0, 4.0, 16, 8));
    for (auto& f : raw.faces)
        std::swap(f[1], f[2]);
    const TreeSurface s = make_tree_surface(raw);
    REQUIRE(s.notes.size() == 1);
    CHECK(s.notes[0].find("inward") != std::string::npos);
    // Outward: the first face's normal points away from the axis.
    auto f = *s.mesh.faces().begin();
    const auto n = s.mesh.calc_face_normal(f);
    const auto c = s.mesh.calc_face_centroid(f);
    CHECK(n[0] * c[0] + n[1] * c[1] > 0.0);
}

TEST_CASE("validation: polygons are triangulated with a note, or refused by option")
{
    RawMesh raw = to_raw_mesh(open_cylinder(1.0, 4.0, 16, 8));
    // Merge the first two triangles (a quad of the cylinder) back into one quad.
    raw.faces[0] = {raw.faces[0][0], raw.faces[0][1], raw.faces[0][2], raw.faces[1][2]};
    raw.faces.erase(raw.faces.begin() + 1);
    const TreeSurface s = make_tree_surface(raw);
    CHECK(s.mesh.n_faces() == raw.faces.size() + 1);
    REQUIRE(s.notes.size() == 1);
    CHECK(s.notes[0].find("triangulated 1 polygon") != std::string::npos);
    TreeSurfaceOptions strict;
    strict.triangulate_polygons = false;
    CHECK_THROWS_AS(make_tree_surface(raw, strict), InvalidInputError);
}

TEST_CASE("validation: faces wound against their neighbours are re-oriented with a note and a "
          "Moebius strip is refused")
{
    const RawMesh tube = to_raw_mesh(open_cylinder(1.0, 4.0, 16, 8));
    RawMesh patch = tube;  // faces 40-51: a patch of 12 faces across two rings
    for (int f = 40; f < 52; ++f)
        std::swap(patch.faces[f][1], patch.faces[f][2]);
    const TreeSurface s = make_tree_surface(patch);
    CHECK(s.reoriented_faces == 12);
    REQUIRE(s.notes.size() == 1);
    CHECK(s.notes[0] == "re-oriented 12 faces to agree with their neighbours");
    // Same faces, same winding as the tube's (outward): no face of the result differs.
    const TreeSurface reference = make_tree_surface(tube);
    REQUIRE(s.mesh.n_faces() == reference.mesh.n_faces());
    for (auto f : s.mesh.faces())
    {
        const auto normal = s.mesh.calc_face_normal(f);
        const auto expected = reference.mesh.calc_face_normal(reference.mesh.face_handle(f.idx()));
        CHECK((normal | expected) > 0.99);
    }

    RawMesh inward = patch;  // most faces wound inward: the patch is the majority's way round
    for (auto& f : inward.faces)
        std::swap(f[1], f[2]);
    const TreeSurface t = make_tree_surface(inward);
    CHECK(t.reoriented_faces == 12);
    REQUIRE(t.notes.size() == 2);
    CHECK(t.notes[1].find("wound inward") != std::string::npos);

    const std::string moebius = refusal(moebius_strip(24, 0.3));
    CHECK_MESSAGE(moebius.find("the surface is not orientable (like a Moebius strip): faces ") !=
                      std::string::npos,
                  moebius);
}

TEST_CASE("validation: a surface with one open end is accepted (a disk)")
{
    const TreeSurface s = make_tree_surface(blind_tube(1.0, 3.0, 24, 12, 6));
    CHECK(boundary_loops(s.mesh).size() == 1);
    CHECK(s.notes.empty());
    RawMesh one_hole = to_raw_mesh(icosphere(1.0, 1));
    one_hole.faces.pop_back();
    CHECK(boundary_loops(make_tree_surface(one_hole).mesh).size() == 1);
}

TEST_CASE("validation: every invalid class is refused with a message naming it")
{
    const RawMesh tube = to_raw_mesh(open_cylinder(1.0, 4.0, 16, 8));

    RawMesh nan = tube;
    nan.points[5].x() = std::nan("");
    CHECK(refusal(nan).find("vertex 5 has a NaN") != std::string::npos);

    RawMesh closed = to_raw_mesh(icosphere(1.0, 1));
    CHECK(refusal(closed).find("closed") != std::string::npos);

    RawMesh two = tube;
    const int offset = static_cast<int>(two.points.size());
    for (const auto& p : tube.points)
        two.points.push_back(p + Eigen::Vector3d(5, 0, 0));
    for (auto f : tube.faces)
    {
        for (int& i : f)
            i += offset;
        two.faces.push_back(f);
    }
    CHECK(refusal(two).find("2 connected components") != std::string::npos);

    RawMesh torus_mesh = to_raw_mesh(torus(3.0, 1.0, 24, 12));
    // Open the torus with two holes: remove two faces far apart -> genus 1 with 2 loops.
    torus_mesh.faces.erase(torus_mesh.faces.begin() + 300);
    torus_mesh.faces.erase(torus_mesh.faces.begin());
    CHECK(refusal(torus_mesh).find("genus 1") != std::string::npos);

    RawMesh flipped = tube;  // refused only when re-orienting is turned off
    std::swap(flipped.faces[10][1], flipped.faces[10][2]);
    TreeSurfaceOptions strict;
    strict.orient_consistently = false;
    CHECK(refusal(flipped, strict).find("inconsistent orientation") != std::string::npos);

    RawMesh fin = tube;  // a third face on an interior edge
    const int apex = static_cast<int>(fin.points.size());
    fin.points.push_back({0, 0, 10});
    fin.faces.push_back({fin.faces[128][1], fin.faces[128][0], apex});  // ring 4: interior edge
    {
        // Located by vertex ids and coordinates.
        const int a = std::min(fin.faces[128][0], fin.faces[128][1]);
        const int b = std::max(fin.faces[128][0], fin.faces[128][1]);
        std::ostringstream where;
        where << "non-manifold edge (" << a << ", " << b << ") (from (" << fin.points[a].x()
              << ", " << fin.points[a].y() << ", " << fin.points[a].z() << ") to ("
              << fin.points[b].x() << ", " << fin.points[b].y() << ", " << fin.points[b].z()
              << ")) is shared by 3 faces";
        CHECK_MESSAGE(refusal(fin).find(where.str()) != std::string::npos, refusal(fin));
    }

    RawMesh pinch = tube;  // a second tube touching the first at one vertex
    const int base = static_cast<int>(pinch.points.size());
    const Eigen::Vector3d shift = tube.points[0] - tube.points[8];
    for (const auto& p : tube.points)
        pinch.points.push_back(p + shift);
    for (auto f : tube.faces)
    {
        for (int& i : f)
            i = (i + base == base + 8) ? 0 : i + base;
        pinch.faces.push_back(f);
    }
    std::ostringstream pinch_at;
    pinch_at << "non-manifold vertex 0 at (" << tube.points[0].x() << ", " << tube.points[0].y()
             << ", " << tube.points[0].z() << "): its faces form several fans";
    CHECK_MESSAGE(refusal(pinch).find(pinch_at.str()) != std::string::npos, refusal(pinch));

    RawMesh degenerate = tube;
    degenerate.points.push_back(degenerate.points[0]);
    degenerate.points.push_back(degenerate.points[0]);
    const int n = static_cast<int>(degenerate.points.size());
    degenerate.faces.push_back({n - 2, n - 1, 0});
    CHECK(refusal(degenerate).find("degenerate") != std::string::npos);

    RawMesh repeated = tube;
    repeated.faces[3] = {1, 1, 2};
    CHECK(refusal(repeated).find("uses vertex 1 twice") != std::string::npos);

    RawMesh out_of_range = tube;
    out_of_range.faces[0][0] = 100000;
    CHECK(refusal(out_of_range).find("refers to vertex 100000") != std::string::npos);
}

TEST_CASE("validation: one-triangle holes in the wall are refused with a perimeter to fill "
          "them below, the ends of a coarse tube are vessel ends")
{
    const RawMesh raw = tube_with_holes(24, 30, 5);
    const std::string why = refusal(raw);
    CHECK_MESSAGE(why.find("5 boundary loops of at most 6 edges and under 0.5 times the largest "
                           "loop's perimeter") != std::string::npos, why);
    CHECK_MESSAGE(why.find("look like holes in the wall, not vessel ends") != std::string::npos,
                  why);
    const std::size_t at = why.find("--fill-holes ");
    REQUIRE(at != std::string::npos);
    const double fill = std::stod(why.substr(at + 13));
    // Accepted as they are with the rule off: 2 rims and 5 loops of 3 edges. The suggested
    // perimeter is above every hole's and below the rims'.
    TreeSurfaceOptions every_loop;
    every_loop.hole_max_edges = 0;
    const auto loops = boundary_loops(make_tree_surface(raw, every_loop).mesh);
    REQUIRE(loops.size() == 7);
    for (std::size_t i = 2; i < loops.size(); ++i)
    {
        CHECK(loops[i].halfedges.size() == 3);
        CHECK(loops[i].arc_length < fill);
    }
    CHECK(fill < loops[1].arc_length);
    CHECK(refusal(tube_with_holes(24, 30, 1)).find("1 boundary loop of at most 6 edges") !=
          std::string::npos);
    // 6 edges around both ends: short loops, but as long as the largest, so vessel ends.
    CHECK_NOTHROW(make_tree_surface(to_raw_mesh(open_cylinder(1.0, 4.0, 6, 4))));
}

TEST_CASE("validation: a vertex far from all others (a corrupt coordinate) is named, not the "
          "faces it makes look degenerate")
{
    RawMesh raw = to_raw_mesh(open_cylinder(1.0, 4.0, 16, 8));
    SUBCASE("one vertex at 1e38")
    {
        raw.points[30].x() = 1e38;
        const std::string why = refusal(raw);
        CHECK_MESSAGE(why.find("vertex 30 at (1e+38, ") != std::string::npos, why);
        CHECK_MESSAGE(why.find("times as far from the middle of the surface as its vertices "
                               "typically do") != std::string::npos, why);
        CHECK(why.find("degenerate") == std::string::npos);
    }
    SUBCASE("one vertex at -1e308 (the areas would overflow)")
    {
        raw.points[7].z() = -1e308;
        CHECK(refusal(raw).find("vertex 7 at (") != std::string::npos);
    }
    SUBCASE("three vertices at 1e6 on a tube of radius 1")
    {
        for (int v : {3, 40, 41})
            raw.points[v].y() = 1e6;
        const std::string why = refusal(raw);
        CHECK_MESSAGE(why.find("3 vertices lie over 1e+03 times as far") != std::string::npos, why);
        CHECK(why.find("the farthest vertex 3 at") != std::string::npos);
    }
    SUBCASE("off: the faces are then refused as degenerate")
    {
        raw.points[30].x() = 1e38;
        TreeSurfaceOptions off;
        off.far_vertex_factor = 0.0;
        CHECK(refusal(raw, off).find("degenerate") != std::string::npos);
    }
}

TEST_CASE("boundary: loops are sorted by arc length and follow the face winding")
{
    // A truncated cone: radius 2 at z = 0, radius 1 at z = 3.
    Mesh mesh = open_cylinder(1.0, 3.0, 24, 6);
    for (auto v : mesh.vertices())
    {
        auto p = mesh.point(v);
        const double scale = 2.0 - p[2] / 3.0;
        mesh.set_point(v, {p[0] * scale, p[1] * scale, p[2]});
    }
    const auto loops = boundary_loops(mesh);
    REQUIRE(loops.size() == 2);
    CHECK(loops[0].arc_length > loops[1].arc_length);
    CHECK(loops[0].arc_length == doctest::Approx(2 * 24 * 2.0 * std::sin(M_PI / 24)));
    CHECK(loops[0].centroid.z() == doctest::Approx(0.0));
    for (const auto& loop : loops)
        for (std::size_t i = 0; i < loop.halfedges.size(); ++i)
        {
            CHECK(mesh.is_boundary(loop.halfedges[i]));
            CHECK(mesh.to_vertex_handle(loop.halfedges[i]) ==
                  loop.vertices[(i + 1) % loop.vertices.size()]);
        }
}
