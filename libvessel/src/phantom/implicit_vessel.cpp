#include "detail/implicit_vessel.h"

#include "vessel/core/errors.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <sstream>
#include <string>
#include <unordered_map>
#include <vector>

namespace vessel::detail {

namespace {

// Newton steps onto the zero set of the field (optionally constrained to a plane).
Eigen::Vector3d project_to_field(const VesselField& field, Eigen::Vector3d x, double h,
                                 const EndPlane* plane = nullptr)
{
    for (int it = 0; it < 12; ++it)
    {
        const double f = field(x);
        if (std::abs(f) < 1e-10 * h)
            break;
        Eigen::Vector3d g = field.gradient(x, 1e-4 * h);
        if (plane)
            g -= g.dot(plane->normal) * plane->normal;
        const double g2 = g.squaredNorm();
        if (g2 < 1e-12)
            break;
        Eigen::Vector3d step = f * g / g2;
        if (step.norm() > h)
            step *= h / step.norm();
        x -= step;
    }
    return x;
}

double min_angle(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c)
{
    auto angle = [](const Eigen::Vector3d& u, const Eigen::Vector3d& w) {
        const double nu = u.norm(), nw = w.norm();
        if (nu < 1e-300 || nw < 1e-300)
            return 0.0;
        return std::acos(std::clamp(u.dot(w) / (nu * nw), -1.0, 1.0));
    };
    return std::min({angle(b - a, c - a), angle(a - b, c - b), angle(a - c, b - c)});
}

Eigen::Vector3d triangle_normal(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                const Eigen::Vector3d& c)
{
    return (b - a).cross(c - a);
}

// Builds the mesh from a triangle soup, adding faces in breadth-first order across shared edges:
// OpenMesh's add_face can fail to re-link a vertex whose faces arrive as several disjoint fans,
// which a growing patch avoids. Returns false on a repeated directed edge (non-manifold or
// inconsistently oriented soup) or if OpenMesh still rejects a face.
bool add_grown_faces(const std::vector<Eigen::Vector3d>& positions,
                     const std::vector<std::array<int, 3>>& triangles, Mesh& mesh)
{
    auto key = [](int a, int b) { return (std::uint64_t(std::uint32_t(a)) << 32) | std::uint32_t(b); };
    std::unordered_map<std::uint64_t, int> face_of_edge;
    face_of_edge.reserve(3 * triangles.size());
    for (std::size_t t = 0; t < triangles.size(); ++t)
        for (int c = 0; c < 3; ++c)
            if (!face_of_edge.emplace(key(triangles[t][c], triangles[t][(c + 1) % 3]), int(t))
                     .second)
                return false;
    mesh.clear();
    std::vector<VertexHandle> handles;
    handles.reserve(positions.size());
    for (const auto& p : positions)
        handles.push_back(mesh.add_vertex(to_openmesh(p)));
    std::vector<char> added(triangles.size(), 0);
    std::vector<int> queue;
    for (std::size_t seed = 0; seed < triangles.size(); ++seed)
    {
        if (added[seed])
            continue;
        added[seed] = 1;
        queue.assign(1, static_cast<int>(seed));
        for (std::size_t q = 0; q < queue.size(); ++q)
        {
            const auto& t = triangles[queue[q]];
            if (!mesh.add_face(handles[t[0]], handles[t[1]], handles[t[2]]).is_valid())
                return false;
            for (int c = 0; c < 3; ++c)
            {
                const auto it = face_of_edge.find(key(t[(c + 1) % 3], t[c]));
                if (it != face_of_edge.end() && !added[it->second])
                {
                    added[it->second] = 1;
                    queue.push_back(it->second);
                }
            }
        }
    }
    return true;
}

// Dual contouring ("surface nets") of the field on a regular grid with one vertex per connected
// patch of the marching-cubes surface in each cell: ambiguous cell faces are resolved by the
// face-centre value, consistently for both cells that share the face. The dual of a consistent
// marching-cubes surface is a closed 2-manifold, so no non-manifold edge or vertex can appear.
// Returns false when OpenMesh rejects a face (which would mean a topological accident).
bool surface_nets(const VesselField& field, double h, const Eigen::Vector3d& offset, Mesh& mesh)
{
    Eigen::AlignedBox3d box;
    for (const auto& tube : field.tubes())
        box.extend(tube.box);
    const Eigen::Vector3d origin = box.min() - (2.0 * h) * Eigen::Vector3d::Ones() - offset * h;
    const Eigen::Vector3i n = (((box.max() - origin) / h).array().ceil() + 3).cast<int>();
    const long nx = n.x(), ny = n.y(), nz = n.z();
    auto index = [&](long i, long j, long k) { return (k * ny + j) * nx + i; };
    auto point = [&](long i, long j, long k) {
        return Eigen::Vector3d(origin.x() + i * h, origin.y() + j * h, origin.z() + k * h);
    };

    // Sample the field tube by tube in the same fold order as VesselField::operator().
    std::vector<double> value(nx * ny * nz, field.outside());
    for (const auto& tube : field.tubes())
    {
        const Eigen::Vector3i lo =
            ((tube.box.min() - origin) / h).array().floor().cast<int>().max(0);
        const Eigen::Vector3i hi =
            ((tube.box.max() - origin) / h).array().ceil().cast<int>().min(n.array() - 1);
        for (long k = lo.z(); k <= hi.z(); ++k)
            for (long j = lo.y(); j <= hi.y(); ++j)
                for (long i = lo.x(); i <= hi.x(); ++i)
                {
                    const Eigen::Vector3d x = point(i, j, k);
                    if (tube.box.contains(x))
                    {
                        double& f = value[index(i, j, k)];
                        f = smooth_min(f, tube.distance(x), field.blend());
                    }
                }
    }

    // Cell corners: bit 0 = +x, bit 1 = +y, bit 2 = +z. Cell edges as corner pairs.
    static const int edge_corner[12][2] = {{0, 1}, {2, 3}, {4, 5}, {6, 7}, {0, 2}, {1, 3},
                                           {4, 6}, {5, 7}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
    // Cell faces as cyclic corner lists.
    static const int face_corner[6][4] = {{0, 2, 6, 4}, {1, 3, 7, 5}, {0, 1, 5, 4},
                                          {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 5, 7, 6}};
    auto edge_of = [](int c0, int c1) {
        for (int e = 0; e < 12; ++e)
            if ((edge_corner[e][0] == c0 && edge_corner[e][1] == c1) ||
                (edge_corner[e][0] == c1 && edge_corner[e][1] == c0))
                return e;
        return -1;
    };

    std::vector<Eigen::Vector3d> positions;
    std::unordered_map<long, std::array<int, 12>> cell_vertex;  // cell -> vertex per edge
    for (long k = 0; k + 1 < nz; ++k)
        for (long j = 0; j + 1 < ny; ++j)
            for (long i = 0; i + 1 < nx; ++i)
            {
                double f[8];
                int inside_mask = 0;
                for (int c = 0; c < 8; ++c)
                {
                    f[c] = value[index(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1))];
                    if (f[c] < 0.0)
                        inside_mask |= 1 << c;
                }
                if (inside_mask == 0 || inside_mask == 255)
                    continue;
                auto inside = [&](int c) { return (inside_mask >> c) & 1; };
                // Union-find over the crossing edges, linked pairwise on each face.
                int parent[12];
                for (int e = 0; e < 12; ++e)
                    parent[e] = e;
                std::function<int(int)> find = [&](int e) {
                    return parent[e] == e ? e : parent[e] = find(parent[e]);
                };
                auto link = [&](int e0, int e1) { parent[find(e0)] = find(e1); };
                for (const auto& fc : face_corner)
                {
                    int crossing[4], n_crossing = 0;
                    for (int q = 0; q < 4; ++q)
                        if (inside(fc[q]) != inside(fc[(q + 1) % 4]))
                            crossing[n_crossing++] = q;
                    if (n_crossing == 2)
                        link(edge_of(fc[crossing[0]], fc[(crossing[0] + 1) % 4]),
                             edge_of(fc[crossing[1]], fc[(crossing[1] + 1) % 4]));
                    else if (n_crossing == 4)
                    {
                        // Isolate the corners whose state differs from the face centre's.
                        const bool centre_inside =
                            f[fc[0]] + f[fc[1]] + f[fc[2]] + f[fc[3]] < 0.0;
                        for (int q = 0; q < 4; ++q)
                            if (static_cast<bool>(inside(fc[q])) != centre_inside)
                                link(edge_of(fc[(q + 3) % 4], fc[q]),
                                     edge_of(fc[q], fc[(q + 1) % 4]));
                    }
                }
                std::array<int, 12> vertex_of_edge;
                vertex_of_edge.fill(-1);
                int root_vertex[12];
                std::fill(root_vertex, root_vertex + 12, -1);
                std::vector<Eigen::Vector3d> sum;
                std::vector<int> count;
                for (int e = 0; e < 12; ++e)
                {
                    const int c0 = edge_corner[e][0], c1 = edge_corner[e][1];
                    if (inside(c0) == inside(c1))
                        continue;
                    const int root = find(e);
                    if (root_vertex[root] < 0)
                    {
                        root_vertex[root] = static_cast<int>(positions.size() + sum.size());
                        sum.push_back(Eigen::Vector3d::Zero());
                        count.push_back(0);
                    }
                    const int local = root_vertex[root] - static_cast<int>(positions.size());
                    const double t = f[c0] / (f[c0] - f[c1]);
                    const Eigen::Vector3d p0 =
                        point(i + (c0 & 1), j + ((c0 >> 1) & 1), k + ((c0 >> 2) & 1));
                    const Eigen::Vector3d p1 =
                        point(i + (c1 & 1), j + ((c1 >> 1) & 1), k + ((c1 >> 2) & 1));
                    sum[local] += p0 + t * (p1 - p0);
                    ++count[local];
                    vertex_of_edge[e] = root_vertex[root];
                }
                for (std::size_t q = 0; q < sum.size(); ++q)
                    positions.push_back(sum[q] / count[q]);
                cell_vertex[index(i, j, k)] = vertex_of_edge;
            }

    // Snap the vertices onto the zero set before choosing quad diagonals.
    for (auto& p : positions)
        p = project_to_field(field, p, h);

    std::vector<std::array<int, 3>> triangles;

    // One quad per crossing grid edge, around the 4 cells sharing it, counter-clockwise seen
    // from the outside.
    for (long k = 1; k + 1 < nz; ++k)
        for (long j = 1; j + 1 < ny; ++j)
            for (long i = 1; i + 1 < nx; ++i)
            {
                const bool in0 = value[index(i, j, k)] < 0.0;
                for (int axis = 0; axis < 3; ++axis)
                {
                    const long di = axis == 0, dj = axis == 1, dk = axis == 2;
                    const bool in1 = value[index(i + di, j + dj, k + dk)] < 0.0;
                    if (in0 == in1)
                        continue;
                    const int b = (axis + 1) % 3, c = (axis + 2) % 3;
                    static const int offsets[4][2] = {{-1, -1}, {0, -1}, {0, 0}, {-1, 0}};
                    int quad[4];
                    for (int q = 0; q < 4; ++q)
                    {
                        long cell[3] = {i, j, k};
                        cell[b] += offsets[q][0];
                        cell[c] += offsets[q][1];
                        const int corner0 =
                            ((offsets[q][0] == -1) << b) | ((offsets[q][1] == -1) << c);
                        const int e = edge_of(corner0, corner0 | (1 << axis));
                        const auto it = cell_vertex.find(index(cell[0], cell[1], cell[2]));
                        if (it == cell_vertex.end() || it->second[e] < 0)
                            return false;
                        quad[q] = it->second[e];
                    }
                    if (!in0)
                        std::swap(quad[1], quad[3]);
                    const Eigen::Vector3d& p0 = positions[quad[0]];
                    const Eigen::Vector3d& p1 = positions[quad[1]];
                    const Eigen::Vector3d& p2 = positions[quad[2]];
                    const Eigen::Vector3d& p3 = positions[quad[3]];
                    const double q02 = std::min(min_angle(p0, p1, p2), min_angle(p0, p2, p3));
                    const double q13 = std::min(min_angle(p1, p2, p3), min_angle(p1, p3, p0));
                    int tri[2][3] = {{quad[0], quad[1], quad[2]}, {quad[0], quad[2], quad[3]}};
                    if (q13 > q02)
                    {
                        int alt[2][3] = {{quad[1], quad[2], quad[3]}, {quad[1], quad[3], quad[0]}};
                        std::copy(&alt[0][0], &alt[0][0] + 6, &tri[0][0]);
                    }
                    triangles.push_back({tri[0][0], tri[0][1], tri[0][2]});
                    triangles.push_back({tri[1][0], tri[1][1], tri[1][2]});
                }
            }
    return add_grown_faces(positions, triangles, mesh);
}

// Cuts every end open: vertices close to an end plane are snapped onto it, edges crossing it are
// split there, and the faces beyond it are deleted.
void cut_ends(Mesh& mesh, const std::vector<EndPlane>& ends, double h)
{
    std::vector<char> discard;
    for (const auto& end : ends)
    {
        std::vector<double> d(mesh.n_vertices());
        for (auto v : mesh.vertices())
            d[v.idx()] = end.beyond(to_eigen(mesh.point(v)), h);
        auto on_plane = [&](VertexHandle v) { return d[v.idx()] == 0.0; };
        // Snap, unless a face would then lie entirely in the plane.
        for (auto v : mesh.vertices())
        {
            if (std::isnan(d[v.idx()]) || std::abs(d[v.idx()]) >= 0.2 * h)
                continue;
            bool flat = false;
            for (auto f : v.faces())
            {
                int n_on = 0;
                for (auto w : f.vertices())
                    n_on += (w == v || on_plane(w)) ? 1 : 0;
                flat = flat || n_on == 3;
            }
            if (flat)
                continue;
            mesh.set_point(v, mesh.point(v) - d[v.idx()] * to_openmesh(end.normal));
            d[v.idx()] = 0.0;
        }
        std::vector<EdgeHandle> crossing;
        for (auto e : mesh.edges())
        {
            const double d0 = d[e.v0().idx()], d1 = d[e.v1().idx()];
            if (!std::isnan(d0) && !std::isnan(d1) && ((d0 < 0 && d1 > 0) || (d0 > 0 && d1 < 0)))
                crossing.push_back(e);
        }
        for (auto e : crossing)
        {
            const auto h0 = mesh.halfedge_handle(e, 0);
            const VertexHandle v0 = mesh.from_vertex_handle(h0), v1 = mesh.to_vertex_handle(h0);
            const double t = d[v0.idx()] / (d[v0.idx()] - d[v1.idx()]);
            const OpenMesh::Vec3d p = mesh.point(v0) + t * (mesh.point(v1) - mesh.point(v0));
            mesh.split(e, p);
            d.push_back(0.0);
        }
        discard.resize(mesh.n_faces(), 0);
        for (auto f : mesh.faces())
            for (auto v : f.vertices())
                if (!std::isnan(d[v.idx()]) && d[v.idx()] > 0.0)
                    discard[f.idx()] = 1;
    }
    mesh.request_face_status();
    mesh.request_edge_status();
    mesh.request_vertex_status();
    for (auto f : mesh.faces())
        if (discard[f.idx()])
            mesh.delete_face(f, true);
    mesh.garbage_collection();
    mesh.release_face_status();
    mesh.release_edge_status();
    mesh.release_vertex_status();
}

// Index of the end plane a boundary vertex lies on (-1 if none).
int end_of(const std::vector<EndPlane>& ends, const Eigen::Vector3d& x, double h)
{
    int best = -1;
    double best_d = 0.5 * h;
    for (std::size_t i = 0; i < ends.size(); ++i)
    {
        const double d = ends[i].beyond(x, h);
        if (!std::isnan(d) && std::abs(d) < best_d)
        {
            best_d = std::abs(d);
            best = static_cast<int>(i);
        }
    }
    return best;
}

// Tangential Laplacian smoothing with re-projection onto the field; boundary vertices slide
// along their end plane's intersection with the surface.
void smooth(Mesh& mesh, const VesselField& field, const std::vector<EndPlane>& ends, double h,
            int iterations)
{
    std::vector<int> end(mesh.n_vertices(), -1);
    for (auto v : mesh.vertices())
        if (v.is_boundary())
            end[v.idx()] = end_of(ends, to_eigen(mesh.point(v)), h);
    std::vector<Eigen::Vector3d> next(mesh.n_vertices());
    for (int it = 0; it < iterations; ++it)
    {
        for (auto v : mesh.vertices())
        {
            const Eigen::Vector3d x = to_eigen(mesh.point(v));
            if (v.is_boundary())
            {
                Eigen::Vector3d c = Eigen::Vector3d::Zero();
                for (auto hh : v.outgoing_halfedges())
                    if (hh.is_boundary())
                        c = 0.5 * (to_eigen(mesh.point(hh.to())) +
                                   to_eigen(mesh.point(hh.prev().from())));
                const int e = end[v.idx()];
                if (e < 0)
                {
                    next[v.idx()] = x;
                    continue;
                }
                Eigen::Vector3d y = x + 0.5 * (c - x);
                y -= (y - ends[e].center).dot(ends[e].normal) * ends[e].normal;
                next[v.idx()] = project_to_field(field, y, h, &ends[e]);
            }
            else
            {
                Eigen::Vector3d c = Eigen::Vector3d::Zero();
                int n = 0;
                for (auto w : v.vertices())
                {
                    c += to_eigen(mesh.point(w));
                    ++n;
                }
                c /= n;
                const Eigen::Vector3d normal = field.gradient(x, 1e-4 * h).normalized();
                Eigen::Vector3d step = 0.5 * (c - x);
                step -= step.dot(normal) * normal;
                next[v.idx()] = project_to_field(field, x + step, h);
            }
        }
        for (auto v : mesh.vertices())
            mesh.set_point(v, to_openmesh(next[v.idx()]));
    }
}

// Edge flips that raise the smaller of the two triangles' minimum angles without folding.
int improve_by_flips(Mesh& mesh, int passes)
{
    int total = 0;
    for (int pass = 0; pass < passes; ++pass)
    {
        int flips = 0;
        for (auto e : mesh.edges())
        {
            if (e.is_boundary() || !mesh.is_flip_ok(e))
                continue;
            const auto hh = e.h0();
            const Eigen::Vector3d a = to_eigen(mesh.point(hh.from()));
            const Eigen::Vector3d b = to_eigen(mesh.point(hh.to()));
            const Eigen::Vector3d c = to_eigen(mesh.point(hh.next().to()));
            const Eigen::Vector3d d = to_eigen(mesh.point(hh.opp().next().to()));
            const double before = std::min(min_angle(a, b, c), min_angle(b, a, d));
            const double after = std::min(min_angle(c, a, d), min_angle(d, b, c));
            if (after < before + 1e-3)
                continue;
            const Eigen::Vector3d n_old = triangle_normal(a, b, c).normalized() +
                                          triangle_normal(b, a, d).normalized();
            const Eigen::Vector3d n1 = triangle_normal(c, a, d).normalized();
            const Eigen::Vector3d n2 = triangle_normal(d, b, c).normalized();
            if (n1.dot(n2) < 0.5 || n1.dot(n_old) <= 0.0 || n2.dot(n_old) <= 0.0)
                continue;
            mesh.flip(e);
            ++flips;
        }
        total += flips;
        if (flips == 0)
            break;
    }
    return total;
}

// Empty string if the mesh is a valid open tree surface with `n_loops` ends, else the reason.
std::string tree_surface_problem(const Mesh& mesh, const VesselField& field, int n_loops,
                                 double h, bool check_geometry)
{
    std::ostringstream why;
    for (auto v : mesh.vertices())
    {
        int n_out = 0, n_boundary = 0;
        for (auto hh : v.outgoing_halfedges())
        {
            ++n_out;
            n_boundary += hh.is_boundary() ? 1 : 0;
        }
        if (n_out == 0 || n_boundary > 1)
        {
            why << "vertex " << v.idx() << " is isolated or non-manifold";
            return why.str();
        }
    }
    std::vector<int> seen(mesh.n_vertices(), 0);
    std::vector<VertexHandle> stack = {VertexHandle(0)};
    seen[0] = 1;
    std::size_t n_seen = 1;
    while (!stack.empty())
    {
        const auto v = OpenMesh::make_smart(stack.back(), mesh);
        stack.pop_back();
        for (auto w : v.vertices())
            if (!seen[w.idx()])
            {
                seen[w.idx()] = 1;
                ++n_seen;
                stack.push_back(w);
            }
    }
    if (n_seen != mesh.n_vertices())
        return "more than one connected component";
    std::vector<char> visited(mesh.n_halfedges(), 0);
    int loops = 0;
    for (auto hh : mesh.halfedges())
    {
        if (!hh.is_boundary() || visited[hh.idx()])
            continue;
        ++loops;
        for (auto g = hh; !visited[g.idx()]; g = g.next())
            visited[g.idx()] = 1;
    }
    const long chi = long(mesh.n_vertices()) - long(mesh.n_edges()) + long(mesh.n_faces());
    if (loops != n_loops || chi != 2 - n_loops)
    {
        why << loops << " boundary loops (expected " << n_loops << "), Euler characteristic "
            << chi << " (expected " << 2 - n_loops << ")";
        return why.str();
    }
    if (!check_geometry)
        return {};
    for (auto f : mesh.faces())
    {
        auto hh = f.halfedge();
        const Eigen::Vector3d a = to_eigen(mesh.point(hh.from()));
        const Eigen::Vector3d b = to_eigen(mesh.point(hh.to()));
        const Eigen::Vector3d c = to_eigen(mesh.point(hh.next().to()));
        const Eigen::Vector3d n = triangle_normal(a, b, c);
        if (n.norm() < 2e-3 * h * h)
        {
            why << "face " << f.idx() << " is degenerate";
            return why.str();
        }
        if (n.dot(field.gradient((a + b + c) / 3.0, 1e-4 * h)) <= 0.0)
        {
            why << "face " << f.idx() << " is folded or points inward";
            return why.str();
        }
    }
    return {};
}

}  // namespace

Mesh vessel_surface(const VesselField& field, const std::vector<EndPlane>& ends, double h,
                    const char* caller)
{
    static const double shifts[4][3] = {
        {0.0, 0.0, 0.0}, {0.31, 0.17, 0.43}, {0.57, 0.71, 0.13}, {0.83, 0.41, 0.67}};
    std::string problem;
    for (const auto& s : shifts)
    {
        Mesh mesh;
        if (!surface_nets(field, h, Eigen::Vector3d(s[0], s[1], s[2]), mesh))
        {
            problem = "the sampled surface is not manifold";
            continue;
        }
        problem = tree_surface_problem(mesh, field, 0, h, false);
        if (!problem.empty())
            continue;
        cut_ends(mesh, ends, h);
        smooth(mesh, field, ends, h, 4);
        improve_by_flips(mesh, 10);
        smooth(mesh, field, ends, h, 6);
        improve_by_flips(mesh, 10);
        smooth(mesh, field, ends, h, 3);
        problem = tree_surface_problem(mesh, field, static_cast<int>(ends.size()), h, true);
        if (problem.empty())
            return mesh;
    }
    throw TopologyError(std::string(caller) + ": could not build a valid surface (" + problem +
                        "); try a smaller edge_length");
}

}  // namespace vessel::detail
