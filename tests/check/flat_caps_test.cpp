#include <doctest/doctest.h>

#include "detail/flat_caps.h"
#include "support/checks.h"
#include "support/meshes.h"
#include "vessel/check/validation.h"
#include "vessel/core/properties.h"
#include "vessel/cut/boundary.h"
#include "vessel/io/io.h"
#include "vessel/phantom/phantom.h"

#include <algorithm>
#include <array>
#include <string>
#include <vector>

using namespace vessel;
using vessel::test::refusal;

namespace {

const std::string kData = VESSEL_SHARED_DATA;

// open_cylinder(1, 4, 12, 6) (144 faces, two loops of 12) with each end closed by a fan of 12
// triangles round a new vertex on the loop's plane (cap_loops_except()): two flat caps. The fan's
// vertex at the end z = 4 moved \p top out of its plane along the axis, and the one at z = 0
// \p bottom: a cone, no flat cap.
RawMesh capped_tube(double top = 0.0, double bottom = 0.0)
{
    RawMesh raw = test::cap_loops_except(open_cylinder(1.0, 4.0, 12, 6), -1);
    for (std::size_t c = raw.points.size() - 2; c < raw.points.size(); ++c)
        raw.points[c].z() += raw.points[c].z() > 2.0 ? top : -bottom;
    return raw;
}

TreeSurfaceOptions removing_caps()
{
    TreeSurfaceOptions options;
    options.remove_flat_caps = true;
    return options;
}

// The multiset of a surface's vertex positions.
std::vector<std::array<double, 3>> positions(const Mesh& mesh)
{
    std::vector<std::array<double, 3>> out;
    for (const VertexHandle v : mesh.vertices())
        out.push_back({mesh.point(v)[0], mesh.point(v)[1], mesh.point(v)[2]});
    std::sort(out.begin(), out.end());
    return out;
}

}  // namespace

TEST_CASE("flat caps: a tube closed by two flat caps opens at both ends")
{
    const RawMesh raw = capped_tube();
    const std::string closed = refusal(raw, {});
    CHECK(closed.find("the surface is closed") != std::string::npos);
    CHECK(closed.find("--remove-caps") != std::string::npos);

    TreeSurface s = make_tree_surface(raw, removing_caps());
    CHECK(s.removed_caps == 2);
    CHECK(s.mesh.n_faces() == 144);
    CHECK(s.mesh.n_vertices() == 84);
    CHECK(boundary_loops(s.mesh).size() == 2);
    // The wall's vertices keep their input indices (point data still match); the centres are
    // left unused.
    const auto input_index = OpenMesh::VProp<int>(s.mesh, prop::input_index);
    int largest = -1;
    for (const VertexHandle v : s.mesh.vertices())
    {
        CHECK(s.mesh.point(v) == to_openmesh(raw.points[input_index[v]]));
        largest = std::max(largest, input_index[v]);
    }
    CHECK(largest == 83);
    REQUIRE(s.notes.size() >= 2);
    CHECK(s.notes[0].rfind("removed 2 flat caps (24 faces; areas ", 0) == 0);
    CHECK(s.notes[1] == "ignored 2 vertices not used by any face");
}

TEST_CASE("flat caps: a cone is no flat cap and stays")
{
    const TreeSurface s = make_tree_surface(capped_tube(0.5), removing_caps());
    CHECK(s.removed_caps == 1);
    CHECK(s.mesh.n_faces() == 144 + 12);
    CHECK(boundary_loops(s.mesh).size() == 1);  // one open end: a disk

    // Both ends cones: nothing to remove, and the refusal says so.
    const std::string message = refusal(capped_tube(0.5, 0.5), removing_caps());
    CHECK(message.find("has no flat cap to remove") != std::string::npos);
}

TEST_CASE("flat caps: the capped real models open to their published open surfaces")
{
    // SimVascular's demo model: its 3 caps are the cells of ModelFaceID 3, 4 and 5 (145
    // triangles; MANIFEST.md), removed there by that label to make demo-model-open.ply.
    const TreeSurface demo = make_tree_surface(
        read_raw_mesh(kData + "/simvascular-tests/demo-model-capped.ply"), removing_caps());
    const TreeSurface open = load_tree_surface(kData + "/simvascular-tests/demo-model-open.ply");
    CHECK(demo.removed_caps == 3);
    CHECK(demo.mesh.n_faces() == open.mesh.n_faces());
    CHECK(demo.mesh.n_vertices() == open.mesh.n_vertices());
    CHECK(positions(demo.mesh) == positions(open.mesh));
    CHECK(boundary_loops(demo.mesh).size() == 3);

    // SPHinXsys' carotid bifurcation: flat caps of 30.9, 14.8 and 7.2 mm^2 (MANIFEST.md).
    const RawMesh carotid = read_raw_mesh(kData + "/sphinxsys-medical/carotid-bif-capped.stl");
    const TreeSurface bif = make_tree_surface(carotid, removing_caps());
    CHECK(bif.removed_caps == 3);
    CHECK(boundary_loops(bif.mesh).size() == 3);
    std::vector<std::array<int, 3>> triangles;
    for (const auto& f : carotid.faces)
        triangles.push_back({f[0], f[1], f[2]});
    std::vector<detail::FlatCap> caps = detail::find_flat_caps(
        carotid.points, triangles, detail::kFlatCapCoplanarDeg, detail::kFlatCapMinRimDeg,
        detail::kFlatCapMeanRimDeg, detail::kFlatCapMinRimEdges);
    REQUIRE(caps.size() == 3);
    std::sort(caps.begin(), caps.end(),
              [](const auto& a, const auto& b) { return a.area > b.area; });
    CHECK(caps[0].area == doctest::Approx(30.9).epsilon(0.005));
    CHECK(caps[1].area == doctest::Approx(14.8).epsilon(0.005));
    CHECK(caps[2].area == doctest::Approx(7.2).epsilon(0.005));
    for (const auto& cap : caps)
        CHECK(cap.mean_rim_angle_deg > 60.0);
}

TEST_CASE("flat caps: no real open tree loses a face, nor a curved cap")
{
    // Flat stretches of the wall (Glenn's 92-face one), slivers in the crease between two
    // walls (the demo model's) and coarse walls (the coronary phantom's) are no caps.
    for (const char* name :
         {"svfsi-tests/pulmonary-glenn-wall.ply", "simvascular-tests/demo-model-open.ply",
          "vampy/artery.ply", "vampy/artery-coarse.ply",
          "vmtk-old-website/aneurisk-id1-lateral-aneurysm.ply",
          "vmtk-test-data/aorta-surface-open-ends.ply",
          "x-ray-angio-data/coronary-clinical-branch-fine.ply",
          "x-ray-angio-data/coronary-phantom-tri3-coarse.ply"})
    {
        CAPTURE(name);
        const RawMesh raw = read_raw_mesh(kData + "/" + name);
        const TreeSurface plain = make_tree_surface(raw);
        const TreeSurface s = make_tree_surface(raw, removing_caps());
        CHECK(s.removed_caps == 0);
        CHECK(s.mesh.n_faces() == plain.mesh.n_faces());
        CHECK(s.notes == plain.notes);
    }
    // vmtk's capped aorta: its caps are domes (no planar patch; MANIFEST.md).
    const std::string message =
        refusal(read_raw_mesh(kData + "/vmtk-test-data/aorta-surface.ply"), removing_caps());
    CHECK(message.find("has no flat cap to remove") != std::string::npos);
}
