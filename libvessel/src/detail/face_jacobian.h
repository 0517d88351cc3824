#pragma once

#include "vessel/core/mesh.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <thread>
#include <vector>

namespace vessel::detail {

//! Per-face constants of a map's Jacobian J = [[D0 u, D1 u], [D0 v, D1 v]] with respect to the
//! face's own isometric 2D frame, where Dk holds the coefficients of the three corners (J is
//! linear in the corners' uv). Used by the distortion energies (SLIM, untangling).
struct FaceOperator
{
    std::array<int, 3> corner{};  //!< vertex indices, in the face's halfedge order
    std::array<double, 3> d0{}, d1{};
    double area = 0.0;  //!< 3D area
};

//! The operator of the triangle (q0, q1, q2) whose corners are the map's vertices \p corner.
FaceOperator face_operator(const Eigen::Vector3d& q0, const Eigen::Vector3d& q1,
                           const Eigen::Vector3d& q2, const std::array<int, 3>& corner);
//! One operator per face, `f.idx()`.
std::vector<FaceOperator> face_operators(const Mesh& mesh);

//! Jacobian of the map x = [u_0, v_0, u_1, v_1, ...] on the face.
inline Eigen::Matrix2d jacobian(const FaceOperator& op, const double* x)
{
    Eigen::Matrix2d J = Eigen::Matrix2d::Zero();
    for (int k = 0; k < 3; ++k)
    {
        const double u = x[2 * op.corner[k]], v = x[2 * op.corner[k] + 1];
        J(0, 0) += op.d0[k] * u;
        J(0, 1) += op.d1[k] * u;
        J(1, 0) += op.d0[k] * v;
        J(1, 1) += op.d1[k] * v;
    }
    return J;
}

//! Adds dE/dJ = \p G of one face to \p gradient through the face's corners: corner vertex v
//! goes to entries 2 slot[v], 2 slot[v] + 1; corners with slot -1 are held fixed.
inline void add_face_gradient(const FaceOperator& op, const Eigen::Matrix2d& G,
                              const std::vector<int>& slot, double* gradient)
{
    for (int k = 0; k < 3; ++k)
    {
        const int s = slot[op.corner[k]];
        if (s < 0)
            continue;
        gradient[2 * s] += G(0, 0) * op.d0[k] + G(0, 1) * op.d1[k];
        gradient[2 * s + 1] += G(1, 0) * op.d0[k] + G(1, 1) * op.d1[k];
    }
}

//! \p uv (|V| x 2, row `v.idx()`) as the interleaved vector [u_0, v_0, u_1, v_1, ...] the face
//! operators read, with room for \p extra_vertices more (left at 0).
inline Eigen::VectorXd interleaved(const Eigen::MatrixX2d& uv, int extra_vertices = 0)
{
    Eigen::VectorXd x = Eigen::VectorXd::Zero(2 * (uv.rows() + extra_vertices));
    for (Eigen::Index v = 0; v < uv.rows(); ++v)
        x.segment<2>(2 * v) = uv.row(v).transpose();
    return x;
}

//! The first `uv.rows()` vertices of the interleaved \p x written back into \p uv.
inline void deinterleave(const Eigen::VectorXd& x, Eigen::MatrixX2d& uv)
{
    for (Eigen::Index v = 0; v < uv.rows(); ++v)
        uv.row(v) = x.segment<2>(2 * v).transpose();
}

//! Threads for per-face loops: two where they pay (the machines this runs on have two cores);
//! small meshes stay serial, where starting a thread costs more than it saves.
inline int face_threads(std::size_t faces)
{
    if (faces < 8192)
        return 1;
    return static_cast<int>(std::clamp(std::thread::hardware_concurrency(), 1u, 2u));
}

//! Calls body(begin, end, thread) on `threads` contiguous chunks of [0, count), in parallel.
//! The body must not throw.
template <class Body>
void parallel_chunks(std::size_t count, int threads, const Body& body)
{
    if (threads <= 1)
    {
        body(std::size_t{0}, count, 0);
        return;
    }
    std::vector<std::thread> pool;
    pool.reserve(threads - 1);
    for (int t = 1; t < threads; ++t)
        pool.emplace_back([&, t] { body(count * t / threads, count * (t + 1) / threads, t); });
    body(std::size_t{0}, count / threads, 0);
    for (auto& thread : pool)
        thread.join();
}

//! Largest step t in (0, 1] along d that keeps every triangle positively oriented (Smith and
//! Schaefer 2015): det of the corner-difference matrix is quadratic in t; the step stops at
//! \p shrink times its first positive root. Only ops[first ..] count (e.g. a scaffold's
//! triangles: first = the surface's face count). On up to two threads.
inline double max_injective_step(const std::vector<FaceOperator>& ops, const Eigen::VectorXd& x,
                                 const Eigen::VectorXd& d, int threads, std::size_t first = 0,
                                 double shrink = 0.8)
{
    std::array<double, 2> partial{1.0, 1.0};
    const int used = std::min(threads, 2);
    const std::size_t count = ops.size() - std::min(first, ops.size());
    parallel_chunks(count, used, [&](std::size_t begin, std::size_t end, int t) {
        double t_max = 1.0;
        for (std::size_t f = first + begin; f < first + end; ++f)
        {
            const FaceOperator& op = ops[f];
            const int i = op.corner[0], j = op.corner[1], k = op.corner[2];
            const double a1 = x[2 * j] - x[2 * i], a2 = x[2 * j + 1] - x[2 * i + 1];
            const double b1 = x[2 * k] - x[2 * i], b2 = x[2 * k + 1] - x[2 * i + 1];
            const double da1 = d[2 * j] - d[2 * i], da2 = d[2 * j + 1] - d[2 * i + 1];
            const double db1 = d[2 * k] - d[2 * i], db2 = d[2 * k + 1] - d[2 * i + 1];
            const double qa = da1 * db2 - da2 * db1;
            const double qb = a1 * db2 + da1 * b2 - a2 * db1 - da2 * b1;
            const double qc = a1 * b2 - a2 * b1;
            double root = std::numeric_limits<double>::infinity();
            if (std::abs(qa) < 1e-300)
            {
                if (qb < 0.0)
                    root = -qc / qb;
            }
            else
            {
                const double disc = qb * qb - 4.0 * qa * qc;
                if (disc >= 0.0)
                {
                    const double sq = std::sqrt(disc);
                    // Numerically stable pair of roots.
                    const double q = -0.5 * (qb + (qb >= 0 ? sq : -sq));
                    for (double r : {q / qa, qc / q})
                        if (r > 0.0)
                            root = std::min(root, r);
                }
            }
            t_max = std::min(t_max, shrink * root);
        }
        partial[t] = t_max;
    });
    return std::min(partial[0], partial[1]);
}

}  // namespace vessel::detail
