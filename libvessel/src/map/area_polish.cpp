#include "vessel/map/area_polish.h"

#include "detail/centre_pull.h"
#include "detail/face_jacobian.h"
#include "solve/paired_cholmod.h"
#include "detail/scaffold.h"
#include "solve/serial_openmp.h"
#include "detail/uv_rows.h"
#include "vessel/cut/boundary.h"
#include "vessel/map/embedding.h"
#include "vessel/core/errors.h"

#include <ceres/gradient_problem.h>
#include <ceres/gradient_problem_solver.h>

#include <Eigen/CholmodSupport>
#include <Eigen/Eigenvalues>
#include <Eigen/Sparse>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

namespace vessel {

void AreaPolishOptions::validate() const
{
    if (!(area_weight >= 0.0 && area_weight < 1.0))
        throw InvalidInputError("AreaPolishOptions: area_weight must be in [0, 1)");
    if (max_iterations < 0)
        throw InvalidInputError("AreaPolishOptions: max_iterations must be >= 0");
    if (chunk_iterations < 1)
        throw InvalidInputError("AreaPolishOptions: chunk_iterations must be >= 1");
    if (newton_max_iterations < 0)
        throw InvalidInputError("AreaPolishOptions: newton_max_iterations must be >= 0");
    if (newton_chunk_iterations < 1)
        throw InvalidInputError("AreaPolishOptions: newton_chunk_iterations must be >= 1");
    if (!(tolerance >= 0.0))
        throw InvalidInputError("AreaPolishOptions: tolerance must be >= 0");
    if (!(scaffold_weight > 0.0))
        throw InvalidInputError("AreaPolishOptions: scaffold_weight must be > 0");
    validate_centre_pulls(centre_pulls, "AreaPolishOptions");
}

namespace {

using detail::FaceOperator;

// The barrier energy over a set of faces (the surface's and the scaffold's) as a function of
// the free vertices' uv; x holds every vertex, the fixed ones included.
class PolishEnergy final : public ceres::FirstOrderFunction
{
public:
    PolishEnergy(std::vector<FaceOperator> ops, const std::vector<int>& free_vertices,
                 Eigen::VectorXd& x, double lambda, const std::vector<CentrePull>& pulls)
        : ops_(std::move(ops)), free_(free_vertices), x_(x), slot_(x.size() / 2, -1),
          lambda_(lambda), pulls_(pulls)
    {
        for (std::size_t i = 0; i < free_.size(); ++i)
            slot_[free_[i]] = static_cast<int>(i);
    }

    const std::vector<FaceOperator>& faces() const { return ops_; }
    const std::vector<CentrePull>& pulls() const { return pulls_; }
    const Eigen::VectorXd& x() const { return x_; }
    // Per vertex: its index among the free vertices (its u, v are parameters 2i, 2i + 1); -1 if fixed.
    const std::vector<int>& slot() const { return slot_; }
    Eigen::Matrix2d jacobian(const FaceOperator& op) const { return detail::jacobian(op, x_.data()); }

    int NumParameters() const override { return 2 * static_cast<int>(free_.size()); }

    void gather(double* p) const
    {
        for (std::size_t i = 0; i < free_.size(); ++i)
            for (int c = 0; c < 2; ++c)
                p[2 * i + c] = x_[2 * free_[i] + c];
    }
    void scatter(const double* p) const
    {
        for (std::size_t i = 0; i < free_.size(); ++i)
            for (int c = 0; c < 2; ++c)
                x_[2 * free_[i] + c] = p[2 * i + c];
    }

    bool Evaluate(const double* p, double* cost, double* gradient) const override
    {
        scatter(p);
        if (gradient)
            std::fill(gradient, gradient + NumParameters(), 0.0);
        double e = 0.0;
        for (const FaceOperator& op : ops_)
        {
            const Eigen::Matrix2d J = detail::jacobian(op, x_.data());
            const double D = J.determinant();
            if (!(D > 0.0))
                return false;  // the line search backs off: no face may flip
            const double frob = J.squaredNorm();
            e += op.area * ((1.0 - lambda_) * frob / D + lambda_ * (D + 1.0 / D));
            if (!gradient)
                continue;
            Eigen::Matrix2d cof;  // d det / d J
            cof << J(1, 1), -J(1, 0), -J(0, 1), J(0, 0);
            const Eigen::Matrix2d G =
                op.area * ((1.0 - lambda_) * (2.0 / D * J - frob / (D * D) * cof) +
                           lambda_ * (1.0 - 1.0 / (D * D)) * cof);
            detail::add_face_gradient(op, G, slot_, gradient);
        }
        if (!pulls_.empty())
        {
            e += detail::centre_pull_energy(pulls_, x_);
            if (gradient)
                detail::add_centre_pull_gradient(pulls_, x_, slot_, gradient);
        }
        *cost = e;
        return std::isfinite(e);
    }

private:
    std::vector<FaceOperator> ops_;
    const std::vector<int>& free_;
    Eigen::VectorXd& x_;
    std::vector<int> slot_;
    double lambda_;
    const std::vector<CentrePull>& pulls_;
};

// The 4 x 4 Hessian of one face's energy with respect to J = [[a, b], [c, d]] as (a, b, c, d),
// its negative eigenvalues clamped to 0 (projected Newton, Teran et al. 2005). With D = det J,
// g = dD/dJ = (d, -c, -b, a) and H_D = d2D/dJ2 (1 at (a, d), -1 at (b, c)):
// ||J||^2 / D has Hessian 2 I / D - 2 (j g^T + g j^T) / D^2 + 2 ||J||^2 g g^T / D^3 - ||J||^2 H_D / D^2,
// D + 1 / D has Hessian 2 g g^T / D^3 + (1 - 1 / D^2) H_D.
Eigen::Matrix4d projected_face_hessian(const Eigen::Matrix2d& J, double lambda)
{
    const Eigen::Vector4d j(J(0, 0), J(0, 1), J(1, 0), J(1, 1));
    const Eigen::Vector4d g(J(1, 1), -J(1, 0), -J(0, 1), J(0, 0));
    Eigen::Matrix4d HD = Eigen::Matrix4d::Zero();
    HD(0, 3) = HD(3, 0) = 1.0;
    HD(1, 2) = HD(2, 1) = -1.0;
    const double D = J.determinant(), F = j.squaredNorm();
    const Eigen::Matrix4d shape = 2.0 / D * Eigen::Matrix4d::Identity() -
                                  2.0 / (D * D) * (j * g.transpose() + g * j.transpose()) +
                                  2.0 * F / (D * D * D) * g * g.transpose() - F / (D * D) * HD;
    const Eigen::Matrix4d area = 2.0 / (D * D * D) * g * g.transpose() + (1.0 - 1.0 / (D * D)) * HD;
    const Eigen::Matrix4d H = (1.0 - lambda) * shape + lambda * area;
    // Most faces' Hessians are already positive definite: a 4 x 4 Cholesky says so for a
    // fraction of the eigensolver's cost, and the projection leaves such a matrix as it is.
    if (Eigen::LLT<Eigen::Matrix4d>(H).info() == Eigen::Success)
        return H;
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> eig(H);
    return eig.eigenvectors() * eig.eigenvalues().cwiseMax(0.0).asDiagonal() *
           eig.eigenvectors().transpose();
}

// Adds one face's projected Hessian with respect to its corners' (u, v) (6 x 6, the lower
// triangle row by row: (a, b), b <= a) to `values` at `entry` (-1: a fixed vertex's, skipped).
void add_face_hessian(const FaceOperator& op, const Eigen::Matrix2d& J, double lambda,
                      const std::array<int, 21>& entry, double* values)
{
    const Eigen::Matrix4d HJ = op.area * projected_face_hessian(J, lambda);
    // dJ/d(u_k) = (d0_k, d1_k, 0, 0), dJ/d(v_k) = (0, 0, d0_k, d1_k): with D the 2 x 3 matrix
    // of the rows d0, d1, the (u, u), (v, u) and (v, v) blocks over the corners are
    // D^T HJ_ij D, HJ_ij the 2 x 2 blocks of HJ (about a third of the flops of the dense
    // 6 x 4 by 4 x 4 by 4 x 6 product).
    Eigen::Matrix<double, 2, 3> D;
    D << op.d0[0], op.d0[1], op.d0[2], op.d1[0], op.d1[1], op.d1[2];
    const Eigen::Matrix3d Huu = D.transpose() * HJ.topLeftCorner<2, 2>() * D;
    const Eigen::Matrix3d Hvu = D.transpose() * HJ.bottomLeftCorner<2, 2>() * D;
    const Eigen::Matrix3d Hvv = D.transpose() * HJ.bottomRightCorner<2, 2>() * D;
    int e = 0;
    for (int a = 0; a < 6; ++a)
        for (int b = 0; b <= a; ++b, ++e)
            if (entry[e] >= 0)
            {
                // Row a = 2k (u_k) or 2k + 1 (v_k), column b = 2l or 2l + 1.
                const int k = a / 2, l = b / 2;
                values[entry[e]] += a % 2 == 0 ? (b % 2 == 0 ? Huu(k, l) : Hvu(l, k))
                                               : (b % 2 == 0 ? Hvu(k, l) : Hvv(k, l));
            }
}

// Up to `iterations` projected Newton steps on `energy` (its faces, free vertices and x), each
// line searched from the full step back to one that flips no face and lowers the energy
// (Armijo). Returns the steps taken; `cost` is the energy at the end.
int newton_steps(PolishEnergy& energy, double lambda, int iterations, double& cost)
{
    const std::vector<int>& slot = energy.slot();
    const int m = energy.NumParameters();
    Eigen::VectorXd p(m), gradient(m), trial(m);
    energy.gather(p.data());
    if (!energy.Evaluate(p.data(), &cost, gradient.data()))
        return 0;
    // The u and v of a vertex share their sparsity: the paired analysis of SLIM's global step
    // (the vertex graph ordered by AMD, by METIS on the largest maps), on the upper triangle.
    // Against CHOLMOD's own AMD on the lower triangle: carotid-300k, 10 Newton steps, 2
    // analyses: the factor's flops 1.17e10 -> 6.1e9, a factorization ~1.08 -> ~0.7 s
    // (docs/benchmarks.md, branch fspeed7).
    detail::PairedCholmod solver;
    // The Hessian's pattern is the same at every step: built once (from triplets), then each
    // face's 6 x 6 block is added straight into the values at `entry` (-1: a fixed vertex's).
    Eigen::SparseMatrix<double> H(m, m);
    std::vector<std::array<int, 21>> entry(energy.faces().size());
    std::vector<int> diagonal(m);
    {
        std::vector<Eigen::Triplet<double>> triplets;
        for (int i = 0; i < m; ++i)
            triplets.emplace_back(i, i, 0.0);
        for (const FaceOperator& op : energy.faces())
            for (int a = 0; a < 6; ++a)
                for (int b = 0; b <= a; ++b)
                {
                    const int sa = slot[op.corner[a / 2]], sb = slot[op.corner[b / 2]];
                    if (sa >= 0 && sb >= 0)
                    {
                        const int ra = 2 * sa + a % 2, rb = 2 * sb + b % 2;
                        triplets.emplace_back(std::min(ra, rb), std::max(ra, rb), 0.0);
                    }
                }
        H.setFromTriplets(triplets.begin(), triplets.end());
        H.makeCompressed();
        const auto index = [&](int row, int col) {
            const int* begin = H.innerIndexPtr() + H.outerIndexPtr()[col];
            const int* end = H.innerIndexPtr() + H.outerIndexPtr()[col + 1];
            return static_cast<int>(std::lower_bound(begin, end, row) - H.innerIndexPtr());
        };
        for (int i = 0; i < m; ++i)
            diagonal[i] = index(i, i);
        for (std::size_t f = 0; f < energy.faces().size(); ++f)
        {
            const FaceOperator& op = energy.faces()[f];
            int e = 0;
            for (int a = 0; a < 6; ++a)
                for (int b = 0; b <= a; ++b, ++e)
                {
                    const int sa = slot[op.corner[a / 2]], sb = slot[op.corner[b / 2]];
                    entry[f][e] = -1;
                    if (sa >= 0 && sb >= 0)
                    {
                        const int ra = 2 * sa + a % 2, rb = 2 * sb + b % 2;
                        entry[f][e] = index(std::min(ra, rb), std::max(ra, rb));
                    }
                }
        }
    }
    double* values = H.valuePtr();
    const Eigen::Index nnz = H.nonZeros();
    // The faces' blocks are summed on up to two threads (as SLIM's), each into its own values.
    const int threads = detail::face_threads(energy.faces().size());
    std::vector<std::vector<double>> partial_values(threads - 1, std::vector<double>(nnz));
    int done = 0;
    for (; done < iterations; ++done)
    {
        const std::vector<FaceOperator>& faces = energy.faces();
        const auto add_faces = [&](std::size_t begin, std::size_t end, int t) {
            double* v = t == 0 ? values : partial_values[t - 1].data();
            std::fill(v, v + nnz, 0.0);
            for (std::size_t f = begin; f < end; ++f)
                add_face_hessian(faces[f], energy.jacobian(faces[f]), lambda, entry[f], v);
        };
        detail::parallel_chunks(faces.size(), threads, add_faces);
        for (const auto& other : partial_values)
            for (Eigen::Index i = 0; i < nnz; ++i)
                values[i] += other[i];
        detail::add_centre_pull_curvature(energy.pulls(), energy.x(), slot, diagonal, values);
        // Translations (and, without pins, rotations) leave the energy unchanged: a small
        // multiple of the identity keeps the system definite.
        double trace = 0.0;
        for (int i = 0; i < m; ++i)
            trace += values[diagonal[i]];
        const double shift = 1e-8 * trace / m;
        for (int i = 0; i < m; ++i)
            values[diagonal[i]] += shift;
        {
            const detail::SerialOpenMp serial;
            if (done == 0)
            {
                solver.analyze_pairs(H);
                if (solver.info() != Eigen::Success)
                    break;
            }
            solver.factorize(H);
        }
        if (solver.info() != Eigen::Success)
            break;
        const Eigen::VectorXd step = solver.solve(-gradient);
        const double slope = gradient.dot(step);
        if (!step.allFinite() || !(slope < 0.0))
            break;
        double t = 1.0, e = 0.0;
        bool accepted = false;
        for (int halving = 0; halving < 40 && !accepted; ++halving, t *= 0.5)
        {
            trial = p + t * step;
            accepted = energy.Evaluate(trial.data(), &e, nullptr) && e <= cost + 1e-4 * t * slope;
        }
        if (!accepted)
            break;
        p = trial;
        if (!energy.Evaluate(p.data(), &cost, gradient.data()))
            break;  // cannot happen: the trial was valid
    }
    energy.scatter(p.data());
    return done;
}

// Appends to x (the map's n vertices) a box around the map and the Steiner vertices of the
// free space's triangulation (detail::scaffold_triangles); returns that triangulation's face
// operators, each with its current shape as rest shape and the same share of `weight`, and
// adds its Steiner vertices to `free_vertices`.
std::vector<FaceOperator> scaffold_faces(const std::vector<int>& boundary, int n, double weight,
                                         const Eigen::Vector2d& inside, Eigen::VectorXd& x,
                                         std::vector<int>& free_vertices)
{
    Eigen::Vector2d lo = x.segment<2>(2 * boundary[0]), hi = lo;
    for (int v : boundary)
    {
        lo = lo.cwiseMin(x.segment<2>(2 * v));
        hi = hi.cwiseMax(x.segment<2>(2 * v));
    }
    const Eigen::Vector2d pad = Eigen::Vector2d::Constant(0.5 * (hi - lo).maxCoeff());
    const Eigen::Vector2d corners[4] = {lo - pad, Eigen::Vector2d(hi.x() + pad.x(), lo.y() - pad.y()),
                                        hi + pad, Eigen::Vector2d(lo.x() - pad.x(), hi.y() + pad.y())};
    x.conservativeResize(2 * (n + 4));
    for (int c = 0; c < 4; ++c)
        x.segment<2>(2 * (n + c)) = corners[c];
    const detail::ScaffoldMesh free_space =
        detail::scaffold_triangles(x, boundary, {n, n + 1, n + 2, n + 3}, inside, n + 4);
    const int steiner = static_cast<int>(free_space.steiner.size());
    x.conservativeResize(2 * (n + 4 + steiner));
    for (int j = 0; j < steiner; ++j)
    {
        x.segment<2>(2 * (n + 4 + j)) = free_space.steiner[j];
        free_vertices.push_back(n + 4 + j);
    }
    std::vector<FaceOperator> ops;
    for (const auto& t : free_space.triangles)
    {
        Eigen::Matrix2d P;
        P << x.segment<2>(2 * t[1]) - x.segment<2>(2 * t[0]),
            x.segment<2>(2 * t[2]) - x.segment<2>(2 * t[0]);
        const double det = P.determinant();
        if (!(det > 0.0))
            continue;  // a sliver at the scale of rounding: nothing passes through it
        // A sliver's own shape as rest shape would make its barrier block every step: use the
        // equilateral triangle of its area (as the SLIM scaffold does).
        const double longest = std::max({P.col(0).squaredNorm(), P.col(1).squaredNorm(),
                                         (P.col(1) - P.col(0)).squaredNorm()});
        if (det < 0.05 * longest)
        {
            const double side = std::sqrt(2.0 * det / std::sqrt(3.0));
            P << side, 0.5 * side, 0.0, 0.5 * std::sqrt(3.0) * side;
        }
        const Eigen::Matrix2d Q = P.inverse();
        FaceOperator op;
        op.corner = t;
        op.d0 = {-Q(0, 0) - Q(1, 0), Q(0, 0), Q(1, 0)};
        op.d1 = {-Q(0, 1) - Q(1, 1), Q(0, 1), Q(1, 1)};
        ops.push_back(op);
    }
    for (auto& op : ops)
        op.area = weight / static_cast<double>(ops.size());
    return ops;
}

}  // namespace

AreaPolishSummary area_polish(const Mesh& mesh, Eigen::MatrixX2d& uv, const Pins& pins,
                              const AreaPolishOptions& options)
{
    options.validate();
    detail::require_uv_rows(mesh, uv, "area_polish");
    const int n = static_cast<int>(mesh.n_vertices());
    const std::vector<int> pinned = pin_index(mesh, pins, "area_polish");
    detail::require_centre_pull_vertices(options.centre_pulls, n, "area_polish");
    const std::vector<FaceOperator> surface = detail::face_operators(mesh);
    const auto loops = boundary_loops(mesh);
    if (loops.size() != 1)
        throw TopologyError("area_polish: the mesh must be a disk (one boundary loop), got " +
                            std::to_string(loops.size()));
    std::vector<int> boundary;
    for (auto v : loops[0].vertices)
        boundary.push_back(v.idx());
    double area = 0.0;
    for (const auto& op : surface)
        area += op.area;

    AreaPolishSummary summary;
    summary.scaffold =
        options.keep_boundary_simple && boundary_self_intersection(mesh, uv).first < 0;
    ceres::GradientProblemSolver::Options solver;
    solver.line_search_direction_type = ceres::LBFGS;
    solver.logging_type = ceres::SILENT;
    solver.minimizer_progress_to_stdout = false;
    // Ceres' relative stopping rules (1e-6) end the run while the area term still falls: the
    // shape term dominates the energy. Stop on `tolerance` per chunk instead.
    solver.function_tolerance = 1e-12;
    solver.gradient_tolerance = 1e-14;
    solver.parameter_tolerance = 1e-14;
    const int limit = options.newton ? options.newton_max_iterations : options.max_iterations;
    for (int chunk = 0; summary.iterations < limit; ++chunk)
    {
        Eigen::VectorXd x = detail::interleaved(uv);
        std::vector<int> free_vertices;
        for (int v = 0; v < n; ++v)
            if (pinned[v] < 0)
                free_vertices.push_back(v);
        std::vector<FaceOperator> ops = surface;
        if (summary.scaffold)  // a new scaffold for each chunk
        {
            Eigen::Vector2d inside = Eigen::Vector2d::Zero();
            for (int v : surface.front().corner)
                inside += x.segment<2>(2 * v) / 3.0;
            const std::vector<FaceOperator> free_space = scaffold_faces(
                boundary, n, options.scaffold_weight * area, inside, x, free_vertices);
            ops.insert(ops.end(), free_space.begin(), free_space.end());
        }
        auto* energy = new PolishEnergy(std::move(ops), free_vertices, x, options.area_weight,
                                        options.centre_pulls);
        const ceres::GradientProblem problem(energy);  // owns the energy
        std::vector<double> p(energy->NumParameters());
        energy->gather(p.data());
        double before = 0.0;
        if (!energy->Evaluate(p.data(), &before, nullptr))
            throw InvalidInputError("area_polish: the map has a flipped or degenerate face; "
                                    "untangle it first (untangle.h)");
        if (chunk == 0)
            summary.energy_before = summary.energy_after = before;
        int done = 0;
        double after = before;
        if (options.newton)
        {
            done = newton_steps(*energy, options.area_weight,
                                std::min(options.newton_chunk_iterations,
                                         options.newton_max_iterations - summary.iterations),
                                after);
        }
        else
        {
            solver.max_num_iterations =
                std::min(options.chunk_iterations, options.max_iterations - summary.iterations);
            ceres::GradientProblemSolver::Summary run;
            ceres::Solve(solver, problem, p.data(), &run);
            energy->scatter(p.data());
            done = std::max(static_cast<int>(run.iterations.size()) - 1, 0);
            after = run.final_cost;
        }
        detail::deinterleave(x, uv);  // every step had no flipped face, scaffold included
        if (done == 0)  // e.g. no valid step from here: the map is as it was
            break;
        summary.iterations += done;
        summary.energy_after = after;
        if (options.on_chunk)
            options.on_chunk(summary.iterations);
        // The energy is at least 2 x the surface area (isometry); stop when a chunk removes
        // less than `tolerance` of what is left above that.
        if (before - after < options.tolerance * (before - 2.0 * area))
            break;
    }
    // The scaffold's share, small by construction, is left in the energies.
    char line[200];
    std::snprintf(line, sizeof line,
                  "area polish (lambda %.2f%s): %d %s, energy %.6g -> %.6g",
                  options.area_weight, summary.scaffold ? ", scaffold" : "", summary.iterations,
                  options.newton ? "Newton steps" : "L-BFGS iterations",
                  summary.energy_before, summary.energy_after);
    summary.report = line;
    return summary;
}

}  // namespace vessel
