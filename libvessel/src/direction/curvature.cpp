#include "vessel/direction/curvature.h"

#include "vessel/core/errors.h"

#include <Eigen/Dense>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <string>
#include <thread>
#include <vector>

namespace vessel {

namespace {

// Flat copies of what the per-vertex fits read: the OpenMesh circulators are much slower than
// a compressed adjacency list when every vertex visits ~100 neighbours.
struct FitInput
{
    std::vector<Eigen::Vector3d> points;
    std::vector<Eigen::Vector3d> normals;  // area-weighted, not normalized
    std::vector<int> offsets;              // neighbours of i: adjacency[offsets[i] .. offsets[i+1])
    std::vector<int> adjacency;
};

FitInput make_fit_input(const Mesh& mesh)
{
    const int n = static_cast<int>(mesh.n_vertices());
    FitInput in;
    in.points.resize(n);
    in.normals.assign(n, Eigen::Vector3d::Zero());
    in.offsets.assign(n + 1, 0);
    for (auto v : mesh.vertices())
    {
        in.points[v.idx()] = to_eigen(mesh.point(v));
        in.offsets[v.idx() + 1] = static_cast<int>(v.valence());
    }
    for (int i = 0; i < n; ++i)
        in.offsets[i + 1] += in.offsets[i];
    in.adjacency.resize(in.offsets[n]);
    for (auto v : mesh.vertices())
    {
        int k = in.offsets[v.idx()];
        for (auto w : v.vertices())
            in.adjacency[k++] = w.idx();
    }
    for (auto f : mesh.faces())
    {
        auto h = f.halfedge();
        const Eigen::Vector3d a = in.points[h.from().idx()];
        const Eigen::Vector3d b = in.points[h.to().idx()];
        const Eigen::Vector3d c = in.points[h.next().to().idx()];
        // |cross| = 2 * area, so summing cross products weights face normals by area.
        const Eigen::Vector3d cross = (b - a).cross(c - a);
        for (auto v : f.vertices())
            in.normals[v.idx()] += cross;
    }
    return in;
}

struct VertexCurvature
{
    Eigen::Vector3d min_direction, max_direction;
    double k_min = 0.0, k_max = 0.0;
};

// Per-thread scratch: a visit stamp per vertex avoids clearing an n-sized array per vertex.
struct Workspace
{
    std::vector<int> stamp;
    int current = 0;
    std::vector<int> inside;   // vertices of the neighbourhood (without the centre)
    std::vector<int> outside;  // visited neighbours beyond the ball: the next ring if needed
    std::vector<int> next;
};

// Collects the vertices reachable from i through edges without leaving the ball of the given
// radius; if that leaves fewer than min_neighbors, whole rings are added until it does not (or
// the component is exhausted).
void gather_neighbourhood(const FitInput& in, int i, double radius, int min_neighbors,
                          Workspace& ws)
{
    ++ws.current;
    ws.inside.clear();
    ws.outside.clear();
    const double r2 = radius * radius;
    const Eigen::Vector3d& p = in.points[i];
    ws.stamp[i] = ws.current;
    ws.inside.push_back(i);  // temporarily, as the BFS queue head
    for (size_t q = 0; q < ws.inside.size(); ++q)
    {
        const int a = ws.inside[q];
        for (int k = in.offsets[a]; k < in.offsets[a + 1]; ++k)
        {
            const int b = in.adjacency[k];
            if (ws.stamp[b] == ws.current)
                continue;
            ws.stamp[b] = ws.current;
            if ((in.points[b] - p).squaredNorm() <= r2)
                ws.inside.push_back(b);
            else
                ws.outside.push_back(b);
        }
    }
    while (static_cast<int>(ws.inside.size()) - 1 < min_neighbors && !ws.outside.empty())
    {
        ws.next.clear();
        for (int a : ws.outside)
        {
            ws.inside.push_back(a);
            for (int k = in.offsets[a]; k < in.offsets[a + 1]; ++k)
            {
                const int b = in.adjacency[k];
                if (ws.stamp[b] != ws.current)
                {
                    ws.stamp[b] = ws.current;
                    ws.next.push_back(b);
                }
            }
        }
        std::swap(ws.outside, ws.next);
    }
    ws.inside.erase(ws.inside.begin());  // drop the centre: it adds nothing to the fit
}

Eigen::Vector3d any_perpendicular(const Eigen::Vector3d& n)
{
    const Eigen::Vector3d axis = std::abs(n.x()) < 0.9 ? Eigen::Vector3d::UnitX()
                                                        : Eigen::Vector3d::UnitY();
    return n.cross(axis).normalized();
}

VertexCurvature fit_vertex(const FitInput& in, int i, double radius, int min_neighbors,
                           Workspace& ws)
{
    VertexCurvature out;
    const double normal_norm = in.normals[i].norm();
    const Eigen::Vector3d n =
        normal_norm > 0.0 ? Eigen::Vector3d(in.normals[i] / normal_norm) : Eigen::Vector3d::UnitZ();
    const Eigen::Vector3d eu = any_perpendicular(n);
    const Eigen::Vector3d ev = n.cross(eu);
    out.min_direction = eu;
    out.max_direction = ev;
    if (!(normal_norm > 0.0))
        return out;  // isolated or fully degenerate vertex: no surface to fit, report flat

    gather_neighbourhood(in, i, radius, min_neighbors, ws);

    // Least squares for h(x, y) = a x^2 + b xy + c y^2 + d x + e y through the centre, in
    // coordinates divided by the radius so the normal equations stay well conditioned.
    // The normal equations only involve 12 distinct moments x^i y^j (2 <= i + j <= 4) and 5
    // right-hand side sums; accumulating those is several times faster than rank updates.
    double x4 = 0, x3y = 0, x2y2 = 0, xy3 = 0, y4 = 0, x3 = 0, x2y = 0, xy2 = 0, y3 = 0, x2 = 0,
           xy = 0, y2 = 0, zx2 = 0, zxy = 0, zy2 = 0, zx = 0, zy = 0;
    const double inv_r = 1.0 / radius;
    for (int j : ws.inside)
    {
        const Eigen::Vector3d q = (in.points[j] - in.points[i]) * inv_r;
        const double x = q.dot(eu), y = q.dot(ev), z = q.dot(n);
        const double xx = x * x, xy_ = x * y, yy = y * y;
        x4 += xx * xx, x3y += xx * xy_, x2y2 += xx * yy, xy3 += xy_ * yy, y4 += yy * yy;
        x3 += xx * x, x2y += xx * y, xy2 += x * yy, y3 += yy * y;
        x2 += xx, xy += xy_, y2 += yy;
        zx2 += z * xx, zxy += z * xy_, zy2 += z * yy, zx += z * x, zy += z * y;
    }
    // Unknowns (a, b, c, d, e) multiply the monomials (x^2, xy, y^2, x, y).
    Eigen::Matrix<double, 5, 5> AtA;
    AtA << x4, x3y, x2y2, x3, x2y,  //
        x3y, x2y2, xy3, x2y, xy2,   //
        x2y2, xy3, y4, xy2, y3,     //
        x3, x2y, xy2, x2, xy,       //
        x2y, xy2, y3, xy, y2;
    const Eigen::Matrix<double, 5, 1> Atz(zx2, zxy, zy2, zx, zy);

    double a = 0, b = 0, c = 0, d = 0, e = 0;
    const Eigen::LDLT<Eigen::Matrix<double, 5, 5>> ldlt(AtA);
    const auto D = ldlt.vectorD();
    if (ldlt.info() == Eigen::Success && D.minCoeff() > 1e-10 * std::max(D.maxCoeff(), 1e-300))
    {
        const Eigen::Matrix<double, 5, 1> s = ldlt.solve(Atz);
        a = s[0], b = s[1], c = s[2], d = s[3], e = s[4];
    }
    else
    {
        // Too few or collinear neighbours (e.g. a vertex on a one-triangle-wide strip): fit the
        // curvature terms alone, trusting the vertex normal for the tangent plane.
        const Eigen::Matrix3d A3 = AtA.topLeftCorner<3, 3>();
        const Eigen::LDLT<Eigen::Matrix3d> ldlt3(A3);
        const auto D3 = ldlt3.vectorD();
        if (ldlt3.info() != Eigen::Success || !(D3.minCoeff() > 1e-10 * D3.maxCoeff()))
            return out;
        const Eigen::Vector3d s = ldlt3.solve(Atz.head<3>());
        a = s[0], b = s[1], c = s[2];
    }
    a *= inv_r, b *= inv_r, c *= inv_r;  // back to unscaled coordinates; d, e are slopes

    // Graph surface X(x, y) = (x, y, h): X_x = (1, 0, d), X_y = (0, 1, e). First fundamental
    // form I, second fundamental form II w.r.t. the fitted normal (-d, -e, 1)/w, and shape
    // operator S = I^-1 II. The sign is flipped so that a surface bending away from its normal
    // (a sphere or cylinder with outward normals) has positive curvature.
    const double w = std::sqrt(1.0 + d * d + e * e);
    Eigen::Matrix2d I, II;
    I << 1.0 + d * d, d * e, d * e, 1.0 + e * e;
    II << 2.0 * a, b, b, 2.0 * c;
    II *= -1.0 / w;
    const Eigen::Matrix2d S = I.inverse() * II;
    const double half_trace = 0.5 * S.trace();
    const double det = S.determinant();
    const double disc = std::sqrt(std::max(half_trace * half_trace - det, 0.0));
    const double k1 = half_trace + disc, k2 = half_trace - disc;
    // Eigenvector of S for the smaller-magnitude curvature, in (x, y) parameter coordinates;
    // either row of S - kI gives one, the longer is the better conditioned.
    const double k_small = std::abs(k1) <= std::abs(k2) ? k1 : k2;
    const double k_large = std::abs(k1) <= std::abs(k2) ? k2 : k1;
    Eigen::Vector2d p1(S(0, 1), k_small - S(0, 0));
    Eigen::Vector2d p2(k_small - S(1, 1), S(1, 0));
    Eigen::Vector2d param = p1.squaredNorm() >= p2.squaredNorm() ? p1 : p2;
    if (!(param.squaredNorm() > 1e-24 * (S.squaredNorm() + 1e-300)))
        param = Eigen::Vector2d(1.0, 0.0);  // umbilic: every direction is principal
    const Eigen::Vector3d fitted_normal = ((n - d * eu - e * ev) / w).normalized();
    Eigen::Vector3d t_min = param[0] * (eu + d * n) + param[1] * (ev + e * n);
    t_min = (t_min - t_min.dot(fitted_normal) * fitted_normal).normalized();
    // Principal directions are orthogonal in 3D, so the second one follows from the first.
    out.min_direction = t_min;
    out.max_direction = fitted_normal.cross(t_min).normalized();
    out.k_min = k_small;
    out.k_max = k_large;
    return out;
}

}  // namespace

void CurvatureOptions::validate() const
{
    if (!(scale > 0.0) || !std::isfinite(scale))
        throw InvalidInputError("CurvatureOptions: scale = " + std::to_string(scale) +
                                " is not a positive finite number; use about 5 (ball radius in "
                                "mean edge lengths)");
    if (min_neighbors < 5)
        throw InvalidInputError("CurvatureOptions: min_neighbors = " +
                                std::to_string(min_neighbors) +
                                " is below 5, the number of quadric coefficients; use 8 or more");
}

PrincipalCurvature principal_curvature(const Mesh& mesh, const CurvatureOptions& options)
{
    options.validate();
    if (mesh.n_faces() == 0)
        throw InvalidInputError("principal_curvature: the mesh has no faces (" +
                                std::to_string(mesh.n_vertices()) +
                                " vertices); pass a triangle mesh");
    const int n = static_cast<int>(mesh.n_vertices());
    const FitInput in = make_fit_input(mesh);
    const double radius = options.scale * mean_edge_length(mesh);

    PrincipalCurvature result;
    result.min_direction.resize(n, 3);
    result.max_direction.resize(n, 3);
    result.k_min.resize(n);
    result.k_max.resize(n);

    // Vertices are handed out in blocks from a shared counter: neighbourhood sizes vary a lot
    // (boundaries, refined regions), so a static split would leave one core idle.
    constexpr int block = 512;
    std::atomic<int> next_block{0};
    auto work = [&] {
        Workspace ws;
        ws.stamp.assign(n, 0);
        for (int start = next_block.fetch_add(block); start < n; start = next_block.fetch_add(block))
        {
            const int end = std::min(n, start + block);
            for (int i = start; i < end; ++i)
            {
                const VertexCurvature k = fit_vertex(in, i, radius, options.min_neighbors, ws);
                result.min_direction.row(i) = k.min_direction.transpose();
                result.max_direction.row(i) = k.max_direction.transpose();
                result.k_min[i] = k.k_min;
                result.k_max[i] = k.k_max;
            }
        }
    };

    const unsigned hardware = std::max(1u, std::thread::hardware_concurrency());
    const unsigned n_threads =
        options.parallel ? std::min<unsigned>(hardware, std::max(1, n / block)) : 1u;
    std::vector<std::thread> threads;
    std::vector<std::exception_ptr> errors(n_threads);
    for (unsigned t = 1; t < n_threads; ++t)
        threads.emplace_back([&, t] {
            try
            {
                work();
            }
            catch (...)
            {
                errors[t] = std::current_exception();
            }
        });
    try
    {
        work();
    }
    catch (...)
    {
        errors[0] = std::current_exception();
    }
    for (auto& thread : threads)
        thread.join();
    for (const auto& error : errors)
        if (error)
            std::rethrow_exception(error);
    return result;
}

}  // namespace vessel
