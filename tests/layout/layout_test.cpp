#include <doctest/doctest.h>

#include "vessel/cut/boundary.h"
#include "vessel/cut/cut.h"
#include "vessel/cut/cut_cost.h"
#include "vessel/cut/cut_plan.h"
#include "vessel/core/errors.h"
#include "vessel/direction/geodesic.h"
#include "vessel/layout/layout.h"
#include "vessel/phantom/phantom.h"
#include "vessel/core/properties.h"

using namespace vessel;

TEST_CASE("layout: a cut cylinder unrolls its rims as straight lines of their own length")
{
    const double radius = 1.0, length = 5.0;
    Mesh mesh = open_cylinder(radius, length, 32, 20);
    const auto loops = boundary_loops(mesh);
    const Eigen::VectorXd G = heat_geodesic_distance(mesh, loops[0].vertices);
    CutPlanOptions shortest;
    shortest.route = CutRoute::ShortestPath;  // no stream field here
    const CutPlan plan = plan_cuts(mesh, loops, evaluate_cost(mesh, LengthCost{1.0}),
                                   Eigen::MatrixX3d(), shortest);
    const std::size_t n_before = mesh.n_vertices();
    cut_along_edges(mesh, plan.seam_edges(mesh));

    std::vector<int> loop_of(n_before, -1);
    for (std::size_t l = 0; l < loops.size(); ++l)
        for (auto v : loops[l].vertices)
            loop_of[v.idx()] = static_cast<int>(l);
    LayoutInput input;
    input.mesh = &mesh;
    input.loops = &loops;
    input.plan = &plan;
    input.geodesic = &G;
    auto origin = OpenMesh::VProp<int>(mesh, prop::origin);
    for (auto v : mesh.vertices())
        input.origin.push_back(origin[v]);
    input.segments = boundary_segments(mesh, input.origin, loop_of);

    REQUIRE(input.segments.size() == 2);
    CHECK(input.segments[0].loop == 0);  // the walk starts on the inlet
    CHECK(input.segments[1].loop == 1);
    for (const auto& seg : input.segments)
    {
        CHECK(seg.arc_length.back() == doctest::Approx(loops[seg.loop].arc_length));
        CHECK(seg.vertices.size() == loops[seg.loop].vertices.size() + 1);  // opened at one vertex
        CHECK(origin[seg.vertices.front()] == origin[seg.vertices.back()]);
    }

    const LayoutResult placed = BranchFanLayout(45.0).place(input);
    REQUIRE(placed.inlet.size() == input.segments[0].vertices.size());
    REQUIRE(placed.outlets.size() == input.segments[1].vertices.size());
    const double perimeter = loops[0].arc_length;
    // The inlet lies on the u axis, centred, walked from right to left (clockwise boundary).
    CHECK(placed.inlet.front().uv.x() == doctest::Approx(0.5 * perimeter));
    CHECK(placed.inlet.back().uv.x() == doctest::Approx(-0.5 * perimeter));
    for (const auto& pin : placed.inlet)
        CHECK(pin.uv.y() == doctest::Approx(0.0));
    // The outlet is parallel, at the geodesic height of the cut, walked left to right.
    CHECK(placed.outlets.front().uv.x() == doctest::Approx(-0.5 * perimeter));
    for (const auto& pin : placed.outlets)
        CHECK(pin.uv.y() == doctest::Approx(length).epsilon(0.05));
}

TEST_CASE("layout: unknown names and bad angles are refused")
{
    CHECK_THROWS_AS(make_layout("spiral"), InvalidInputError);
    CHECK_THROWS_AS(BranchFanLayout(95.0), InvalidInputError);
    CHECK(make_layout("fan", 30.0)->name() == "fan");
}
