#include "vessel/injective.h"

#include "vessel/boundary.h"
#include "vessel/errors.h"
#include "vessel/metrics.h"

#include <Eigen/CholmodSupport>
#include <Eigen/Sparse>

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>

namespace vessel {

void InjectiveOptions::validate() const
{
    if (max_iterations < 1)
        throw InvalidInputError("InjectiveOptions: max_iterations must be >= 1");
    if (!(tolerance > 0.0))
        throw InvalidInputError("InjectiveOptions: tolerance must be > 0");
}

Eigen::MatrixX2d tutte_embedding(const Mesh& mesh)
{
    const auto loops = boundary_loops(mesh);
    if (loops.size() != 1)
        throw TopologyError("tutte_embedding: the mesh has " + std::to_string(loops.size()) +
                            " boundary loops; a disk (one loop) is required — cut it first");
    const auto& loop = loops[0];
    const int n = static_cast<int>(mesh.n_vertices());
    Eigen::MatrixX2d uv = Eigen::MatrixX2d::Zero(n, 2);
    std::vector<int> slot(n, -1);  // index among the free vertices, -1 on the boundary
    // Boundary halfedges run clockwise around the disk; walking them backwards is
    // counter-clockwise, which makes the faces counter-clockwise.
    const double radius = loop.arc_length / (2.0 * M_PI);
    double s = 0.0;
    std::vector<char> on_boundary(n, 0);
    for (std::size_t i = 0; i < loop.halfedges.size(); ++i)
    {
        const int v = loop.vertices[i].idx();
        on_boundary[v] = 1;
        const double angle = -2.0 * M_PI * s / loop.arc_length;
        uv.row(v) << radius * std::cos(angle), radius * std::sin(angle);
        s += mesh.calc_edge_length(loop.halfedges[i]);
    }
    int n_free = 0;
    for (int v = 0; v < n; ++v)
        if (!on_boundary[v])
            slot[v] = n_free++;
    if (n_free == 0)
        return uv;
    std::vector<Eigen::Triplet<double>> triplets;
    Eigen::MatrixX2d rhs = Eigen::MatrixX2d::Zero(n_free, 2);
    for (auto v : mesh.vertices())
    {
        const int i = slot[v.idx()];
        if (i < 0)
            continue;
        double degree = 0.0;
        for (auto w : v.vertices())
        {
            degree += 1.0;
            if (slot[w.idx()] >= 0)
                triplets.emplace_back(i, slot[w.idx()], -1.0);
            else
                rhs.row(i) += uv.row(w.idx());
        }
        triplets.emplace_back(i, i, degree);
    }
    Eigen::SparseMatrix<double> L(n_free, n_free);
    L.setFromTriplets(triplets.begin(), triplets.end());
    Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>> solver(L);
    if (solver.info() != Eigen::Success)
        throw SolverError("tutte_embedding: CHOLMOD could not factor the graph Laplacian");
    const Eigen::MatrixX2d x = solver.solve(rhs);
    if (solver.info() != Eigen::Success || !x.allFinite())
        throw SolverError("tutte_embedding: CHOLMOD solve failed");
    for (int v = 0; v < n; ++v)
        if (slot[v] >= 0)
            uv.row(v) = x.row(slot[v]);
    // A circle of the boundary's perimeter encloses far more than the surface's area; scale to
    // the 3D area so that a distortion energy starts from the right size.
    double area2 = 0.0;
    for (auto f : mesh.faces())
        area2 += signed_uv_area(mesh, uv, f);
    const double area3 = face_areas(mesh).sum();
    if (area2 > 0.0)
        uv *= std::sqrt(area3 / area2);
    return uv;
}

namespace {

// Per-face constants of the map's Jacobian J = [[D0 u, D1 u], [D0 v, D1 v]], where Dk holds the
// coefficients of the three corners (J is linear in the uv of the corners).
struct FaceOperator
{
    std::array<int, 3> corner{};
    std::array<double, 3> d0{}, d1{};
    double area = 0.0;
};

std::vector<FaceOperator> face_operators(const Mesh& mesh)
{
    std::vector<FaceOperator> ops(mesh.n_faces());
    for (auto f : mesh.faces())
    {
        auto h = f.halfedge();
        FaceOperator& op = ops[f.idx()];
        op.corner = {h.from().idx(), h.to().idx(), h.next().to().idx()};
        const Eigen::Vector3d q0 = to_eigen(mesh.point(h.from()));
        const Eigen::Vector3d e1 = to_eigen(mesh.point(h.to())) - q0;
        const Eigen::Vector3d e2 = to_eigen(mesh.point(h.next().to())) - q0;
        const Eigen::Vector3d ax = e1.normalized();
        const Eigen::Vector3d ay = (e2 - e2.dot(ax) * ax).normalized();
        Eigen::Matrix2d P;  // columns: the two edges in a local orthonormal frame
        P << e1.dot(ax), e2.dot(ax), 0.0, e2.dot(ay);
        const Eigen::Matrix2d Pi = P.inverse();
        op.d0 = {-(Pi(0, 0) + Pi(1, 0)), Pi(0, 0), Pi(1, 0)};
        op.d1 = {-(Pi(0, 1) + Pi(1, 1)), Pi(0, 1), Pi(1, 1)};
        op.area = 0.5 * std::abs(P.determinant());
    }
    return ops;
}

// x = [u_0, v_0, u_1, v_1, ...].
Eigen::Matrix2d jacobian(const FaceOperator& op, const Eigen::VectorXd& x)
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

// Symmetric Dirichlet energy; +infinity if a triangle is flipped or collapsed.
double energy(const std::vector<FaceOperator>& ops, const Eigen::VectorXd& x)
{
    double e = 0.0;
    for (const auto& op : ops)
    {
        const Eigen::Matrix2d J = jacobian(op, x);
        const double det = J.determinant();
        if (!(det > 0.0))
            return INFINITY;
        const double frob = J.squaredNorm();
        e += op.area * (frob + frob / (det * det));
    }
    return e;
}

// Largest step t in (0, 1] along d that keeps every triangle positively oriented (Smith and
// Schaefer 2015): det of the corner-difference matrix is quadratic in t; stop short of its first
// positive root.
double max_injective_step(const std::vector<FaceOperator>& ops, const Eigen::VectorXd& x,
                          const Eigen::VectorXd& d)
{
    double t_max = 1.0;
    for (const auto& op : ops)
    {
        const int i = op.corner[0], j = op.corner[1], k = op.corner[2];
        const double a1 = x[2 * j] - x[2 * i], a2 = x[2 * j + 1] - x[2 * i + 1];
        const double b1 = x[2 * k] - x[2 * i], b2 = x[2 * k + 1] - x[2 * i + 1];
        const double da1 = d[2 * j] - d[2 * i], da2 = d[2 * j + 1] - d[2 * i + 1];
        const double db1 = d[2 * k] - d[2 * i], db2 = d[2 * k + 1] - d[2 * i + 1];
        const double qa = da1 * db2 - da2 * db1;
        const double qb = a1 * db2 + da1 * b2 - a2 * db1 - da2 * b1;
        const double qc = a1 * b2 - a2 * b1;
        double root = INFINITY;
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
        t_max = std::min(t_max, 0.8 * root);
    }
    return t_max;
}

// The global step's normal matrix has a fixed pattern: 6 x 6 entries per face (the u and v of
// its three corners). It is built once; every iteration only refills the values.
struct NormalMatrix
{
    Eigen::SparseMatrix<double> A;
    std::vector<int> slot;  // 36 value indices per face, row-major over the 6 local unknowns
};

NormalMatrix normal_matrix_pattern(const std::vector<FaceOperator>& ops, int n)
{
    std::vector<Eigen::Triplet<double>> triplets;
    triplets.reserve(36 * ops.size() + 2 * n);
    const auto dof = [](const FaceOperator& op, int l) { return 2 * op.corner[l / 2] + l % 2; };
    for (const auto& op : ops)
        for (int a = 0; a < 6; ++a)
            for (int b = 0; b < 6; ++b)
                triplets.emplace_back(dof(op, a), dof(op, b), 0.0);
    for (int i = 0; i < 2 * n; ++i)
        triplets.emplace_back(i, i, 0.0);
    NormalMatrix M;
    M.A.resize(2 * n, 2 * n);
    M.A.setFromTriplets(triplets.begin(), triplets.end());
    M.A.makeCompressed();
    M.slot.resize(36 * ops.size());
    const auto index_of = [&](int row, int col) {
        const int* begin = M.A.innerIndexPtr() + M.A.outerIndexPtr()[col];
        const int* end = M.A.innerIndexPtr() + M.A.outerIndexPtr()[col + 1];
        return static_cast<int>(std::lower_bound(begin, end, row) - M.A.innerIndexPtr());
    };
    for (std::size_t f = 0; f < ops.size(); ++f)
        for (int a = 0; a < 6; ++a)
            for (int b = 0; b < 6; ++b)
                M.slot[36 * f + 6 * a + b] = index_of(dof(ops[f], a), dof(ops[f], b));
    return M;
}

}  // namespace

InjectiveSummary injective_refine(const Mesh& mesh, Eigen::MatrixX2d& uv, const Pins& pins,
                                  const InjectiveOptions& options)
{
    options.validate();
    const int n = static_cast<int>(mesh.n_vertices());
    if (uv.rows() != n)
        throw InvalidInputError("injective_refine: uv has " + std::to_string(uv.rows()) +
                                " rows for " + std::to_string(n) + " vertices");
    for (const auto& pin : pins)
        if (!mesh.is_valid_handle(pin.vertex))
            throw InvalidInputError("injective_refine: invalid pin vertex handle");
    Eigen::VectorXd x(2 * n);
    for (int v = 0; v < n; ++v)
        x.segment<2>(2 * v) = uv.row(v).transpose();
    for (const auto& pin : pins)
        x.segment<2>(2 * pin.vertex.idx()) = pin.uv;

    const std::vector<FaceOperator> ops = face_operators(mesh);
    InjectiveSummary summary;
    summary.initial_energy = energy(ops, x);
    if (!std::isfinite(summary.initial_energy))
        throw InvalidInputError("injective_refine: the start map has a flipped or collapsed "
                                "triangle; start from a map without flips (e.g. tutte_embedding)");

    // SLIM (Rabinovich et al. 2017): each iteration fits, per face, the rotation R and weights
    // W of a quadratic proxy ||W (J - R)||^2 whose gradient matches the symmetric Dirichlet
    // energy's, solves the proxy globally, and line-searches toward its minimizer without
    // letting a triangle flip. Pins are soft constraints with a large weight; a small proximal
    // term removes the free translation.
    const double total_area = std::accumulate(ops.begin(), ops.end(), 0.0,
                                              [](double s, const FaceOperator& op) { return s + op.area; });
    const double pin_weight = 1e6 * total_area / n;
    const double proximal = 1e-8 * total_area / n;
    NormalMatrix M = normal_matrix_pattern(ops, n);
    Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>> solver;
    solver.analyzePattern(M.A);

    double e = summary.initial_energy;
    int slow = 0;  // consecutive iterations below the tolerance
    for (int it = 0; it < options.max_iterations; ++it)
    {
        std::fill(M.A.valuePtr(), M.A.valuePtr() + M.A.nonZeros(), 0.0);
        Eigen::VectorXd rhs = Eigen::VectorXd::Zero(2 * n);
        for (std::size_t f = 0; f < ops.size(); ++f)
        {
            const FaceOperator& op = ops[f];
            const Eigen::Matrix2d J = jacobian(op, x);
            Eigen::JacobiSVD<Eigen::Matrix2d> svd(J, Eigen::ComputeFullU | Eigen::ComputeFullV);
            const Eigen::Vector2d sigma = svd.singularValues();
            const Eigen::Matrix2d U = svd.matrixU(), V = svd.matrixV();
            Eigen::Matrix2d R = U * V.transpose();
            if (R.determinant() < 0.0)  // cannot happen for det J > 0, kept for safety
            {
                Eigen::Matrix2d U2 = U;
                U2.col(1) *= -1.0;
                R = U2 * V.transpose();
            }
            Eigen::Vector2d w;
            for (int k = 0; k < 2; ++k)
            {
                // Clamped: on a Tutte start, deep branches are compressed by orders of magnitude,
                // and weights ~ sigma^-1.5 would make the system numerically indefinite. A
                // weaker proxy still descends: the line search uses the true energy.
                const double s = std::max(sigma[k], 1e-2);
                w[k] = std::sqrt(1.0 + 1.0 / s + 1.0 / (s * s) + 1.0 / (s * s * s));
            }
            const Eigen::Matrix2d W = U * w.asDiagonal() * U.transpose();
            const Eigen::Matrix2d target = W * R;
            // Residual (r, c) = sqrt(area) (W_r0 (Dc u) + W_r1 (Dc v) - target_rc); local
            // unknowns l = 2 * corner + (0 for u, 1 for v).
            double row[4][6];
            for (int r = 0; r < 2; ++r)
                for (int c = 0; c < 2; ++c)
                {
                    const auto& D = c == 0 ? op.d0 : op.d1;
                    for (int k = 0; k < 3; ++k)
                    {
                        row[2 * r + c][2 * k] = W(r, 0) * D[k];
                        row[2 * r + c][2 * k + 1] = W(r, 1) * D[k];
                    }
                }
            const int* slot = &M.slot[36 * f];
            double* values = M.A.valuePtr();
            for (int a = 0; a < 6; ++a)
            {
                const int dof_a = 2 * op.corner[a / 2] + a % 2;
                for (int q = 0; q < 4; ++q)
                    rhs[dof_a] += op.area * row[q][a] * target(q / 2, q % 2);
                for (int b = 0; b < 6; ++b)
                {
                    double sum = 0.0;
                    for (int q = 0; q < 4; ++q)
                        sum += row[q][a] * row[q][b];
                    values[slot[6 * a + b]] += op.area * sum;
                }
            }
        }
        for (int i = 0; i < 2 * n; ++i)
        {
            M.A.coeffRef(i, i) += proximal;
            rhs[i] += proximal * x[i];
        }
        for (const auto& pin : pins)
            for (int k = 0; k < 2; ++k)
            {
                const int i = 2 * pin.vertex.idx() + k;
                M.A.coeffRef(i, i) += pin_weight;
                rhs[i] += pin_weight * pin.uv[k];
            }
        solver.factorize(M.A);
        if (solver.info() != Eigen::Success)
            throw SolverError("injective_refine: CHOLMOD could not factor the global step");
        const Eigen::VectorXd target = solver.solve(rhs);
        if (solver.info() != Eigen::Success || !target.allFinite())
            throw SolverError("injective_refine: CHOLMOD solve failed");

        const Eigen::VectorXd d = target - x;
        double t = max_injective_step(ops, x, d);
        double e_new = energy(ops, x + t * d);
        while (!(e_new <= e) && t > 1e-12)
        {
            t *= 0.5;
            e_new = energy(ops, x + t * d);
        }
        summary.iterations = it + 1;
        if (!(e_new <= e))
        {
            summary.converged = true;  // no descent left along the proxy's direction
            break;
        }
        x += t * d;
        const double decrease = (e - e_new) / e;
        e = e_new;
        // One small step can come from a short line search (a nearly collapsed triangle in
        // the way), not from convergence; three in a row cannot.
        slow = decrease < options.tolerance ? slow + 1 : 0;
        if (slow == 3)
        {
            summary.converged = true;
            break;
        }
    }
    for (int v = 0; v < n; ++v)
        uv.row(v) = x.segment<2>(2 * v).transpose();
    summary.final_energy = e;
    summary.report = "SLIM symmetric Dirichlet: " + std::to_string(summary.iterations) +
                     " iterations, energy " + std::to_string(summary.initial_energy) + " -> " +
                     std::to_string(summary.final_energy) +
                     (summary.converged ? " (converged)" : " (iteration limit)");
    return summary;
}

}  // namespace vessel
