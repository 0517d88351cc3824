#pragma once
// One vertex's projected Newton step on the area polish's energy (area_polish.h),
//   E = sum_t A_t ((1 - lambda) ||J_t||^2 / det J_t + lambda (det J_t + 1 / det J_t)),
// over the faces around it. With the vertex's position x the only unknown, each face's
// J = R + x g^T is affine in x (g: the gradient of the vertex's hat function in the face's rest
// frame), so det J = det R + (cof(J) g) . x is affine too, and the 2x2 Hessian is exact and
// cheap (projected to positive definite, as in Teran et al. 2005). The largest step that keeps
// every det J positive is known in closed form; the line search stays below it, so no face
// flips. Used by relax_area() and prolongate() (multilevel.h).

#include "detail/face_jacobian.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace vessel::detail {

struct Corner
{
    int face = 0;
    int k = 0;  // the vertex's corner in the face operator
};

class VertexEnergy
{
public:
    VertexEnergy(const std::vector<detail::FaceOperator>& ops, double lambda)
        : ops_(ops), lambda_(lambda)
    {
    }

    double face(const detail::FaceOperator& op, const double* x) const
    {
        const Eigen::Matrix2d J = detail::jacobian(op, x);
        return of(op.area, J.squaredNorm(), J.determinant());
    }

    // Energy of the faces around one vertex.
    double around(const Corner* begin, const Corner* end, const double* x) const
    {
        double e = 0.0;
        for (const Corner* c = begin; c != end; ++c)
            e += face(ops_[c->face], x);
        return e;
    }

    // Energy (as around()), gradient and Hessian of the energy around one vertex with respect
    // to its position, from one evaluation of each face's Jacobian; also the largest step along
    // a direction that keeps every face's det positive is computed from the det gradients kept
    // in `ds`.
    double derivatives(const Corner* begin, const Corner* end, const double* x,
                       Eigen::Vector2d& grad, Eigen::Matrix2d& hess,
                       std::vector<Eigen::Vector3d>& ds) const
    {
        grad.setZero();
        hess.setZero();
        ds.clear();
        double e = 0.0;
        for (const Corner* c = begin; c != end; ++c)
        {
            const detail::FaceOperator& op = ops_[c->face];
            const Eigen::Matrix2d J = detail::jacobian(op, x);
            const Eigen::Vector2d g(op.d0[c->k], op.d1[c->k]);
            const double s = J.determinant();
            const double a = J.squaredNorm();
            Eigen::Matrix2d cof;
            cof << J(1, 1), -J(1, 0), -J(0, 1), J(0, 0);
            const Eigen::Vector2d da = 2.0 * J * g;
            const Eigen::Vector2d dsv = cof * g;
            ds.emplace_back(dsv.x(), dsv.y(), s);
            const double A = op.area, w = 1.0 - lambda_;
            e += of(op.area, a, s);  // face()'s, so that the sum is around()'s
            grad += A * (w * (da / s - a * dsv / (s * s)) + lambda_ * (1.0 - 1.0 / (s * s)) * dsv);
            const Eigen::Matrix2d cross = da * dsv.transpose() + dsv * da.transpose();
            hess += A * (w * (2.0 * g.squaredNorm() / s * Eigen::Matrix2d::Identity() -
                              cross / (s * s) + 2.0 * a / (s * s * s) * dsv * dsv.transpose()) +
                         lambda_ * 2.0 / (s * s * s) * dsv * dsv.transpose());
        }
        return e;
    }

private:
    // A face's energy from its area, ||J||^2 and det J (infinite for a flipped face).
    double of(double area, double squared_norm, double det) const
    {
        if (!(det > 0.0))
            return std::numeric_limits<double>::infinity();
        return area * ((1.0 - lambda_) * squared_norm / det + lambda_ * (det + 1.0 / det));
    }

    const std::vector<detail::FaceOperator>& ops_;
    double lambda_;
};

//! No energy beside the faces' (vertex_newton_step()'s \p extra).
struct NoExtraEnergy
{
    double operator()(const Eigen::Vector2d&, Eigen::Vector2d*, Eigen::Matrix2d*) const
    {
        return 0.0;
    }
};

//! One projected Newton step of vertex \p v (position x[2v], x[2v + 1]) over the faces
//! [begin, end) around it, at most \p max_step long; \p accept(position) may veto a trial
//! position (it is written into x when asked). Returns the energy lowered (0: not moved).
//! \p extra(p, grad, hess): more energy of the vertex at position p (the look pulls), adding
//! its gradient and a positive semidefinite Hessian where those are not null.
template <class Accept, class Extra = NoExtraEnergy>
double vertex_newton_step(const VertexEnergy& energy, const Corner* begin, const Corner* end,
                          double* x, int v, double max_step, const Accept& accept,
                          std::vector<Eigen::Vector3d>& ds, const Extra& extra = Extra())
{
    Eigen::Vector2d grad;
    Eigen::Matrix2d hess;
    const Eigen::Vector2d start(x[2 * v], x[2 * v + 1]);
    const double before =
        energy.derivatives(begin, end, x, grad, hess, ds) + extra(start, &grad, &hess);
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig;
    eig.computeDirect(hess);
    Eigen::Vector2d lambda = eig.eigenvalues();
    const double floor = 1e-8 * std::max(std::abs(lambda.maxCoeff()), 1e-30);
    lambda = lambda.cwiseMax(floor);
    const Eigen::Vector2d step = -(eig.eigenvectors() * lambda.cwiseInverse().asDiagonal() *
                                   eig.eigenvectors().transpose() * grad);
    const double slope = grad.dot(step);
    if (!(slope < 0.0))
        return 0.0;
    // det J along the step is affine: stop short of the first face that would collapse.
    double alpha = std::min(1.0, max_step / std::max(step.norm(), 1e-300));
    for (const Eigen::Vector3d& d : ds)
    {
        const double rate = d.x() * step.x() + d.y() * step.y();
        if (rate < 0.0)
            alpha = std::min(alpha, 0.9 * (-d.z() / rate));
    }
    for (int tries = 0; tries < 12; ++tries, alpha *= 0.5)
    {
        x[2 * v] = start.x() + alpha * step.x();
        x[2 * v + 1] = start.y() + alpha * step.y();
        const double after = energy.around(begin, end, x) +
                             extra(Eigen::Vector2d(x[2 * v], x[2 * v + 1]), nullptr, nullptr);
        if (after <= before + 1e-4 * alpha * slope && accept(Eigen::Vector2d(x[2 * v], x[2 * v + 1])))
            return before - after;
    }
    x[2 * v] = start.x();
    x[2 * v + 1] = start.y();
    return 0.0;
}

}  // namespace vessel::detail
