#include <doctest/doctest.h>

#include "vessel/cut/boundary.h"
#include "vessel/cut/cut_metrics.h"
#include "vessel/direction/direction.h"
#include "vessel/core/errors.h"
#include "vessel/direction/geodesic.h"
#include "vessel/phantom/phantom.h"

#include <cmath>

using namespace vessel;

namespace {

// A path along mesh edges from \p start, taking at each vertex the outgoing edge whose
// direction is closest to step(vertex), for \p n_edges edges.
template <class Step>
CutPath walk(const Mesh& mesh, VertexHandle start, Step step, int n_edges)
{
    CutPath path;
    path.start = start;
    VertexHandle at = start;
    for (int k = 0; k < n_edges; ++k)
    {
        HalfedgeHandle best;
        double best_cos = -2.0;
        for (auto h : mesh.voh_range(at))
        {
            const Eigen::Vector3d e = to_eigen(mesh.point(h.to()) - mesh.point(at));
            const double c = e.normalized().dot(step(at).normalized());
            if (c > best_cos)
            {
                best_cos = c;
                best = h;
            }
        }
        path.halfedges.push_back(best);
        at = mesh.to_vertex_handle(best);
    }
    path.end = at;
    return path;
}


}  // namespace

TEST_CASE("cut_metrics: harmonic longitudinal coordinate of a cylinder is linear along it")
{
    const Mesh mesh = open_cylinder(1.0, 6.0, 32, 24);
    const auto loops = boundary_loops(mesh);
    REQUIRE(loops.size() == 2);
    const Eigen::VectorXd G = heat_geodesic_distance(mesh, loops[0].vertices);
    const Eigen::VectorXd h = harmonic_longitudinal(mesh, loops, G);
    // 0 on the inlet, the outlet's mean distance there, linear in between.
    double outlet = 0.0;
    for (auto v : loops[1].vertices)
        outlet += G[v.idx()];
    outlet /= static_cast<double>(loops[1].vertices.size());
    const double inlet_z = mesh.point(loops[0].vertices.front())[2];
    for (auto v : mesh.vertices())
    {
        const double t = std::abs(mesh.point(v)[2] - inlet_z) / 6.0;
        CHECK(h[v.idx()] == doctest::Approx(t * outlet).epsilon(1e-6));
    }
    // Its descent runs along the axis, toward the inlet.
    const Eigen::MatrixX3d z = descent_direction(mesh, h);
    for (auto v : mesh.vertices())
        CHECK(std::abs(z(v.idx(), 2)) > 0.999);

    CHECK_THROWS_AS(harmonic_longitudinal(mesh, {loops[0]}, G), InvalidInputError);
    CHECK_THROWS_AS(harmonic_longitudinal(mesh, loops, G.head(3)), InvalidInputError);

    // In two steps (factor, then solve): the same bits, and the factor serves other distances.
    const HarmonicLongitudinal two_step(mesh, loops);
    CHECK(two_step.solve(G) == h);
    const Eigen::VectorXd doubled = 2.0 * G;
    CHECK(two_step.solve(doubled) == harmonic_longitudinal(mesh, loops, doubled));
    CHECK_THROWS_AS(two_step.solve(G.head(3)), InvalidInputError);
    CHECK_THROWS_AS(HarmonicLongitudinal(mesh, {loops[0]}), InvalidInputError);
}

TEST_CASE("cut_metrics: a cut along the cylinder is aligned, a cut around it is not")
{
    const Mesh mesh = open_cylinder(1.0, 6.0, 32, 24);
    const auto loops = boundary_loops(mesh);
    const Eigen::VectorXd G = heat_geodesic_distance(mesh, loops[0].vertices);
    const Eigen::MatrixX3d reference = descent_direction(mesh, harmonic_longitudinal(mesh, loops, G));
    const VertexHandle rim = loops[0].vertices.front();
    const double up = mesh.point(rim)[2] < 3.0 ? 1.0 : -1.0;
    const auto axial = [&](VertexHandle) { return Eigen::Vector3d(0, 0, up); };
    const auto around = [&](VertexHandle v) {
        const auto p = mesh.point(v);
        return Eigen::Vector3d(-p[1], p[0], 0.0);
    };

    // Straight along the axis, rim to rim.
    const CutPath along = walk(mesh, rim, axial, 24);
    CHECK(std::abs(mesh.point(along.end)[2] - mesh.point(rim)[2]) == doctest::Approx(6.0));
    const PathAlignment a = path_alignment(mesh, along, reference);
    CHECK(a.mean > 0.999);
    CHECK(a.low_fraction == 0.0);
    CHECK(a.length == doctest::Approx(6.0));

    // Once around at mid height: perpendicular to the vessel everywhere.
    const CutPath to_middle = walk(mesh, rim, axial, 12);
    const CutPath ring = walk(mesh, to_middle.end, around, 16);
    const PathAlignment r = path_alignment(mesh, ring, reference);
    CHECK(r.mean < 0.05);
    CHECK(r.low_fraction == 1.0);

    // The seam figure weights cuts by length.
    const PathAlignment both = seam_alignment({a, r});
    CHECK(both.length == doctest::Approx(a.length + r.length));
    CHECK(both.mean == doctest::Approx((a.mean * a.length + r.mean * r.length) / both.length));
    CHECK(seam_alignment({}).mean == 0.0);

    SeamAlignmentOptions bad;
    bad.window = 0;
    CHECK_THROWS_AS(path_alignment(mesh, along, reference, bad), InvalidInputError);
    CHECK_THROWS_AS(path_alignment(mesh, along, reference.topRows(3)), InvalidInputError);
}
