#include <doctest/doctest.h>

#include "vessel/cut/boundary.h"
#include "vessel/core/errors.h"
#include "vessel/phantom/phantom.h"
#include "vessel/cut/streamline.h"

#include <cmath>

using namespace vessel;

namespace {

std::vector<char> flags(const Mesh& mesh, const std::vector<VertexHandle>& vertices)
{
    std::vector<char> is(mesh.n_vertices(), 0);
    for (auto v : vertices)
        is[v.idx()] = 1;
    return is;
}

// The loop whose vertices lie at height z.
const BoundaryLoop& loop_at(const Mesh& mesh, const std::vector<BoundaryLoop>& loops, double z)
{
    for (const auto& loop : loops)
        if (std::abs(mesh.point(loop.vertices.front())[2] - z) < 1e-9)
            return loop;
    FAIL("no loop at z = " << z);
    return loops.front();
}

}  // namespace

TEST_CASE("streamline: the axial field on a cylinder traces a straight generator line")
{
    const double length = 5.0;
    const Mesh mesh = open_cylinder(1.0, length, 16, 10);
    const auto loops = boundary_loops(mesh);
    const BoundaryLoop& top = loop_at(mesh, loops, length);
    const BoundaryLoop& bottom = loop_at(mesh, loops, 0.0);
    Eigen::MatrixX3d down(mesh.n_vertices(), 3);
    down.rowwise() = Eigen::RowVector3d(0.0, 0.0, -1.0);
    for (VertexHandle start : {top.vertices[0], top.vertices[5]})
    {
        const Streamline line = trace_streamline(mesh, down, start, flags(mesh, bottom.vertices));
        CHECK(line.stop == StreamlineStop::Target);
        REQUIRE(line.points.size() >= 2);
        const Eigen::Vector3d p0 = line.points.front();
        const double angle0 = std::atan2(p0.y(), p0.x());
        double max_off = 0.0;
        for (const auto& p : line.points)
            max_off = std::max(max_off, std::abs(std::remainder(std::atan2(p.y(), p.x()) - angle0,
                                                                2.0 * M_PI)));
        CHECK(max_off < 1e-9);
        // Down the whole cylinder to the ring next to the bottom rim, never up.
        CHECK(line.points.back().z() <= length / 10.0 + 1e-9);
        for (std::size_t i = 1; i < line.points.size(); ++i)
            CHECK(line.points[i].z() <= line.points[i - 1].z() + 1e-12);
        CHECK(line.length == doctest::Approx(length - line.points.back().z()).epsilon(1e-9));
    }
}

TEST_CASE("streamline: a parallel-transported field on a helical tube keeps its frame angle")
{
    // Staggered rings: the generic case, the line crosses faces instead of running on edges.
    HelicalTubeOptions options;
    options.turns = 1.5;
    options.n_around = 32;
    const Mesh mesh = helical_tube(options);
    const auto loops = boundary_loops(mesh);
    // Ring 0 (u = 0) is one loop; the field points toward it along the lines of constant
    // frame angle (the tube's parallel-transported generators).
    const int n_rings = static_cast<int>(mesh.n_vertices()) / options.n_around;
    Eigen::MatrixX3d field(mesh.n_vertices(), 3);
    std::vector<char> at_start_ring(mesh.n_vertices(), 0);
    for (auto v : mesh.vertices())
    {
        const int ring = v.idx() / options.n_around;
        const double u = static_cast<double>(ring) / (n_rings - 1);
        const double angle = helical_tube_angle(options, to_eigen(mesh.point(v)));
        const double du = 1e-6;
        field.row(v.idx()) = (helical_tube_point(options, u - du, angle, options.tube_radius) -
                              helical_tube_point(options, u + du, angle, options.tube_radius))
                                 .normalized()
                                 .transpose();
        at_start_ring[v.idx()] = ring == 0;
    }
    for (int i : {0, 7, 20})
    {
        const VertexHandle start(static_cast<int>((n_rings - 1) * options.n_around + i));
        const Streamline line = trace_streamline(mesh, field, start, at_start_ring);
        CHECK(line.stop == StreamlineStop::Target);
        const double angle0 = helical_tube_angle(options, line.points.front());
        double max_off = 0.0;
        for (const auto& p : line.points)
            max_off = std::max(max_off, std::abs(std::remainder(
                                            helical_tube_angle(options, p) - angle0, 2.0 * M_PI)));
        MESSAGE("helical tube streamline from rim vertex " << i << ": " << line.faces.size()
                                                           << " faces, frame angle within "
                                                           << max_off * 180.0 / M_PI << " deg");
        // The per-face constant direction is the chord of a curved field: a small deviation
        // (one angular step around is 11.25 degrees; measured under 0.1).
        CHECK(max_off * 180.0 / M_PI < 0.5);
        // It covers the tube: the last face touches ring 0.
        CHECK(line.faces.size() > static_cast<std::size_t>(n_rings));
    }
}

TEST_CASE("streamline: sinks, boundaries and bad input")
{
    const Mesh mesh = open_cylinder(1.0, 2.0, 12, 4);
    const auto loops = boundary_loops(mesh);
    const BoundaryLoop& top = loop_at(mesh, loops, 2.0);
    const std::vector<char> none(mesh.n_vertices(), 0);
    Eigen::MatrixX3d down(mesh.n_vertices(), 3);
    down.rowwise() = Eigen::RowVector3d(0.0, 0.0, -1.0);
    // No target: it leaves through the bottom rim.
    CHECK(trace_streamline(mesh, down, top.vertices[0], none).stop == StreamlineStop::Boundary);
    // A zero field is singular at once.
    const Eigen::MatrixX3d zero = Eigen::MatrixX3d::Zero(mesh.n_vertices(), 3);
    CHECK(trace_streamline(mesh, zero, top.vertices[0], none).stop == StreamlineStop::Singular);
    // A field converging on the middle ring (z = 1): the trace ends at the sink, not beyond it.
    Eigen::MatrixX3d to_middle(mesh.n_vertices(), 3);
    for (auto v : mesh.vertices())
        to_middle.row(v.idx()) = Eigen::RowVector3d(0.0, 0.0, 1.0 - mesh.point(v)[2]);
    const Streamline sink = trace_streamline(mesh, to_middle, top.vertices[0], none);
    CHECK(sink.stop != StreamlineStop::Boundary);
    for (const auto& p : sink.points)
        CHECK(p.z() >= 1.0 - 1e-9);

    CHECK_THROWS_AS(trace_streamline(mesh, down.topRows(3), top.vertices[0], none),
                    InvalidInputError);
    CHECK_THROWS_AS(trace_streamline(mesh, down, VertexHandle(), none), InvalidInputError);
    StreamlineOptions bad;
    bad.max_face_visits = 0;
    CHECK_THROWS_AS(bad.validate(), InvalidInputError);
}
