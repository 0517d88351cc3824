#include "vessel/cut/streamline.h"

#include "vessel/core/errors.h"

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>

namespace vessel {

void StreamlineOptions::validate() const
{
    if (max_face_visits < 1)
        throw InvalidInputError("StreamlineOptions: max_face_visits must be >= 1");
    if (max_steps < 0)
        throw InvalidInputError("StreamlineOptions: max_steps must be >= 0 (0 = 4 x faces)");
}

namespace {

// One face as the tracer sees it: corners v0 v1 v2 (from the face's halfedge h0: v0 = from(h0),
// v1 = to(h0), v2 = to(next(h0))), the halfedge opposite each corner, and the face direction.
struct FaceFrame
{
    std::array<VertexHandle, 3> v;
    std::array<HalfedgeHandle, 3> opposite;  // halfedge of the edge across from corner i
    std::array<Eigen::Vector3d, 3> x;
    Eigen::Vector3d d = Eigen::Vector3d::Zero();  // field in the face plane
};

class Tracer
{
public:
    Tracer(const Mesh& mesh, const Eigen::MatrixX3d& field) : mesh_(mesh), field_(field) {}

    FaceFrame frame(FaceHandle f) const
    {
        FaceFrame frame;
        const HalfedgeHandle h0 = mesh_.halfedge_handle(f);
        const HalfedgeHandle h1 = mesh_.next_halfedge_handle(h0);
        const HalfedgeHandle h2 = mesh_.next_halfedge_handle(h1);
        frame.v = {mesh_.from_vertex_handle(h0), mesh_.to_vertex_handle(h0),
                   mesh_.to_vertex_handle(h1)};
        frame.opposite = {h1, h2, h0};
        Eigen::Vector3d mean = Eigen::Vector3d::Zero();
        for (int i = 0; i < 3; ++i)
        {
            frame.x[i] = to_eigen(mesh_.point(frame.v[i]));
            mean += field_.row(frame.v[i].idx()).transpose();
        }
        const Eigen::Vector3d n = (frame.x[1] - frame.x[0]).cross(frame.x[2] - frame.x[0]);
        if (n.norm() > 0.0 && mean.allFinite())
        {
            const Eigen::Vector3d u = n.normalized();
            frame.d = mean - u * u.dot(mean);
        }
        return frame;
    }

    // Coordinates (a, b) of the in-plane vector d in the basis (e1, e2).
    static bool solve2(const Eigen::Vector3d& e1, const Eigen::Vector3d& e2,
                       const Eigen::Vector3d& d, double& a, double& b)
    {
        const double g11 = e1.dot(e1), g12 = e1.dot(e2), g22 = e2.dot(e2);
        const double det = g11 * g22 - g12 * g12;
        if (!(det > 1e-300))
            return false;
        const double r1 = e1.dot(d), r2 = e2.dot(d);
        a = (g22 * r1 - g12 * r2) / det;
        b = (g11 * r2 - g12 * r1) / det;
        return std::isfinite(a) && std::isfinite(b);
    }

    // Barycentric rate of change of moving along the face direction.
    static bool barycentric_direction(const FaceFrame& f, Eigen::Vector3d& db)
    {
        double a = 0, b = 0;
        if (f.d.squaredNorm() == 0.0 || !solve2(f.x[1] - f.x[0], f.x[2] - f.x[0], f.d, a, b))
            return false;
        db = Eigen::Vector3d(-a - b, a, b);
        return true;
    }

    // From vertex v: the face around v whose corner wedge holds its own direction, the most
    // centrally; sets \p bary to the corner. Invalid face if there is none.
    FaceHandle leave_vertex(VertexHandle v, FaceFrame& out, Eigen::Vector3d& bary) const
    {
        FaceHandle best;
        double best_score = -1.0;
        for (auto f : mesh_.vf_range(v))
        {
            const FaceFrame fr = frame(f);
            const int i = fr.v[0] == v ? 0 : (fr.v[1] == v ? 1 : 2);
            const int j = (i + 1) % 3, k = (i + 2) % 3;
            double a = 0, b = 0;
            if (fr.d.squaredNorm() == 0.0 ||
                !solve2(fr.x[j] - fr.x[i], fr.x[k] - fr.x[i], fr.d, a, b))
                continue;
            const double sum = a + b;
            if (!(sum > 0.0) || a < -1e-9 * sum || b < -1e-9 * sum)
                continue;
            const double score = std::min(a, b) / sum;
            if (score > best_score)
            {
                best_score = score;
                best = f;
                out = fr;
                bary = Eigen::Vector3d::Zero();
                bary[i] = 1.0;
            }
        }
        return best;
    }

private:
    const Mesh& mesh_;
    const Eigen::MatrixX3d& field_;
};

Eigen::Vector3d point_of(const FaceFrame& f, const Eigen::Vector3d& b)
{
    return b[0] * f.x[0] + b[1] * f.x[1] + b[2] * f.x[2];
}

bool touches(const FaceFrame& f, const std::vector<char>& stop_at)
{
    return stop_at[f.v[0].idx()] || stop_at[f.v[1].idx()] || stop_at[f.v[2].idx()];
}

}  // namespace

Streamline trace_streamline(const Mesh& mesh, const Eigen::MatrixX3d& field, VertexHandle start,
                            const std::vector<char>& stop_at, const StreamlineOptions& options)
{
    options.validate();
    const std::size_t nv = mesh.n_vertices();
    if (static_cast<std::size_t>(field.rows()) != nv || stop_at.size() != nv)
        throw InvalidInputError("trace_streamline: field and stop_at need one row per vertex (" +
                                std::to_string(nv) + ")");
    if (!mesh.is_valid_handle(start) || static_cast<std::size_t>(start.idx()) >= nv)
        throw InvalidInputError("trace_streamline: invalid start vertex");
    const int max_steps =
        options.max_steps > 0 ? options.max_steps : 4 * static_cast<int>(mesh.n_faces()) + 16;

    Tracer tracer(mesh, field);
    Streamline line;
    std::vector<int> visits(mesh.n_faces(), 0);
    const auto add_point = [&](const Eigen::Vector3d& p) {
        if (!line.points.empty())
            line.length += (p - line.points.back()).norm();
        line.points.push_back(p);
    };
    // Enter face f; false (with line.stop set) when the trace ends there.
    const auto enter = [&](const FaceFrame& f, FaceHandle handle) {
        line.faces.push_back(handle);
        if (touches(f, stop_at))
        {
            line.stop = StreamlineStop::Target;
            return false;
        }
        if (++visits[handle.idx()] > options.max_face_visits)
        {
            line.stop = StreamlineStop::Cycle;
            return false;
        }
        return true;
    };

    FaceFrame f;
    Eigen::Vector3d b;
    VertexHandle at_vertex = start;  // valid while the trace sits on a vertex
    add_point(to_eigen(mesh.point(start)));
    line.vertices.push_back(start);
    for (int step = 0; step < max_steps; ++step)
    {
        if (at_vertex.is_valid())
        {
            if (stop_at[at_vertex.idx()])
            {
                line.stop = StreamlineStop::Target;
                return line;
            }
            const FaceHandle next = tracer.leave_vertex(at_vertex, f, b);
            if (!next.is_valid())
            {
                // Nowhere on from here: out over the rim, or a sink of the field.
                line.stop = mesh.is_boundary(at_vertex) && step > 0 ? StreamlineStop::Boundary
                                                                    : StreamlineStop::Singular;
                return line;
            }
            at_vertex = VertexHandle();
            if (!enter(f, next))
                return line;
        }
        Eigen::Vector3d db;
        if (!Tracer::barycentric_direction(f, db))
        {
            line.stop = StreamlineStop::Singular;
            return line;
        }
        // Leave through the edge across from the corner whose weight reaches 0 first.
        int exit = -1;
        double t = std::numeric_limits<double>::infinity();
        for (int i = 0; i < 3; ++i)
            if (db[i] < 0.0 && b[i] > 1e-12 && b[i] / -db[i] < t)
            {
                t = b[i] / -db[i];
                exit = i;
            }
        if (exit < 0)
        {
            line.stop = StreamlineStop::Singular;
            return line;
        }
        b += t * db;
        b[exit] = 0.0;
        b = b.cwiseMax(0.0) / b.cwiseMax(0.0).sum();
        add_point(point_of(f, b));
        const HalfedgeHandle across = f.opposite[exit];
        const VertexHandle va = mesh.from_vertex_handle(across);
        const VertexHandle vb = mesh.to_vertex_handle(across);
        const int ia = (exit + 1) % 3, ib = (exit + 2) % 3;  // corners va, vb of f
        const double wa = b[ia], wb = b[ib];
        if (wa < 1e-9 || wb < 1e-9)
        {
            // Out through a corner (e.g. running along an edge): go on from that vertex.
            at_vertex = wa < 1e-9 ? vb : va;
            line.vertices.push_back(at_vertex);
            continue;
        }
        const FaceHandle g_handle = mesh.face_handle(mesh.opposite_halfedge_handle(across));
        if (!g_handle.is_valid())
        {
            line.stop = StreamlineStop::Boundary;
            return line;
        }
        const FaceFrame g = tracer.frame(g_handle);
        Eigen::Vector3d bg = Eigen::Vector3d::Zero();
        int k = -1;  // corner of g off the shared edge
        for (int i = 0; i < 3; ++i)
        {
            if (g.v[i] == va)
                bg[i] = wa;
            else if (g.v[i] == vb)
                bg[i] = wb;
            else
                k = i;
        }
        Eigen::Vector3d dbg;
        const bool onward = Tracer::barycentric_direction(g, dbg) && dbg[k] > 1e-12 * dbg.norm();
        if (onward)
        {
            f = g;
            b = bg;
            if (!enter(f, g_handle))
                return line;
            continue;
        }
        // Both faces push toward the shared edge: slide along it to the end it leans to.
        const Eigen::Vector3d xa = to_eigen(mesh.point(va)), xb = to_eigen(mesh.point(vb));
        at_vertex = (f.d + g.d).dot(xb - xa) >= 0.0 ? vb : va;
        add_point(to_eigen(mesh.point(at_vertex)));
        line.vertices.push_back(at_vertex);
    }
    line.stop = StreamlineStop::Length;
    return line;
}

}  // namespace vessel
