#include "vessel/phantom.h"

#include "vessel/errors.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <sstream>
#include <string>

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

}  // namespace vessel
