#include "vessel/map/area_polish.h"

#include "detail/centre_pull.h"
#include "detail/face_jacobian.h"
#include "detail/polish_hessian.h"
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
#include <memory>

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
            detail::add_face_gradient(op, op.area * detail::polish_face_gradient(J, lambda_), slot_,
                                      gradient);
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

// The Newton steps' Hessian and its symbolic analysis, for one set of faces and free vertices.
// The u and v of a vertex share their sparsity: the paired analysis of SLIM's global step (the
// vertex graph ordered by AMD, by METIS on the largest maps), on the upper triangle, about half
// the factor's flops of CHOLMOD's own AMD on the lower triangle
// (docs/journal/benchmarks-2026-11.md, "Stage F: counts per sub-step"). The pattern is the same
// at every step: built once, then each face's block is added straight into its values. Without
// a scaffold the faces stay the same from chunk to chunk, and so does all of this.
struct NewtonSystem
{
    explicit NewtonSystem(const PolishEnergy& energy)
        : hessian(energy.faces(), energy.slot(), energy.NumParameters())
    {
    }
    detail::PolishHessian hessian;
    detail::PairedCholmod solver;
    bool analyzed = false;
};

// The Newton step H^-1 (-gradient), with the pulls' Gauss-Newton terms 2 W u u^T added to H
// (PullSteps::GaussNewton), u over the free vertices' unknowns (slot), by the Woodbury identity
// with the factor of H (which holds the faces' part only).
Eigen::VectorXd pulled_step(const std::vector<CentrePull>& pulls, const Eigen::VectorXd& x,
                            const std::vector<int>& slot, detail::PairedCholmod& solver,
                            const Eigen::VectorXd& descent)
{
    // Hinges within a margin of turning on count too (AreaPolishOptions::pull_steps).
    const std::vector<detail::PullRow> rows = detail::active_pull_rows(pulls, x, 1.0);
    if (!rows.empty())
    {
        const detail::PullColumns columns = detail::pull_columns(rows, descent.size(), 2.0, &slot);
        Eigen::VectorXd step = solver.solve_with_low_rank(descent, columns.U, columns.c);
        if (solver.info() == Eigen::Success && step.allFinite())
            return step;
    }
    return solver.solve(descent);
}

// Up to `iterations` projected Newton steps on `energy` (its faces, free vertices and x) with
// `system` (made for the same faces and free vertices), each line searched from the full step
// back to one that flips no face and lowers the energy (Armijo). Returns the steps taken; `cost`
// is the energy at the end.
int newton_steps(PolishEnergy& energy, NewtonSystem& system, double lambda, PullSteps pull_steps,
                 int iterations, double& cost, const std::function<void(int done)>& on_step)
{
    const std::vector<int>& slot = energy.slot();
    const int m = energy.NumParameters();
    Eigen::VectorXd p(m), gradient(m), trial(m);
    energy.gather(p.data());
    if (!energy.Evaluate(p.data(), &cost, gradient.data()))
        return 0;
    detail::PairedCholmod& solver = system.solver;
    detail::PolishHessian& hessian = system.hessian;
    Eigen::SparseMatrix<double>& H = hessian.matrix();
    int done = 0;
    for (; done < iterations; ++done)
    {
        hessian.assemble(energy.faces(), energy.x().data(), lambda);
        const bool exact_pulls = pull_steps == PullSteps::GaussNewton;
        if (!exact_pulls)
            detail::add_centre_pull_curvature(energy.pulls(), energy.x(), slot,
                                              hessian.diagonal(), H.valuePtr());
        hessian.shift_diagonal();
        {
            const detail::SerialOpenMp serial;
            if (!system.analyzed)
            {
                solver.analyze_pairs(H);
                if (solver.info() != Eigen::Success)
                    break;
                system.analyzed = true;
            }
            solver.factorize(H);
        }
        if (solver.info() != Eigen::Success)
            break;
        const Eigen::VectorXd step =
            exact_pulls && !energy.pulls().empty()
                ? pulled_step(energy.pulls(), energy.x(), slot, solver, -gradient)
                : Eigen::VectorXd(solver.solve(-gradient));
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
        on_step(done + 1);
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
        detail::scaffold_triangles(x, boundary, {n, n + 1, n + 2, n + 3}, inside, n + 4,
                                   detail::kPolishScaffoldShape);
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
    std::unique_ptr<NewtonSystem> system;  // kept from chunk to chunk without a scaffold
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
            if (!system || summary.scaffold)
            {
                system.reset();  // the last chunk's factor freed before the next is made
                system = std::make_unique<NewtonSystem>(*energy);
            }
            done = newton_steps(*energy, *system, options.area_weight, options.pull_steps,
                                std::min(options.newton_chunk_iterations,
                                         options.newton_max_iterations - summary.iterations),
                                after, [&](int steps) {
                                    if (options.on_step)
                                        options.on_step(summary.iterations + steps);
                                });
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
        if (!options.newton && options.on_step)
            options.on_step(summary.iterations);
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
