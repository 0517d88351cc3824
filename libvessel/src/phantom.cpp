#include "vessel/phantom.h"

#include "vessel/errors.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <unordered_map>

namespace vessel {

namespace {

// Adds the two triangles of quad (a, b, c, d), counter-clockwise seen from outside.
void add_quad(Mesh& mesh, VertexHandle a, VertexHandle b, VertexHandle c, VertexHandle d)
{
    mesh.add_face(a, b, c);
    mesh.add_face(a, c, d);
}

}  // namespace

Mesh open_cylinder(double radius, double length, int n_around, int n_along)
{
    if (radius <= 0 || length <= 0 || n_around < 3 || n_along < 1)
        throw InvalidInputError("open_cylinder: need radius > 0, length > 0, n_around >= 3, "
                                "n_along >= 1");
    Mesh mesh;
    std::vector<VertexHandle> v((n_along + 1) * n_around);
    for (int j = 0; j <= n_along; ++j)
        for (int i = 0; i < n_around; ++i)
        {
            const double t = 2.0 * M_PI * i / n_around;
            v[j * n_around + i] = mesh.add_vertex(
                {radius * std::cos(t), radius * std::sin(t), length * j / n_along});
        }
    for (int j = 0; j < n_along; ++j)
        for (int i = 0; i < n_around; ++i)
        {
            const int i1 = (i + 1) % n_around;
            add_quad(mesh, v[j * n_around + i], v[j * n_around + i1], v[(j + 1) * n_around + i1],
                     v[(j + 1) * n_around + i]);
        }
    return mesh;
}

Mesh torus(double R, double r, int n_major, int n_minor)
{
    if (R <= r || r <= 0 || n_major < 3 || n_minor < 3)
        throw InvalidInputError("torus: need R > r > 0 and at least 3 segments each way");
    Mesh mesh;
    std::vector<VertexHandle> v(n_major * n_minor);
    for (int i = 0; i < n_major; ++i)
        for (int j = 0; j < n_minor; ++j)
        {
            const double u = 2.0 * M_PI * i / n_major, w = 2.0 * M_PI * j / n_minor;
            v[i * n_minor + j] = mesh.add_vertex({(R + r * std::cos(w)) * std::cos(u),
                                                  (R + r * std::cos(w)) * std::sin(u),
                                                  r * std::sin(w)});
        }
    for (int i = 0; i < n_major; ++i)
        for (int j = 0; j < n_minor; ++j)
        {
            const int i1 = (i + 1) % n_major, j1 = (j + 1) % n_minor;
            add_quad(mesh, v[i * n_minor + j], v[i1 * n_minor + j], v[i1 * n_minor + j1],
                     v[i * n_minor + j1]);
        }
    return mesh;
}

Mesh icosphere(double radius, int subdivisions)
{
    if (radius <= 0 || subdivisions < 0)
        throw InvalidInputError("icosphere: need radius > 0 and subdivisions >= 0");
    const double p = (1.0 + std::sqrt(5.0)) / 2.0;
    std::vector<Eigen::Vector3d> points = {{-1, p, 0}, {1, p, 0},  {-1, -p, 0}, {1, -p, 0},
                                           {0, -1, p}, {0, 1, p},  {0, -1, -p}, {0, 1, -p},
                                           {p, 0, -1}, {p, 0, 1},  {-p, 0, -1}, {-p, 0, 1}};
    std::vector<std::array<int, 3>> faces = {
        {0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
        {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
        {3, 8, 9},  {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
    for (int s = 0; s < subdivisions; ++s)
    {
        std::map<std::pair<int, int>, int> midpoint;
        auto mid = [&](int a, int b) {
            auto key = std::minmax(a, b);
            auto it = midpoint.find(key);
            if (it != midpoint.end())
                return it->second;
            points.push_back(0.5 * (points[a] + points[b]));
            return midpoint[key] = static_cast<int>(points.size()) - 1;
        };
        std::vector<std::array<int, 3>> next;
        for (auto [a, b, c] : faces)
        {
            const int ab = mid(a, b), bc = mid(b, c), ca = mid(c, a);
            next.push_back({a, ab, ca});
            next.push_back({b, bc, ab});
            next.push_back({c, ca, bc});
            next.push_back({ab, bc, ca});
        }
        faces = std::move(next);
    }
    Mesh mesh;
    std::vector<VertexHandle> v;
    for (const auto& q : points)
        v.push_back(mesh.add_vertex(to_openmesh(radius * q.normalized())));
    for (auto [a, b, c] : faces)
        mesh.add_face(v[a], v[b], v[c]);
    return mesh;
}

Mesh plane_grid(double size, int n)
{
    if (size <= 0 || n < 1)
        throw InvalidInputError("plane_grid: need size > 0 and n >= 1");
    Mesh mesh;
    std::vector<VertexHandle> v((n + 1) * (n + 1));
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i)
            v[j * (n + 1) + i] = mesh.add_vertex({size * i / n, size * j / n, 0.0});
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i)
            add_quad(mesh, v[j * (n + 1) + i], v[j * (n + 1) + i + 1],
                     v[(j + 1) * (n + 1) + i + 1], v[(j + 1) * (n + 1) + i]);
    return mesh;
}

// ---------------------------------------------------------------------------------------------
// Helical tube
// ---------------------------------------------------------------------------------------------

void HelicalTubeOptions::validate() const
{
    auto fail = [](const std::string& what) {
        throw InvalidInputError("HelicalTubeOptions: " + what);
    };
    if (!(tube_radius > 0.0))
        fail("tube_radius must be > 0");
    if (!(helix_radius >= 0.0))
        fail("helix_radius must be >= 0");
    if (!(pitch > 0.0))
        fail("pitch must be > 0");
    if (!(turns > 0.0))
        fail("turns must be > 0");
    if (n_around < 3)
        fail("n_around must be >= 3 (got " + std::to_string(n_around) + ")");
    const double around = 2.0 * M_PI * tube_radius / n_around;
    if (!(edge_length >= 0.0) || (edge_length > 0.0 && edge_length <= 0.55 * around))
        fail("edge_length must be 0 or > 0.55 * 2 pi tube_radius / n_around (" +
             std::to_string(0.55 * around) + ")");
    const double h = pitch / (2.0 * M_PI);
    if (helix_radius > 0.0 && tube_radius >= (helix_radius * helix_radius + h * h) / helix_radius)
        fail("tube_radius must be below the centerline's radius of curvature "
             "(helix_radius^2 + (pitch / 2 pi)^2) / helix_radius");
    if (turns > 1.0 && helix_radius >= tube_radius && pitch <= 2.0 * tube_radius)
        fail("pitch must exceed 2 * tube_radius when turns > 1, or the coils touch");
}

namespace {

// Closed-form rotation-minimizing frame of the helix c(t) = (R cos t, R sin t, h t): the frame
// normal turns against the Frenet normal at the torsion rate, theta(s) = -tau s, with
// tau = h / L^2 and ds/dt = L = sqrt(R^2 + h^2).
struct HelixFrame
{
    Eigen::Vector3d c, T, U, V;
};

HelixFrame helix_frame(double R, double h, double t)
{
    const double L = std::sqrt(R * R + h * h);
    const double ct = std::cos(t), st = std::sin(t);
    HelixFrame f;
    f.c = {R * ct, R * st, h * t};
    f.T = Eigen::Vector3d(-R * st, R * ct, h) / L;
    const Eigen::Vector3d N(-ct, -st, 0.0);
    const Eigen::Vector3d B = Eigen::Vector3d(h * st, -h * ct, R) / L;
    const double theta = -(h / L) * t;
    f.U = std::cos(theta) * N + std::sin(theta) * B;
    f.V = std::cos(theta) * B - std::sin(theta) * N;
    return f;
}

}  // namespace

Eigen::Vector3d helical_tube_point(const HelicalTubeOptions& options, double u, double angle,
                                   double radius)
{
    const double h = options.pitch / (2.0 * M_PI);
    const HelixFrame f = helix_frame(options.helix_radius, h, 2.0 * M_PI * options.turns * u);
    return f.c + radius * (std::cos(angle) * f.U + std::sin(angle) * f.V);
}

double helical_tube_angle(const HelicalTubeOptions& options, const Eigen::Vector3d& p)
{
    const double R = options.helix_radius;
    const double h = options.pitch / (2.0 * M_PI);
    // Initial guess: the azimuth of p, unwrapped onto the coil closest in height.
    double t = p.z() / h;
    if (R > 1e-9 * options.tube_radius)
    {
        const double phi = std::atan2(p.y(), p.x());
        t = phi + 2.0 * M_PI * std::round((p.z() / h - phi) / (2.0 * M_PI));
    }
    // Newton on d/dt |c(t) - p|^2 / 2 = (c - p) . c' = 0.
    for (int it = 0; it < 50; ++it)
    {
        const double ct = std::cos(t), st = std::sin(t);
        const Eigen::Vector3d d(R * ct - p.x(), R * st - p.y(), h * t - p.z());
        const Eigen::Vector3d c1(-R * st, R * ct, h);
        const Eigen::Vector3d c2(-R * ct, -R * st, 0.0);
        const double g = d.dot(c1);
        double gp = c1.squaredNorm() + d.dot(c2);
        if (gp < 0.1 * c1.squaredNorm())
            gp = 0.1 * c1.squaredNorm();  // far from the tube: fall back to a damped step
        const double step = g / gp;
        t -= std::clamp(step, -1.0, 1.0);
        if (std::abs(step) < 1e-15 * (1.0 + std::abs(t)))
            break;
    }
    const HelixFrame f = helix_frame(R, h, t);
    const Eigen::Vector3d d = p - f.c;
    return std::atan2(d.dot(f.V), d.dot(f.U));
}

Mesh helical_tube(const HelicalTubeOptions& options)
{
    options.validate();
    const int n = options.n_around;
    const double r = options.tube_radius;
    const double h = options.pitch / (2.0 * M_PI);
    const double L = std::sqrt(options.helix_radius * options.helix_radius + h * h);
    const double t_end = 2.0 * M_PI * options.turns;
    const double around = 2.0 * M_PI * r / n;
    const double slant = options.edge_length > 0.0 ? options.edge_length : around;
    const double ring_spacing = std::sqrt(slant * slant - 0.25 * around * around);
    const int n_rings = std::max(1, static_cast<int>(std::lround(L * t_end / ring_spacing)));

    Mesh mesh;
    std::vector<VertexHandle> v((n_rings + 1) * n);
    for (int j = 0; j <= n_rings; ++j)
        for (int i = 0; i < n; ++i)
        {
            const double angle = 2.0 * M_PI * (i + 0.5 * j) / n;
            v[j * n + i] = mesh.add_vertex(
                to_openmesh(helical_tube_point(options, double(j) / n_rings, angle, r)));
        }
    // (U, V, T) is right-handed, so increasing angle runs counter-clockwise seen from ahead:
    // (a, b, c) below has normal ~ e_angle x T, i.e. outward.
    for (int j = 0; j < n_rings; ++j)
        for (int i = 0; i < n; ++i)
        {
            const int i1 = (i + 1) % n;
            const VertexHandle a = v[j * n + i], b = v[j * n + i1];
            const VertexHandle c = v[(j + 1) * n + i], d = v[(j + 1) * n + i1];
            mesh.add_face(a, b, c);
            mesh.add_face(b, d, c);
        }
    return mesh;
}

// ---------------------------------------------------------------------------------------------
// Implicit vessel surfaces (shared by carotid_phantom and tree_phantom)
// ---------------------------------------------------------------------------------------------

namespace {

// Polynomial smooth minimum: exact min when |a - b| >= k, a fillet of depth k / 4 otherwise.
double smooth_min(double a, double b, double k)
{
    const double g = std::max(k - std::abs(a - b), 0.0) / k;
    return std::min(a, b) - 0.25 * g * g * k;
}

// A straight piece of centerline from a to b whose radius is radius(s), s = arc length from a.
struct Tube
{
    Eigen::Vector3d a, b;
    std::function<double(double)> radius;
    double max_radius = 0.0;
    Eigen::AlignedBox3d box;  // where the tube can change the field (see VesselField)

    double distance(const Eigen::Vector3d& x) const
    {
        const Eigen::Vector3d ab = b - a;
        const double len2 = ab.squaredNorm();
        const double t = std::clamp((x - a).dot(ab) / len2, 0.0, 1.0);
        return (x - a - t * ab).norm() - radius(t * std::sqrt(len2));
    }
};

// Smooth union of tubes; negative inside. Far from every tube the field saturates at `outside`.
// A tube only enters the fold where its inflated box contains x; the box is inflated so that
// outside it the tube's distance exceeds outside + blend, where smooth_min(f, d) = f exactly, so
// the field is continuous and identical whether evaluated point-wise or on the grid.
class VesselField
{
public:
    VesselField(double blend, double outside) : blend_(blend), outside_(outside) {}

    void add_tube(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                  std::function<double(double)> radius)
    {
        Tube tube{a, b, std::move(radius), 0.0, {}};
        const double len = (b - a).norm();
        for (int i = 0; i <= 256; ++i)
            tube.max_radius = std::max(tube.max_radius, tube.radius(len * i / 256.0));
        const double inflate = tube.max_radius * 1.05 + outside_ + blend_ + 1e-9;
        tube.box.extend(a);
        tube.box.extend(b);
        tube.box.min().array() -= inflate;
        tube.box.max().array() += inflate;
        tubes_.push_back(std::move(tube));
    }

    double operator()(const Eigen::Vector3d& x) const
    {
        double f = outside_;
        for (const auto& tube : tubes_)
            if (tube.box.contains(x))
                f = smooth_min(f, tube.distance(x), blend_);
        return f;
    }

    Eigen::Vector3d gradient(const Eigen::Vector3d& x, double step) const
    {
        Eigen::Vector3d g;
        for (int i = 0; i < 3; ++i)
        {
            Eigen::Vector3d e = Eigen::Vector3d::Zero();
            e[i] = step;
            g[i] = ((*this)(x + e) - (*this)(x - e)) / (2.0 * step);
        }
        return g;
    }

    const std::vector<Tube>& tubes() const { return tubes_; }
    double outside() const { return outside_; }
    double blend() const { return blend_; }

private:
    double blend_, outside_;
    std::vector<Tube> tubes_;
};

// A vessel end: the surface is cut by the plane through `center` with normal `normal` (pointing
// away from the kept vessel); everything beyond it, within the end's region, is discarded.
struct EndPlane
{
    Eigen::Vector3d center, normal;
    double radius = 0.0;  // vessel radius at the end
    double extent = 0.0;  // how far beyond the plane the (capped) implicit tube reaches

    // Signed distance beyond the plane, or nullopt-like NaN when x is not in the end's region.
    double beyond(const Eigen::Vector3d& x, double h) const
    {
        const Eigen::Vector3d d = x - center;
        const double a = d.dot(normal);
        const double radial = (d - a * normal).norm();
        if (a < -3.0 * h || a > extent + 3.0 * h || radial > 1.5 * radius + 3.0 * h)
            return std::numeric_limits<double>::quiet_NaN();
        return a;
    }
};

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

// Closed implicit surface -> manifold mesh -> open ends -> better triangles, retrying on a
// shifted grid should the sampling ever produce a wrong topology.
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

}  // namespace

// ---------------------------------------------------------------------------------------------
// Carotid bifurcation
// ---------------------------------------------------------------------------------------------

void CarotidPhantomOptions::validate() const
{
    auto fail = [](const std::string& what) {
        throw InvalidInputError("CarotidPhantomOptions: " + what);
    };
    if (!(cca_radius > 0.0) || !(ica_radius > 0.0) || !(eca_radius > 0.0))
        fail("cca_radius, ica_radius and eca_radius must be > 0");
    if (ica_radius > cca_radius || eca_radius > cca_radius)
        fail("the branches (ica_radius, eca_radius) must not be wider than cca_radius");
    if (!(branch_angle_deg >= 10.0 && branch_angle_deg <= 60.0))
        fail("branch_angle_deg must be in [10, 60] (got " + std::to_string(branch_angle_deg) +
             ")");
    if (!(stenosis >= 0.0 && stenosis <= 0.8))
        fail("stenosis must be in [0, 0.8] (got " + std::to_string(stenosis) + ")");
    if (!(edge_length > 0.0))
        fail("edge_length must be > 0");
    if (edge_length > 0.6 * std::min(ica_radius, eca_radius))
        fail("edge_length must be <= 0.6 * min(ica_radius, eca_radius) (" +
             std::to_string(0.6 * std::min(ica_radius, eca_radius)) +
             ") so that each vessel gets at least ~10 edges around");
    const double min_length = 3.0 * cca_radius + 2.0 * edge_length;
    if (!(cca_length >= min_length) || !(ica_length >= min_length) ||
        !(eca_length >= min_length))
        fail("cca_length, ica_length and eca_length must be >= 3 * cca_radius + 2 * "
             "edge_length (" + std::to_string(min_length) + ")");
}

Mesh carotid_phantom(const CarotidPhantomOptions& options)
{
    options.validate();
    const CarotidPhantomOptions o = options;
    // ICA profile: sinus bulb just past the bifurcation, then a Gaussian narrowing whose throat
    // has (1 - stenosis) times the local diameter.
    const double bulb_at = 0.2 * o.ica_length, bulb_width = 0.12 * o.ica_length;
    const double stenosis_at = 0.45 * o.ica_length, stenosis_width = 0.1 * o.ica_length;
    auto ica_radius = [o, bulb_at, bulb_width, stenosis_at, stenosis_width](double s) {
        const double bulb = 0.3 * std::exp(-std::pow((s - bulb_at) / bulb_width, 2));
        const double narrowing =
            o.stenosis * std::exp(-std::pow((s - stenosis_at) / stenosis_width, 2));
        return o.ica_radius * (1.0 + bulb) * (1.0 - narrowing);
    };
    const double r_min = std::min(o.eca_radius, o.ica_radius * (1.0 - o.stenosis));
    const double h = std::min(o.edge_length, r_min / 1.6);
    const double blend = 0.6 * std::min(o.ica_radius, o.eca_radius);
    VesselField field(blend, 3.0 * h + blend);

    // CCA along +z ending at the bifurcation (origin); branches in the x-z plane.
    const double angle = o.branch_angle_deg * M_PI / 180.0;
    const Eigen::Vector3d z(0, 0, 1);
    const Eigen::Vector3d ica_dir(std::sin(angle), 0, std::cos(angle));
    const Eigen::Vector3d eca_dir(-std::sin(angle), 0, std::cos(angle));
    auto extension = [h](double r) { return r + 3.0 * h; };  // capped overshoot past each end
    const double cca_r = o.cca_radius, eca_r = o.eca_radius;
    field.add_tube(-(o.cca_length + extension(cca_r)) * z, Eigen::Vector3d::Zero(),
                   [cca_r](double) { return cca_r; });
    field.add_tube(Eigen::Vector3d::Zero(), (o.ica_length + extension(o.ica_radius)) * ica_dir,
                   ica_radius);
    field.add_tube(Eigen::Vector3d::Zero(), (o.eca_length + extension(eca_r)) * eca_dir,
                   [eca_r](double) { return eca_r; });

    std::vector<EndPlane> ends;
    ends.push_back({-o.cca_length * z, -z, cca_r, extension(cca_r) + cca_r});
    ends.push_back({o.ica_length * ica_dir, ica_dir, ica_radius(o.ica_length),
                    extension(o.ica_radius) + o.ica_radius});
    ends.push_back({o.eca_length * eca_dir, eca_dir, eca_r, extension(eca_r) + eca_r});
    return vessel_surface(field, ends, h, "carotid_phantom");
}

// ---------------------------------------------------------------------------------------------
// Random vessel tree
// ---------------------------------------------------------------------------------------------

void TreePhantomOptions::validate() const
{
    auto fail = [](const std::string& what) {
        throw InvalidInputError("TreePhantomOptions: " + what);
    };
    if (outlets < 1 || outlets > 30)
        fail("outlets must be in [1, 30] (got " + std::to_string(outlets) + ")");
    if (!(root_radius > 0.0))
        fail("root_radius must be > 0");
    if (!(edge_length > 0.0))
        fail("edge_length must be > 0");
    if (edge_length > 0.5 * root_radius)
        fail("edge_length must be <= root_radius / 2 (" + std::to_string(0.5 * root_radius) +
             ")");
}

namespace {

// Draws from std::mt19937, whose output sequence the standard fixes, through hand-written
// distributions (the std:: distributions differ between standard libraries).
class Random
{
public:
    explicit Random(std::uint32_t seed) : engine_(seed) {}
    double uniform(double lo, double hi)
    {
        return lo + (hi - lo) * static_cast<double>(engine_() >> 8) * (1.0 / 16777216.0);
    }
    //! Uniform integer in [0, n).
    int below(int n)
    {
        return static_cast<int>((static_cast<std::uint64_t>(engine_()) * std::uint64_t(n)) >> 32);
    }

private:
    std::mt19937 engine_;
};

// Smallest distance between segments [p0, p1] and [q0, q1] (Ericson, Real-Time Collision
// Detection, 5.1.9).
double segment_distance(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                        const Eigen::Vector3d& q0, const Eigen::Vector3d& q1)
{
    const Eigen::Vector3d d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
    const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
    double s = 0.0, t = 0.0;
    if (a <= 1e-300 && e <= 1e-300)
        return r.norm();
    if (a <= 1e-300)
        t = std::clamp(f / e, 0.0, 1.0);
    else
    {
        const double c = d1.dot(r);
        if (e <= 1e-300)
            s = std::clamp(-c / a, 0.0, 1.0);
        else
        {
            const double b = d1.dot(d2), denom = a * e - b * b;
            s = denom > 1e-14 * a * e ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
            t = (b * s + f) / e;
            if (t < 0.0)
            {
                t = 0.0;
                s = std::clamp(-c / a, 0.0, 1.0);
            }
            else if (t > 1.0)
            {
                t = 1.0;
                s = std::clamp((b - c) / a, 0.0, 1.0);
            }
        }
    }
    return ((p0 + s * d1) - (q0 + t * d2)).norm();
}

struct TreeNode
{
    int parent = -1;
    int outlets = 0;
    double wedge_lo = 0.0, wedge_hi = 0.0;  // angular sector of the subtree, radians from +y
    double rho = 0.0;                       // distance from the first bifurcation, in the plane
    double radius = 0.0;                    // radius of the vessel ending at this node
    Eigen::Vector3d position = Eigen::Vector3d::Zero();
    std::vector<int> children;
};

// One attempt at laying out the tree: a radial layout in which every subtree keeps to its own
// angular sector, sized by its outlet count, and every node lies farther from the first
// bifurcation than its parent, so that subtrees cannot cross; a little out-of-plane jitter keeps
// it from being flat. Returns false if a clearance, branching-angle or bend check fails.
bool layout_tree(const TreePhantomOptions& o, Random& random, double scale, double h,
                 double blend, std::vector<TreeNode>& nodes)
{
    const int N = o.outlets;
    const double r_min = 2.0 * o.edge_length;
    auto radius_of = [&](int n) { return std::max(o.root_radius * std::cbrt(double(n) / N), r_min); };
    const double half_wedge = 75.0 * M_PI / 180.0;

    nodes.clear();
    TreeNode inlet;
    inlet.position = Eigen::Vector3d(0, -6.0 * o.root_radius * scale, 0);
    nodes.push_back(inlet);
    TreeNode first;
    first.parent = 0;
    first.outlets = N;
    first.wedge_lo = -half_wedge;
    first.wedge_hi = half_wedge;
    first.radius = o.root_radius;
    nodes.push_back(first);
    nodes[0].children.push_back(1);

    for (std::size_t k = 1; k < nodes.size(); ++k)  // breadth-first; nodes grows as we go
    {
        const int n = nodes[k].outlets;
        if (n == 1)
            continue;
        const int lo = std::max(1, n / 4), hi = std::min(n - 1, n - n / 4);
        const int n1 = lo + random.below(hi - lo + 1);
        const double width = nodes[k].wedge_hi - nodes[k].wedge_lo;
        const double split = nodes[k].wedge_lo + width * n1 / n;
        for (int side = 0; side < 2; ++side)
        {
            TreeNode child;
            child.parent = static_cast<int>(k);
            child.outlets = side == 0 ? n1 : n - n1;
            child.wedge_lo = side == 0 ? nodes[k].wedge_lo : split;
            child.wedge_hi = side == 0 ? split : nodes[k].wedge_hi;
            child.radius = radius_of(child.outlets);
            const double child_width = child.wedge_hi - child.wedge_lo;
            const double phi = 0.5 * (child.wedge_lo + child.wedge_hi) +
                               random.uniform(-0.15, 0.15) * child_width;
            double length = random.uniform(3.5, 6.0) * nodes[k].radius * scale;
            length = std::max(length, 2.5 * nodes[k].radius + 2.5 * child.radius + 4.0 * h);
            // Far enough out for the vessel to fit inside its own sector.
            const double needed = (1.3 * child.radius + 1.5 * h + 0.5 * blend) /
                                  std::sin(std::min(0.5 * child_width, 1.2));
            child.rho = std::max(nodes[k].rho + length, needed);
            const double z = nodes[k].position.z() +
                             random.uniform(-0.15, 0.15) * (child.rho - nodes[k].rho);
            child.position = Eigen::Vector3d(child.rho * std::sin(phi), child.rho * std::cos(phi), z);
            nodes[k].children.push_back(static_cast<int>(nodes.size()));
            nodes.push_back(child);
        }
    }

    // Segment k runs from its parent to node k; outlets and inlet include their capped overshoot.
    struct Segment
    {
        Eigen::Vector3d a, b;
        double r;
        int from, to;
    };
    std::vector<Segment> segments;
    for (std::size_t k = 1; k < nodes.size(); ++k)
    {
        Eigen::Vector3d a = nodes[nodes[k].parent].position, b = nodes[k].position;
        const double r = nodes[k].radius;
        const Eigen::Vector3d dir = (b - a).normalized();
        if (nodes[k].children.empty())
            b += (2.0 * r + 3.0 * h) * dir;
        if (nodes[k].parent == 0)
            a -= (2.0 * r + 3.0 * h) * dir;
        segments.push_back({a, b, r, nodes[k].parent, static_cast<int>(k)});
    }
    for (std::size_t i = 0; i < segments.size(); ++i)
        for (std::size_t j = i + 1; j < segments.size(); ++j)
        {
            const auto &s = segments[i], &t = segments[j];
            const bool adjacent =
                s.from == t.from || s.from == t.to || s.to == t.from || s.to == t.to;
            if (adjacent)
            {
                // Siblings must diverge; a child must not fold back onto its parent.
                const Eigen::Vector3d ds = (s.b - s.a).normalized(), dt = (t.b - t.a).normalized();
                const double cos_angle = ds.dot(dt);
                if (s.from == t.from && cos_angle > std::cos(25.0 * M_PI / 180.0))
                    return false;
                if ((s.to == t.from || t.to == s.from) && cos_angle < std::cos(80.0 * M_PI / 180.0))
                    return false;
                continue;
            }
            const double clearance = 1.5 * (s.r + t.r) + 3.0 * h + blend;
            if (segment_distance(s.a, s.b, t.a, t.b) < clearance)
                return false;
        }
    return true;
}

}  // namespace

Mesh tree_phantom(const TreePhantomOptions& options)
{
    options.validate();
    const double h = options.edge_length;
    const double r_min = std::max(options.root_radius * std::cbrt(1.0 / options.outlets),
                                  2.0 * options.edge_length);
    const double blend = 0.4 * r_min;
    Random random(options.seed);
    std::vector<TreeNode> nodes;
    bool found = false;
    for (int attempt = 0; attempt < 200 && !found; ++attempt)
        found = layout_tree(options, random, std::pow(1.05, attempt / 10), h, blend, nodes);
    if (!found)
        throw TopologyError("tree_phantom: could not lay out " + std::to_string(options.outlets) +
                            " outlets without overlapping vessels; try another seed");

    VesselField field(blend, 3.0 * h + blend);
    std::vector<EndPlane> ends;
    for (std::size_t k = 1; k < nodes.size(); ++k)
    {
        const TreeNode& node = nodes[k];
        Eigen::Vector3d a = nodes[node.parent].position, b = node.position;
        const Eigen::Vector3d dir = (b - a).normalized();
        const double r = node.radius, overshoot = r + 3.0 * h;
        if (node.parent == 0)
        {
            ends.push_back({a, -dir, r, overshoot + r});
            a -= overshoot * dir;
        }
        if (node.children.empty())
        {
            ends.push_back({b, dir, r, overshoot + r});
            b += overshoot * dir;
        }
        field.add_tube(a, b, [r](double) { return r; });
    }
    return vessel_surface(field, ends, h, "tree_phantom");
}

}  // namespace vessel
