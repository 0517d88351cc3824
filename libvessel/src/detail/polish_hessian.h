#pragma once
// The derivatives of the area polish's energy (area_polish.h),
//   E = sum_t A_t ((1 - lambda) ||J_t||^2 / det J_t + lambda (det J_t + 1 / det J_t)):
// per face its gradient and projected Hessian with respect to J, and the Hessian's scatter into
// a sparse matrix of fixed pattern. Shared by the polish's Newton steps and the relaxation's
// coarse-grid corrections (coarse_correction.h).

#include "detail/face_jacobian.h"
#include "solve/paired_pattern.h"

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>

#include <Eigen/Sparse>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace vessel::detail {

// dE_t/dJ of one face per unit of its area (det J > 0).
inline Eigen::Matrix2d polish_face_gradient(const Eigen::Matrix2d& J, double lambda)
{
    const double D = J.determinant(), frob = J.squaredNorm();
    Eigen::Matrix2d cof;  // d det / d J
    cof << J(1, 1), -J(1, 0), -J(0, 1), J(0, 0);
    return (1.0 - lambda) * (2.0 / D * J - frob / (D * D) * cof) +
           lambda * (1.0 - 1.0 / (D * D)) * cof;
}

// The 4 x 4 Hessian of one face's energy per unit area, psi(J) = (1 - lambda) ||J||^2 / det J
// + lambda (det J + 1 / det J), with respect to J = [[a, b], [c, d]] as (a, b, c, d), its
// negative eigenvalues clamped to 0 (projected Newton, Teran et al. 2005), from its analytic
// eigensystem (Smith, De Goes and Kim 2019, "Analytic eigensystems for isotropic distortion
// energies"): with J = U diag(s, t) V^T (det J > 0, so s, t > 0), the eigenvectors are
// U M V^T for M the twist [[0, -1], [1, 0]] / sqrt 2, the flip [[0, 1], [1, 0]] / sqrt 2 and the
// two eigenvectors (x, y) of the Hessian of psi(s, t) as diag(x, y). With D = s t, the twist's
// eigenvalue (psi_s + psi_t) / (s + t) = lambda (1 - 1 / D^2) - (1 - lambda) (s - t)^2 / D^2 and
// the flip's (psi_s - psi_t) / (s - t) = (1 - lambda) (s + t)^2 / D^2 + lambda (1 / D^2 - 1),
// both without a division by s - t. No 4 x 4 eigensolver: most faces' Hessians are indefinite
// (det J is an indefinite quadratic of J).
inline Eigen::Matrix4d projected_face_hessian(const Eigen::Matrix2d& J, double lambda)
{
    const Eigen::JacobiSVD<Eigen::Matrix2d> svd(J, Eigen::ComputeFullU | Eigen::ComputeFullV);
    const double s = svd.singularValues()(0), t = svd.singularValues()(1);
    const double D = s * t, w = 1.0 - lambda;
    const double inv_D2 = 1.0 / (D * D);
    const Eigen::Matrix2d& U = svd.matrixU();
    const Eigen::Matrix2d& V = svd.matrixV();
    // vec(U M V^T) in J's (a, b, c, d) order.
    const auto mode = [&](const Eigen::Matrix2d& M) {
        const Eigen::Matrix2d F = U * M * V.transpose();
        return Eigen::Vector4d(F(0, 0), F(0, 1), F(1, 0), F(1, 1));
    };
    Eigen::Matrix4d H = Eigen::Matrix4d::Zero();
    const auto add = [&H](double value, const Eigen::Vector4d& q) {
        if (value > 0.0)
            H.noalias() += value * q * q.transpose();
    };
    const double half = std::sqrt(0.5);
    Eigen::Matrix2d M;
    M << 0.0, -half, half, 0.0;
    add(lambda * (1.0 - inv_D2) - w * (s - t) * (s - t) * inv_D2, mode(M));
    M << 0.0, half, half, 0.0;
    add(w * (s + t) * (s + t) * inv_D2 + lambda * (inv_D2 - 1.0), mode(M));
    // The Hessian of psi(s, t): (1 - lambda) (s / t + t / s) + lambda (s t + 1 / (s t)).
    Eigen::Matrix2d scaling;
    scaling(0, 0) = w * 2.0 * t / (s * s * s) + lambda * 2.0 / (s * s * s * t);
    scaling(1, 1) = w * 2.0 * s / (t * t * t) + lambda * 2.0 / (s * t * t * t);
    scaling(0, 1) = scaling(1, 0) = -w * (1.0 / (t * t) + 1.0 / (s * s)) + lambda * (1.0 + inv_D2);
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig;
    eig.computeDirect(scaling);
    for (int k = 0; k < 2; ++k)
        add(eig.eigenvalues()(k), mode(eig.eigenvectors().col(k).asDiagonal()));
    return H;
}

// One face's projected Hessian with respect to its corners' (u, v), as the 3 x 3 matrices of
// its (u, u), (v, u) and (v, v) entries over the corners: corner k's row and corner l's column
// form the 2 x 2 block [[Huu(k, l), Hvu(l, k)], [Hvu(k, l), Hvv(k, l)]].
struct FaceHessian
{
    Eigen::Matrix3d uu, vu, vv;

    FaceHessian() = default;
    FaceHessian(const FaceOperator& op, const Eigen::Matrix2d& J, double lambda)
    {
        const Eigen::Matrix4d HJ = op.area * projected_face_hessian(J, lambda);
        // dJ/d(u_k) = (d0_k, d1_k, 0, 0), dJ/d(v_k) = (0, 0, d0_k, d1_k): with D the 2 x 3
        // matrix of the rows d0, d1, the blocks over the corners are D^T HJ_ij D, HJ_ij the
        // 2 x 2 blocks of HJ (about a third of the flops of the dense 6 x 4 by 4 x 4 by 4 x 6
        // product).
        Eigen::Matrix<double, 2, 3> D;
        D << op.d0[0], op.d0[1], op.d0[2], op.d1[0], op.d1[1], op.d1[2];
        uu = D.transpose() * HJ.topLeftCorner<2, 2>() * D;
        vu = D.transpose() * HJ.bottomLeftCorner<2, 2>() * D;
        vv = D.transpose() * HJ.bottomRightCorner<2, 2>() * D;
    }

    Eigen::Matrix2d block(int k, int l) const
    {
        Eigen::Matrix2d b;
        b << uu(k, l), vu(l, k), vu(k, l), vv(k, l);
        return b;
    }
};

// Adds one face's projected Hessian with respect to its corners' (u, v) (6 x 6, the lower
// triangle row by row: (a, b), b <= a) to `values` at `entry` (-1: a fixed vertex's, skipped).
inline void add_face_hessian(const FaceOperator& op, const Eigen::Matrix2d& J, double lambda,
                      const std::array<int, 21>& entry, double* values)
{
    const FaceHessian H(op, J, lambda);
    int e = 0;
    for (int a = 0; a < 6; ++a)
        for (int b = 0; b <= a; ++b, ++e)
            if (entry[e] >= 0)
            {
                // Row a = 2k (u_k) or 2k + 1 (v_k), column b = 2l or 2l + 1.
                const int k = a / 2, l = b / 2;
                values[entry[e]] += a % 2 == 0 ? (b % 2 == 0 ? H.uu(k, l) : H.vu(l, k))
                                               : (b % 2 == 0 ? H.vu(k, l) : H.vv(k, l));
            }
}

// The projected Hessian of E over a set of faces with respect to the free vertices' (u, v)
// (vertex v's at rows 2 slot[v], 2 slot[v] + 1; slot -1: held), upper triangle. Its pattern is
// built once; assemble() then adds each face's 6 x 6 block straight into the values.
class PolishHessian
{
public:
    PolishHessian(const std::vector<FaceOperator>& faces, const std::vector<int>& slot, int m)
        : H_(m, m), entry_(faces.size()), diagonal_(m)
    {
        // Two free vertices couple when they share a face.
        const PairedPattern pattern = PairedPattern::of_triangles(
            m / 2, faces.size(), [&](std::size_t f, std::array<int, 3>& s) {
                int count = 0;
                for (int v : faces[f].corner)
                    if (slot[v] >= 0)
                        s[count++] = slot[v];
                std::sort(s.begin(), s.begin() + count);
                return count;
            });
        pattern.into(H_);
        for (int i = 0; i < m; ++i)
            diagonal_[i] = pattern.index(i, i);
        const auto row = [&](const FaceOperator& op, int a) {
            const int v = slot[op.corner[a / 2]];
            return v < 0 ? -1 : 2 * v + a % 2;
        };
        for (std::size_t f = 0; f < faces.size(); ++f)
        {
            std::array<std::array<int, 3>, 3> rank{};  // of the free corners (k, l), l <= k
            for (int k = 0; k < 3; ++k)
                for (int l = 0; l <= k; ++l)
                {
                    const int p = slot[faces[f].corner[k]], q = slot[faces[f].corner[l]];
                    if (p >= 0 && q >= 0)
                        rank[k][l] = pattern.rank(std::min(p, q), std::max(p, q));
                }
            int e = 0;
            for (int a = 0; a < 6; ++a)
                for (int b = 0; b <= a; ++b, ++e)
                {
                    const int ra = row(faces[f], a), rb = row(faces[f], b);
                    entry_[f][e] = ra >= 0 && rb >= 0
                                       ? pattern.index_at(rank[a / 2][b / 2], std::min(ra, rb),
                                                          std::max(ra, rb))
                                       : -1;
                }
        }
    }

    //! The Hessian at the map x (interleaved, every vertex): the faces' blocks summed on up to
    //! two threads, each into its own values.
    void assemble(const std::vector<FaceOperator>& faces, const double* x, double lambda)
    {
        double* values = H_.valuePtr();
        const Eigen::Index nnz = H_.nonZeros();
        const int threads = face_threads(faces.size());
        partial_.resize(threads - 1);
        for (auto& other : partial_)
            other.resize(nnz);
        parallel_chunks(faces.size(), threads, [&](std::size_t begin, std::size_t end, int t) {
            double* v = t == 0 ? values : partial_[t - 1].data();
            std::fill(v, v + nnz, 0.0);
            for (std::size_t f = begin; f < end; ++f)
                add_face_hessian(faces[f], jacobian(faces[f], x), lambda, entry_[f], v);
        });
        for (const auto& other : partial_)
            for (Eigen::Index i = 0; i < nnz; ++i)
                values[i] += other[i];
    }

    //! Adds a multiple of the identity: translations (and, without pins, rotations) leave the
    //! energy unchanged; 1e-8 of the mean diagonal keeps the system definite.
    void shift_diagonal()
    {
        double* values = H_.valuePtr();
        double trace = 0.0;
        for (int i : diagonal_)
            trace += values[i];
        const double shift = 1e-8 * trace / std::max<std::size_t>(diagonal_.size(), 1);
        for (int i : diagonal_)
            values[i] += shift;
    }

    Eigen::SparseMatrix<double>& matrix() { return H_; }
    const std::vector<int>& diagonal() const { return diagonal_; }

private:
    Eigen::SparseMatrix<double> H_;
    std::vector<std::array<int, 21>> entry_;
    std::vector<int> diagonal_;
    std::vector<std::vector<double>> partial_;
};

}  // namespace vessel::detail
