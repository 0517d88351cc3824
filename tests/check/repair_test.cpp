#include <doctest/doctest.h>

#include "support/meshes.h"
#include "vessel/cut/boundary.h"
#include "vessel/phantom/phantom.h"
#include "vessel/check/repair.h"
#include "vessel/check/validation.h"
#include "vessel/core/errors.h"

#include <algorithm>

using namespace vessel;

namespace {

// open_cylinder(1, 4, 12, 6): 7 rings of 12 vertices, 144 triangles.
RawMesh tube() { return to_raw_mesh(open_cylinder(1.0, 4.0, 12, 6)); }

// The repaired mesh must be a valid tree surface: a tube (2 loops, 144 faces).
void check_valid_tube(const RawMesh& raw)
{
    const TreeSurface s = make_tree_surface(raw);
    CHECK(s.mesh.n_faces() == 144);
    CHECK(s.mesh.n_vertices() == 84);
    CHECK(boundary_loops(s.mesh).size() == 2);
}

}  // namespace

TEST_CASE("repair: a clean mesh is left exactly as it was")
{
    const RawMesh raw = tube();
    const RepairedMesh r = repair_raw_mesh(raw);
    CHECK(r.mesh.points == raw.points);
    CHECK(r.mesh.faces == raw.faces);
    CHECK(r.summary.notes().empty());
}

TEST_CASE("repair: a duplicate face is removed and counted")
{
    RawMesh raw = tube();
    raw.faces.push_back({raw.faces[30][2], raw.faces[30][1], raw.faces[30][0]});  // reversed copy
    const RepairedMesh r = repair_raw_mesh(raw);
    CHECK(r.summary.duplicate_faces == 1);
    REQUIRE(r.summary.notes().size() == 1);
    CHECK(r.summary.notes()[0] == "repair: removed 1 duplicate face");
    check_valid_tube(r.mesh);
}

TEST_CASE("repair: a face wound against its neighbours is reversed")
{
    RawMesh raw = tube();
    std::swap(raw.faces[30][1], raw.faces[30][2]);
    const RepairedMesh r = repair_raw_mesh(raw);
    CHECK(r.summary.reoriented_faces == 1);
    CHECK(r.summary.split_vertices == 0);
    check_valid_tube(r.mesh);
}

TEST_CASE("repair: degenerate faces are removed (repeated corner, coincident corners)")
{
    SUBCASE("a face repeating a vertex")
    {
        RawMesh raw = tube();
        raw.faces.push_back({3, 3, 4});
        const RepairedMesh r = repair_raw_mesh(raw);
        CHECK(r.summary.degenerate_faces == 1);
        check_valid_tube(r.mesh);
    }
    SUBCASE("two corners at the same position: the zero-length edge is collapsed")
    {
        RawMesh raw = tube();
        // Vertex 40 (ring 3) moved onto vertex 41: the two faces on edge (40, 41) have no area.
        raw.points[40] = raw.points[41];
        const RepairedMesh r = repair_raw_mesh(raw);
        CHECK(r.summary.degenerate_faces == 2);
        const TreeSurface s = make_tree_surface(r.mesh);
        CHECK(s.mesh.n_faces() == 142);
        CHECK(boundary_loops(s.mesh).size() == 2);
    }
}

TEST_CASE("repair: a tube split along a ring with duplicated vertices is stitched")
{
    const RawMesh raw = vessel::test::split_tube();
    const RepairedMesh r = repair_raw_mesh(raw);
    CHECK(r.summary.stitched_edges == 12);
    CHECK(r.summary.removed_vertices == 12);
    // One of each coincident pair is kept, and the kept vertices stay in input order.
    REQUIRE(r.mesh.points.size() == 84);
    std::size_t next = 0;
    for (const auto& p : r.mesh.points)
    {
        while (next < raw.points.size() && raw.points[next] != p)
            ++next;
        CHECK(next < raw.points.size());
        ++next;
    }
    check_valid_tube(r.mesh);
}

TEST_CASE("repair: a mesh with a NaN coordinate is returned unchanged for the validation")
{
    RawMesh raw = tube();
    raw.points[4].x() = std::nan("");
    raw.faces.push_back(raw.faces[0]);
    const RepairedMesh r = repair_raw_mesh(raw);
    CHECK(r.mesh.faces == raw.faces);
    CHECK(r.summary.notes().empty());
}

TEST_CASE("repair: holes below fill_holes_below are filled, the vessel ends are kept")
{
    const RawMesh raw = vessel::test::tube_with_holes(24, 30, 5);
    RepairOptions options;
    options.fill_holes_below = 2.0;  // the holes are about 0.9 around, the rims 6.28
    const RepairedMesh r = repair_raw_mesh(raw, options);
    CHECK(r.summary.filled_holes == 5);
    CHECK(r.summary.unfilled_holes == 0);
    CHECK(r.summary.hole_faces >= 5);
    CHECK(r.summary.longest_filled_hole < 2.0);
    CHECK(r.summary.removed_vertices == 0);
    CHECK(r.mesh.points.size() == raw.points.size() + r.summary.hole_vertices);
    for (std::size_t i = 0; i < raw.points.size(); ++i)  // input order kept, new ones after
        CHECK(r.mesh.points[i] == raw.points[i]);
    const auto notes = r.summary.notes();
    REQUIRE(notes.size() == 1);
    CHECK(notes[0].rfind("repair: filled 5 holes (perimeter up to 0.", 0) == 0);
    const TreeSurface s = make_tree_surface(r.mesh);
    CHECK(boundary_loops(s.mesh).size() == 2);
    CHECK(s.mesh.n_faces() == raw.faces.size() + r.summary.hole_faces);

    // Below the holes' perimeter nothing is filled; a negative perimeter is refused.
    options.fill_holes_below = 0.5;
    CHECK(repair_raw_mesh(raw, options).summary.filled_holes == 0);
    options.fill_holes_below = -1.0;
    CHECK_THROWS_AS(repair_raw_mesh(raw, options), InvalidInputError);
}
