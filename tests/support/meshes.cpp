#include "support/meshes.h"

#include "vessel/check/validation.h"
#include "vessel/cut/boundary.h"
#include "vessel/phantom/phantom.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>

namespace vessel::test {

namespace {

// Lays out a (cols x rows) vertex grid and adds two counter-clockwise triangles per quad.
void add_grid_faces(Mesh& mesh, const std::vector<VertexHandle>& v, int cols, int rows)
{
    for (int j = 0; j + 1 < rows; ++j)
        for (int i = 0; i + 1 < cols; ++i)
        {
            const VertexHandle a = v[j * cols + i], b = v[j * cols + i + 1];
            const VertexHandle c = v[(j + 1) * cols + i + 1], d = v[(j + 1) * cols + i];
            mesh.add_face(a, b, c);
            mesh.add_face(a, c, d);
        }
}

}  // namespace

PathTurn path_turn(const Mesh& mesh, const CutPath& path,
                   const std::function<double(const Eigen::Vector3d&)>& angle)
{
    const auto at = [&](VertexHandle v) { return angle(to_eigen(mesh.point(v))); };
    double previous = at(path.start), unwrapped = 0.0, low = 0.0, high = 0.0;
    for (auto h : path.halfedges)
    {
        const double a = at(mesh.to_vertex_handle(h));
        unwrapped += std::remainder(a - previous, 2.0 * M_PI);
        previous = a;
        low = std::min(low, unwrapped);
        high = std::max(high, unwrapped);
    }
    return {unwrapped * 180.0 / M_PI, (high - low) * 180.0 / M_PI};
}

PathTurn helix_turn(const HelicalTubeOptions& options, const Mesh& mesh, const CutPath& path)
{
    return path_turn(mesh, path, [&options](const Eigen::Vector3d& p) {
        return helical_tube_angle(options, p);
    });
}

Mesh shared_tree_mesh(const std::string& relative)
{
    const std::string path = std::string(VESSEL_SHARED_DATA) + "/" + relative;
    if (!std::filesystem::exists(path))
        throw std::invalid_argument("missing shared data: " + path);
    return load_tree_surface(path).mesh;
}

Mesh test_tree_phantom(int outlets)
{
    return test_tree_phantom(outlets, static_cast<std::uint32_t>(outlets));
}

Mesh test_tree_phantom(int outlets, std::uint32_t seed, double edge_length)
{
    TreePhantomOptions tree;
    tree.outlets = outlets;
    tree.seed = seed;
    tree.edge_length = edge_length;
    return tree_phantom(tree);
}

Mesh cut_cylinder(double radius, double length, int n_around, int n_along)
{
    Mesh mesh;
    const int cols = n_around + 1, rows = n_along + 1;
    std::vector<VertexHandle> v(cols * rows);
    for (int j = 0; j < rows; ++j)
        for (int i = 0; i < cols; ++i)
        {
            // i = n_around lands exactly on i = 0: use the same angle, not 2 pi.
            const double t = 2.0 * M_PI * (i % n_around) / n_around;
            v[j * cols + i] =
                mesh.add_vertex({radius * std::cos(t), radius * std::sin(t), length * j / n_along});
        }
    add_grid_faces(mesh, v, cols, rows);
    return mesh;
}

Mesh posed_grid(double size, int n, const Eigen::Isometry3d& pose)
{
    Mesh mesh;
    std::vector<VertexHandle> v((n + 1) * (n + 1));
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i)
        {
            const Eigen::Vector3d p = pose * Eigen::Vector3d(size * i / n, size * j / n, 0.0);
            v[j * (n + 1) + i] = mesh.add_vertex(to_openmesh(p));
        }
    add_grid_faces(mesh, v, n + 1, n + 1);
    return mesh;
}

Mesh bumped_grid(double size, int n, double height)
{
    Mesh mesh = posed_grid(size, n, Eigen::Isometry3d::Identity());
    const double c = 0.5 * size, sigma = 0.25 * size;
    for (auto v : mesh.vertices())
    {
        auto p = mesh.point(v);
        const double r2 = (p[0] - c) * (p[0] - c) + (p[1] - c) * (p[1] - c);
        p[2] = height * std::exp(-r2 / (sigma * sigma));
        mesh.set_point(v, p);
    }
    return mesh;
}

Eigen::VectorXd uv_signed_areas(const Mesh& mesh, const Eigen::MatrixX2d& uv)
{
    Eigen::VectorXd areas(mesh.n_faces());
    for (auto f : mesh.faces())
    {
        const auto h = f.halfedge();
        const Eigen::RowVector2d a = uv.row(h.from().idx());
        const Eigen::RowVector2d b = uv.row(h.to().idx()) - a;
        const Eigen::RowVector2d c = uv.row(h.next().to().idx()) - a;
        areas[f.idx()] = 0.5 * (b[0] * c[1] - b[1] * c[0]);
    }
    return areas;
}

int count_flips(const Mesh& mesh, const Eigen::MatrixX2d& uv)
{
    return static_cast<int>((uv_signed_areas(mesh, uv).array() <= 0.0).count());
}

double max_edge_length_error(const Mesh& mesh, const Eigen::MatrixX2d& uv)
{
    double worst = 0.0;
    for (auto e : mesh.edges())
    {
        const int i = e.v0().idx(), j = e.v1().idx();
        const double l2 = (uv.row(i) - uv.row(j)).norm();
        worst = std::max(worst, std::abs(l2 / mesh.calc_edge_length(e) - 1.0));
    }
    return worst;
}

std::vector<VertexHandle> boundary_vertices(const Mesh& mesh)
{
    std::vector<VertexHandle> out;
    for (auto v : mesh.vertices())
        if (v.is_boundary())
            out.push_back(v);
    return out;
}

RawMesh tube_with_quads(int around, int along)
{
    RawMesh raw;
    for (int j = 0; j <= along; ++j)
        for (int i = 0; i < around; ++i)
        {
            const double a = 2 * M_PI * (i + 0.5 * j) / around;
            raw.points.emplace_back(std::cos(a), std::sin(a), 0.4 * j);
        }
    for (int j = 0; j < along; ++j)
        for (int i = 0; i < around; ++i)
        {
            const int a = j * around + i, b = j * around + (i + 1) % around;
            if (j == 0)
                raw.faces.push_back({a, b, b + around, a + around});
            else
            {
                raw.faces.push_back({a, b, b + around});
                raw.faces.push_back({a, b + around, a + around});
            }
        }
    return raw;
}

PolyData tube_with_fields(int around, int along)
{
    PolyData d;
    d.mesh = vessel::test::tube_with_quads(around, along);
    const auto np = static_cast<Eigen::Index>(d.mesh.points.size());
    const auto nf = static_cast<Eigen::Index>(d.mesh.faces.size());
    Field pressure{"pressure", FieldLocation::Point, FieldType::Float32, Eigen::MatrixXd(np, 1)};
    Field velocity{"velocity", FieldLocation::Point, FieldType::Float64, Eigen::MatrixXd(np, 3)};
    Field node{"GlobalNodeID", FieldLocation::Point, FieldType::Int32, Eigen::MatrixXd(np, 1)};
    for (Eigen::Index i = 0; i < np; ++i)
    {
        pressure.values(i, 0) = static_cast<float>(0.1 * i - 3.3);
        velocity.values.row(i) << std::sin(i * 0.37), 1e-9 * i, -12345.678901234567 + i;
        node.values(i, 0) = 1000 + 7 * i;
    }
    Field element{"GlobalElementID", FieldLocation::Cell, FieldType::Int64, Eigen::MatrixXd(nf, 1)};
    Field thickness{"thickness", FieldLocation::Cell, FieldType::Float64, Eigen::MatrixXd(nf, 1)};
    for (Eigen::Index f = 0; f < nf; ++f)
    {
        element.values(f, 0) = 5000000000.0 + f;  // needs 64 bits
        thickness.values(f, 0) = 0.3 + 1.0 / (f + 3.0);
    }
    d.point_data = {pressure, velocity, node};
    d.cell_data = {element, thickness};
    return d;
}

Eigen::MatrixX2d planar_uv(const Mesh& mesh)
{
    Eigen::MatrixX2d uv(mesh.n_vertices(), 2);
    for (auto v : mesh.vertices())
        uv.row(v.idx()) << mesh.point(v)[0], mesh.point(v)[1];
    return uv;
}

RawMesh split_tube()
{
    RawMesh raw = to_raw_mesh(open_cylinder(1.0, 4.0, 12, 6));
    const int n = static_cast<int>(raw.points.size());
    for (int i = 36; i < 48; ++i)
        raw.points.push_back(raw.points[i]);
    for (auto& face : raw.faces)
        if (*std::max_element(face.begin(), face.end()) >= 48)
            for (int& i : face)
                if (i >= 36 && i < 48)
                    i = n + i - 36;
    return raw;
}

}  // namespace vessel::test

namespace vessel::test {

RawMesh tube_with_holes(int n_around, int n_along, int holes)
{
    RawMesh raw = to_raw_mesh(
        open_cylinder(1.0, n_along * 2.0 * M_PI / n_around, n_around, n_along));
    // Vertex (i, j), i around and j along, is j * n_around + i (split_tube() relies on it too).
    std::vector<char> taken(raw.points.size(), 0);
    for (int i = 0; i < n_around; ++i)
        taken[i] = taken[n_along * n_around + i] = 1;  // the rims
    std::vector<char> removed(raw.faces.size(), 0);
    int left = holes;
    // A stride through the faces spreads the holes along the tube.
    const std::size_t stride = std::max<std::size_t>(1, raw.faces.size() / (2 * holes + 1));
    for (std::size_t start = 0; start < stride && left > 0; ++start)
        for (std::size_t f = start; f < raw.faces.size() && left > 0; f += stride)
        {
            const auto& face = raw.faces[f];
            if (face.size() != 3 ||
                std::any_of(face.begin(), face.end(), [&](int v) { return taken[v]; }))
                continue;
            removed[f] = 1;
            --left;
            for (const int v : face)
            {
                const int i = v % n_around, j = v / n_around;
                for (int dj = -1; dj <= 1; ++dj)
                    for (int di = -1; di <= 1; ++di)
                        if (j + dj >= 0 && j + dj <= n_along)
                            taken[(j + dj) * n_around + (i + di + n_around) % n_around] = 1;
            }
        }
    if (left > 0)
        throw std::invalid_argument("tube_with_holes: only " + std::to_string(holes - left) +
                                    " holes fit");
    std::vector<std::vector<int>> kept;
    for (std::size_t f = 0; f < raw.faces.size(); ++f)
        if (!removed[f])
            kept.push_back(raw.faces[f]);
    raw.faces = std::move(kept);
    return raw;
}

RawMesh tube_with_touching_holes()
{
    RawMesh raw = to_raw_mesh(open_cylinder(1.0, 4.0, 12, 6));
    const auto inside = [](const std::vector<int>& f) {
        return std::all_of(f.begin(), f.end(), [](int v) { return v >= 12 && v < 72; });
    };
    for (std::size_t a = 0; a < raw.faces.size(); ++a)
        for (std::size_t b = a + 1; b < raw.faces.size(); ++b)
        {
            int shared = 0;
            for (const int v : raw.faces[a])
                shared += static_cast<int>(
                    std::count(raw.faces[b].begin(), raw.faces[b].end(), v));
            if (shared != 1 || !inside(raw.faces[a]) || !inside(raw.faces[b]))
                continue;
            raw.faces.erase(raw.faces.begin() + static_cast<std::ptrdiff_t>(b));
            raw.faces.erase(raw.faces.begin() + static_cast<std::ptrdiff_t>(a));
            return raw;
        }
    throw std::logic_error("tube_with_touching_holes: no two faces share one vertex");
}

RawMesh blind_tube(double radius, double length, int n_around, int n_along, int n_cap)
{
    RawMesh raw;
    const auto ring = [&](double r, double z) {
        for (int i = 0; i < n_around; ++i)
        {
            const double t = 2.0 * M_PI * i / n_around;
            raw.points.emplace_back(r * std::cos(t), r * std::sin(t), z);
        }
    };
    for (int j = 0; j <= n_along; ++j)
        ring(radius, length * j / n_along);
    for (int k = 1; k < n_cap; ++k)
    {
        const double phi = 0.5 * M_PI * k / n_cap;
        ring(radius * std::cos(phi), length + radius * std::sin(phi));
    }
    const int rings = n_along + n_cap;  // ring indices 0 .. rings - 1
    for (int j = 0; j + 1 < rings; ++j)
        for (int i = 0; i < n_around; ++i)
        {
            const int a = j * n_around + i, b = j * n_around + (i + 1) % n_around;
            const int c = b + n_around, d = a + n_around;
            raw.faces.push_back({a, b, c});
            raw.faces.push_back({a, c, d});
        }
    const int pole = static_cast<int>(raw.points.size());
    raw.points.emplace_back(0.0, 0.0, length + radius);
    const int last = (rings - 1) * n_around;
    for (int i = 0; i < n_around; ++i)
        raw.faces.push_back({last + i, last + (i + 1) % n_around, pole});
    return raw;
}

RawMesh cap_loops_except(const Mesh& mesh, int keep)
{
    RawMesh raw = to_raw_mesh(mesh);
    const auto loops = boundary_loops(mesh);
    for (std::size_t l = 0; l < loops.size(); ++l)
    {
        if (static_cast<int>(l) == keep)
            continue;
        const int centre = static_cast<int>(raw.points.size());
        raw.points.push_back(loops[l].centroid);
        // A boundary halfedge runs opposite to its inner face's edge, as the cap's face must.
        for (const auto h : loops[l].halfedges)
            raw.faces.push_back({mesh.from_vertex_handle(h).idx(), mesh.to_vertex_handle(h).idx(),
                                 centre});
    }
    return raw;
}

RawMesh moebius_strip(int n, double width)
{
    RawMesh raw;
    for (int i = 0; i < n; ++i)
    {
        const double t = 2.0 * M_PI * i / n;
        for (const double s : {-0.5 * width, 0.5 * width})
        {
            const double r = 1.0 + s * std::cos(0.5 * t);
            raw.points.emplace_back(r * std::cos(t), r * std::sin(t), s * std::sin(0.5 * t));
        }
    }
    for (int i = 0; i < n; ++i)
    {
        const int a = 2 * i, b = 2 * i + 1;
        // After a full turn the strip's two edges have swapped (the half twist).
        const int c = i + 1 < n ? 2 * (i + 1) : 1, d = i + 1 < n ? 2 * (i + 1) + 1 : 0;
        raw.faces.push_back({a, c, d});
        raw.faces.push_back({a, d, b});
    }
    return raw;
}

}  // namespace vessel::test
