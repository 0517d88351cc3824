#include <doctest/doctest.h>

#include "vessel/cut/boundary.h"
#include "vessel/cut/cut.h"
#include "vessel/core/errors.h"
#include "vessel/phantom/phantom.h"
#include "vessel/pipeline.h"
#include "vessel/cut/relief_cut.h"

#include <cmath>
#include <set>

using namespace vessel;

namespace {

// An open tube (inlet z = 0, outlet z = 20) with a lateral sac: the radius swells by a Gaussian
// bump of relative height \p bulge around angle 0, half-way along. With bulge ~4 the sac is a
// cap that a map without a slit in it must squeeze.
Mesh tube_with_sac(double bulge)
{
    Mesh mesh = open_cylinder(1.0, 20.0, 64, 160);
    for (auto v : mesh.vertices())
    {
        auto p = mesh.point(v);
        const double angle = std::atan2(p[1], p[0]);
        const double dz = (p[2] - 10.0) / 2.0;
        const double scale = 1.0 + bulge * std::exp(-(angle * angle) / 0.5 - dz * dz);
        mesh.set_point(v, OpenMesh::Vec3d(p[0] * scale, p[1] * scale, p[2]));
    }
    return mesh;
}

// The seam of a straight cut of an open cylinder along its vertices at angle pi (any column).
CutPlan straight_cut(const Mesh& mesh, const std::vector<BoundaryLoop>& loops)
{
    // Walk from the outlet loop's vertex nearest angle pi down to the inlet, edge by edge.
    VertexHandle v;
    double best = -1e9;
    for (auto w : loops[1].vertices)
        if (-mesh.point(w)[0] > best)
        {
            best = -mesh.point(w)[0];
            v = w;
        }
    CutPath path;
    path.outlet = 1;
    path.start = v;
    std::set<int> inlet;
    for (auto w : loops[0].vertices)
        inlet.insert(w.idx());
    // Toward the inlet (the loops of an open cylinder are equally long: either may be loop 0).
    const double toward = mesh.point(loops[0].vertices.front())[2] < mesh.point(v)[2] ? -1 : 1;
    while (!inlet.count(v.idx()))
    {
        HalfedgeHandle step;
        double gained = 1e-9;
        for (auto h : mesh.voh_range(v))
        {
            const auto p = mesh.point(h.to());
            const double dz = toward * (p[2] - mesh.point(v)[2]);
            if (dz > gained && std::abs(p[1]) < 1e-6)
            {
                gained = dz;
                step = h;
            }
        }
        REQUIRE(step.is_valid());
        path.halfedges.push_back(step);
        v = mesh.to_vertex_handle(step);
    }
    path.end = v;
    CutPlan plan;
    plan.paths.push_back(path);
    return plan;
}

}  // namespace

TEST_CASE("relief cut: starts at the most compressed vertex away from the seam and ends on it")
{
    const Mesh mesh = tube_with_sac(0.0);
    const auto loops = boundary_loops(mesh);
    const CutPlan plan = straight_cut(mesh, loops);
    // A compression well at the vertex opposite the seam, half-way up.
    VertexHandle target;
    double best = 1e9;
    for (auto v : mesh.vertices())
    {
        const auto p = mesh.point(v);
        const double d = std::hypot(p[0] - 1.0, p[1], p[2] - 10.0);
        if (d < best)
        {
            best = d;
            target = v;
        }
    }
    Eigen::VectorXd log_area(mesh.n_vertices());
    for (auto v : mesh.vertices())
        log_area[v.idx()] = -std::exp(-(mesh.point(v) - mesh.point(target)).sqrnorm());
    // A deeper well right beside the seam must be passed over (min_rings).
    const VertexHandle beside = mesh.to_vertex_handle(mesh.next_halfedge_handle(
        mesh.opposite_halfedge_handle(plan.paths[0].halfedges[80])));
    log_area[beside.idx()] = -10.0;

    const auto relief = plan_relief_cut(mesh, loops, plan, log_area, 5);
    REQUIRE(relief.has_value());
    CHECK(relief->start == target);
    CHECK(relief->outlet == -1);
    CHECK(relief->parent == 0);  // it ends on the cut
    CHECK(std::abs(mesh.point(relief->end)[0] + 1.0) < 1e-6);
    // Shortest: half-way round the tube (pi) plus at most a few edges of slack.
    double length = 0;
    for (auto h : relief->halfedges)
        length += mesh.calc_edge_length(mesh.edge_handle(h));
    CHECK(length < M_PI * 1.1);

    // Cutting the seam and the slit leaves a disk: one boundary loop, Euler characteristic 1.
    CutPlan with = plan;
    with.relief.push_back(*relief);
    Mesh cut = mesh;
    cut_along_edges(cut, with.seam_edges(cut));
    CHECK(boundary_loops(cut).size() == 1);
    const long euler = static_cast<long>(cut.n_vertices()) - static_cast<long>(cut.n_edges()) +
                       static_cast<long>(cut.n_faces());
    CHECK(euler == 1);
}

TEST_CASE("relief cut: none when no vertex is far enough from the seam and options are validated")
{
    const Mesh mesh = open_cylinder(1.0, 1.0, 8, 2);
    const auto loops = boundary_loops(mesh);
    const CutPlan plan = straight_cut(mesh, loops);
    const Eigen::VectorXd log_area = Eigen::VectorXd::Zero(mesh.n_vertices());
    CHECK_FALSE(plan_relief_cut(mesh, loops, plan, log_area, 5).has_value());
    CHECK_THROWS_AS(plan_relief_cut(mesh, loops, plan, Eigen::VectorXd(3), 5), InvalidInputError);

    ReliefCutOptions options;
    options.max_cuts = -1;
    CHECK_THROWS_AS(options.validate(), InvalidInputError);
    options = {};
    options.target_mean_abs_log_area = std::nan("");
    CHECK_THROWS_AS(options.validate(), InvalidInputError);
}

TEST_CASE("relief cut: a tube with a lateral sac opens the sac and lowers the area distortion")
{
    FlattenOptions without;
    without.relief.max_cuts = 0;
    const FlattenResult plain = flatten(tube_with_sac(4.0), without);
    REQUIRE(plain.quality.flipped_triangles == 0);

    FlattenOptions with;
    with.relief.target_mean_abs_log_area = 0.0;  // always try, to see what one slit does
    with.relief.max_cuts = 1;
    const FlattenResult relieved = flatten(tube_with_sac(4.0), with);
    MESSAGE("sac: mean |log area| " << plain.quality.mean_abs_log_area << " without, "
                                    << relieved.quality.mean_abs_log_area << " with "
                                    << relieved.plan.relief.size() << " relief cut(s)");
    REQUIRE(relieved.plan.relief.size() == 1);
    CHECK(relieved.quality.flipped_triangles == 0);
    CHECK(relieved.quality.overlapping_triangles <= plain.quality.overlapping_triangles);
    CHECK(relieved.quality.mean_abs_log_area < 0.8 * plain.quality.mean_abs_log_area);
    // The slit starts in the sac (where the radius swelled), not on the plain tube.
    const auto p = relieved.mesh.point(relieved.plan.relief[0].start);
    CHECK(std::hypot(p[0], p[1]) > 1.5);
    // Still one disk.
    CHECK(boundary_loops(relieved.mesh).size() == 1);
}
