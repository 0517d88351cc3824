#include "detail/coarse_correction.h"

#include "detail/segments.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace vessel::detail {

namespace {

double total_energy(const std::vector<FaceOperator>& faces, const VertexEnergy& energy, const double* x)
{
    double e = 0.0;
    for (const FaceOperator& op : faces)
        e += energy.face(op, x);
    return e;
}

}  // namespace

Eigen::SparseMatrix<double> coarse_interpolation(const Mesh& coarse, const std::vector<int>& coarse_of,
                                                 const Eigen::MatrixX2d& coarse_uv,
                                                 const Eigen::MatrixX2d& fine_uv)
{
    const int n = static_cast<int>(fine_uv.rows());
    const int m = static_cast<int>(coarse_uv.rows());
    std::vector<std::array<int, 3>> triangles;
    triangles.reserve(coarse.n_faces());
    for (auto f : coarse.faces())
    {
        auto h = f.halfedge();
        triangles.push_back({h.from().idx(), h.to().idx(), h.next().to().idx()});
    }
    // A uniform grid of the coarse triangles' boxes, cells about two triangles wide.
    const Eigen::Vector2d lo = coarse_uv.colwise().minCoeff().transpose();
    const Eigen::Vector2d hi = coarse_uv.colwise().maxCoeff().transpose();
    const double cell = std::max(
        2.0 * std::sqrt((hi - lo).prod() / std::max<std::size_t>(triangles.size(), 1)), 1e-12);
    const int nx = static_cast<int>((hi.x() - lo.x()) / cell) + 1;
    const int ny = static_cast<int>((hi.y() - lo.y()) / cell) + 1;
    const auto column = [&](double u) { return std::clamp(static_cast<int>((u - lo.x()) / cell), 0, nx - 1); };
    const auto row = [&](double v) { return std::clamp(static_cast<int>((v - lo.y()) / cell), 0, ny - 1); };
    std::vector<std::vector<int>> grid(static_cast<std::size_t>(nx) * ny);
    for (int t = 0; t < static_cast<int>(triangles.size()); ++t)
    {
        Eigen::Vector2d a = coarse_uv.row(triangles[t][0]).transpose(), b = a;
        for (int k = 1; k < 3; ++k)
        {
            a = a.cwiseMin(coarse_uv.row(triangles[t][k]).transpose());
            b = b.cwiseMax(coarse_uv.row(triangles[t][k]).transpose());
        }
        for (int i = column(a.x()); i <= column(b.x()); ++i)
            for (int j = row(a.y()); j <= row(b.y()); ++j)
                grid[static_cast<std::size_t>(i) * ny + j].push_back(t);
    }
    std::vector<Eigen::Triplet<double>> triplets;
    triplets.reserve(6 * static_cast<std::size_t>(n));
    const auto add = [&](int v, int c, double w) {
        triplets.emplace_back(2 * v, 2 * c, w);
        triplets.emplace_back(2 * v + 1, 2 * c + 1, w);
    };
    for (int v = 0; v < n; ++v)
    {
        if (coarse_of[v] >= 0)
        {
            add(v, coarse_of[v], 1.0);
            continue;
        }
        // The triangle whose smallest barycentric coordinate of the vertex is largest: the one
        // holding it, else the nearest in that sense, searched in rings of cells.
        const Eigen::Vector2d p = fine_uv.row(v).transpose();
        double best = -std::numeric_limits<double>::infinity();
        Eigen::Vector3d weights(1.0, 0.0, 0.0);
        int found = -1;
        const int i0 = column(p.x()), j0 = row(p.y());
        for (int ring = 0; ring <= 2 && best < 0.0; ++ring)
            for (int i = std::max(i0 - ring, 0); i <= std::min(i0 + ring, nx - 1); ++i)
                for (int j = std::max(j0 - ring, 0); j <= std::min(j0 + ring, ny - 1); ++j)
                {
                    if (std::max(std::abs(i - i0), std::abs(j - j0)) != ring)
                        continue;  // the ring's cells only
                    for (int t : grid[static_cast<std::size_t>(i) * ny + j])
                    {
                        Eigen::Vector3d w;
                        if (!barycentric(p, coarse_uv.row(triangles[t][0]).transpose(),
                                         coarse_uv.row(triangles[t][1]).transpose(),
                                         coarse_uv.row(triangles[t][2]).transpose(), w))
                            continue;
                        if (w.minCoeff() > best)
                        {
                            best = w.minCoeff();
                            weights = w;
                            found = t;
                        }
                    }
                }
        if (found < 0)
            continue;  // far from every coarse triangle: the correction does not move it
        weights = weights.cwiseMax(0.0);
        weights /= weights.sum();
        for (int k = 0; k < 3; ++k)
            if (weights[k] > 0.0)
                add(v, triangles[found][k], weights[k]);
    }
    Eigen::SparseMatrix<double> P(2 * n, 2 * m);
    P.setFromTriplets(triplets.begin(), triplets.end());
    return P;
}

namespace {

std::vector<int> free_slots(const std::vector<int>& pinned)
{
    std::vector<int> slot(pinned.size());
    for (std::size_t v = 0; v < pinned.size(); ++v)
        slot[v] = pinned[v] >= 0 ? -1 : static_cast<int>(v);
    return slot;
}

}  // namespace

CoarseCorrection::CoarseCorrection(const std::vector<FaceOperator>& faces,
                                   Eigen::SparseMatrix<double> interpolation,
                                   const std::vector<int>& pinned, double lambda)
    : faces_(faces), P_(std::move(interpolation)), slot_(free_slots(pinned)), lambda_(lambda)
{
    // A pinned vertex does not move: its rows of P are emptied.
    P_.prune([&](Eigen::Index r, Eigen::Index, double) { return pinned[r / 2] < 0; });
    rows_ = P_;
}

int CoarseCorrection::hold_around(int v, std::vector<char>& held) const
{
    int added = 0;
    for (int r = 2 * v; r < 2 * v + 2; ++r)
        for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(rows_, r); it; ++it)
            if (!held[it.col()])
            {
                held[it.col()] = 1;
                ++added;
            }
    return added;
}

void CoarseCorrection::factorize()
{
    // Held unknowns become identity rows with a zero right-hand side, so the pattern stays that
    // of the analysis.
    system_ = coarse_;
    for (Eigen::Index c = 0; c < system_.outerSize(); ++c)
        for (Eigen::SparseMatrix<double>::InnerIterator it(system_, c); it; ++it)
        {
            if (held_[it.row()] || held_[c])
                it.valueRef() = it.row() == c ? mean_diagonal_ : 0.0;
            if (it.row() == c)
                it.valueRef() += 1e-8 * mean_diagonal_;
        }
    if (!analysed_)
    {
        solver_.analyze_pairs(system_);
        analysed_ = true;
    }
    if (solver_.info() == Eigen::Success)
        solver_.factorize(system_);
}

double CoarseCorrection::step(const VertexEnergy& energy, Eigen::VectorXd& xv, BoundaryGuard* guard,
                              double& current)
{
    const double* x = xv.data();
    const Eigen::Index n2 = xv.size();
    Eigen::VectorXd gradient = Eigen::VectorXd::Zero(n2);
    for (const FaceOperator& op : faces_)
        add_face_gradient(op, op.area * polish_face_gradient(jacobian(op, x), lambda_), slot_,
                          gradient.data());
    if (coarse_.size() == 0)
    {
        // The coarse operator at the first step, kept for the next ones: the relaxation changes
        // the map little, and the line search makes up for the difference (a frozen Newton
        // matrix), while the Galerkin product costs several sweeps.
        PolishHessian hessian(faces_, slot_, static_cast<int>(n2));
        hessian.assemble(faces_, x, lambda_);
        const Eigen::SparseMatrix<double> full = hessian.matrix().selfadjointView<Eigen::Upper>();
        coarse_ = (P_.transpose() * full * P_).triangularView<Eigen::Upper>();
        double trace = 0.0;
        for (Eigen::Index c = 0; c < coarse_.rows(); ++c)
            trace += coarse_.coeff(c, c);
        mean_diagonal_ = std::max(trace / std::max<Eigen::Index>(coarse_.rows(), 1), 1e-300);
        held_.assign(coarse_.rows(), 0);
        // Held from the start: the coarse vertices around boundary parts within half a boundary
        // edge of each other, where a step would soon close the gap.
        if (guard)
        {
            guard->rebuild(x);
            for (int v : guard->near_pairs(x, std::max(0.5 * guard->mean_edge(), guard->clearance())))
                hold_around(v, held_);
        }
        factorize();
    }
    const Eigen::VectorXd restricted = P_.transpose() * gradient;
    const Eigen::Index m2 = coarse_.rows();
    Eigen::VectorXd trial(n2);
    for (int round = 0; round < 8; ++round)
    {
        if (solver_.info() != Eigen::Success)
            return 0.0;
        Eigen::VectorXd rhs = -restricted;
        for (Eigen::Index c = 0; c < m2; ++c)
            if (held_[c])
                rhs[c] = 0.0;
        const Eigen::VectorXd direction = P_ * solver_.solve(rhs);
        const double slope = gradient.dot(direction);
        if (!direction.allFinite() || !(slope < 0.0))
            return 0.0;
        double t = max_injective_step(faces_, xv, direction, face_threads(faces_.size()), 0, 0.9);
        double e = std::numeric_limits<double>::infinity();
        for (; t > 1e-3; t *= 0.5)
        {
            trial = xv + t * direction;
            e = total_energy(faces_, energy, trial.data());
            if (e <= current + 1e-4 * t * slope)
                break;
        }
        if (!(t > 1e-3))
            return 0.0;
        // A step that brings boundary parts nearer than the clearance is solved again with the
        // coarse vertices there held.
        int added = 0;
        if (guard)
        {
            guard->rebuild(trial.data());
            for (int v : guard->near_contacts(trial.data()))
                added += hold_around(v, held_);
        }
        if (added == 0)
        {
            const double lowered = current - e;
            xv = trial;
            current = e;
            return lowered;
        }
        factorize();
    }
    return 0.0;
}

}  // namespace vessel::detail
