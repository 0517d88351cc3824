#include "vessel/phantom/phantom.h"

#include "vessel/core/errors.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace vessel {

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
