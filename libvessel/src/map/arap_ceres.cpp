#include "detail/arap_ceres.h"

#include "vessel/core/errors.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

namespace vessel::detail {

namespace {

// Residual of one face: r = sqrt(area_t) * vec(J_t - R(theta_t)), four components, where
// J_t = [u1 - u0, u2 - u0] X_inv is the Jacobian of the map in the face's isometric frame.
// Ceres minimises 1/2 sum ||r||^2 = 1/2 sum_t area_t ||J_t - R(theta_t)||_F^2, which at the
// optimal angles is exactly half the documented arap_energy(); the factor 1/2 changes neither
// the minimiser nor the relative function tolerance. The per-face form (rather than per-edge
// residuals sqrt(cot_k / 2) * (...)) also works for obtuse triangles, whose cotangents are < 0.
struct ArapFaceResidual
{
    ArapFaceResidual(const Eigen::Matrix2d& X_inv, double area)
        : X_inv_(X_inv), sqrt_area_(std::sqrt(area))
    {}

    template <typename T>
    bool operator()(const T* uv0, const T* uv1, const T* uv2, const T* angle, T* r) const
    {
        using std::cos;
        using std::sin;
        const T d00 = uv1[0] - uv0[0], d01 = uv2[0] - uv0[0];  // row u of [u1 - u0, u2 - u0]
        const T d10 = uv1[1] - uv0[1], d11 = uv2[1] - uv0[1];  // row v
        const T j00 = d00 * X_inv_(0, 0) + d01 * X_inv_(1, 0);
        const T j01 = d00 * X_inv_(0, 1) + d01 * X_inv_(1, 1);
        const T j10 = d10 * X_inv_(0, 0) + d11 * X_inv_(1, 0);
        const T j11 = d10 * X_inv_(0, 1) + d11 * X_inv_(1, 1);
        const T c = cos(angle[0]), s = sin(angle[0]);
        r[0] = sqrt_area_ * (j00 - c);
        r[1] = sqrt_area_ * (j01 + s);
        r[2] = sqrt_area_ * (j10 - s);
        r[3] = sqrt_area_ * (j11 - c);
        return true;
    }

    static ceres::CostFunction* create(const Eigen::Matrix2d& X_inv, double area)
    {
        return new ceres::AutoDiffCostFunction<ArapFaceResidual, 4, 2, 2, 2, 1>(
            new ArapFaceResidual(X_inv, area));
    }

private:
    Eigen::Matrix2d X_inv_;
    double sqrt_area_;
};

// Reports the documented energy of the current map after every iteration to
// ArapOptions::on_iteration (the parameter blocks are kept up to date for it).
class EnergyReporter : public ceres::IterationCallback
{
public:
    EnergyReporter(const std::vector<ArapFace>& faces, const std::vector<double>& x,
                   const Eigen::MatrixX2d& uv, const ArapOptions& options)
        : faces_(faces), x_(x), uv_(uv), options_(options)
    {}

    ceres::CallbackReturnType operator()(const ceres::IterationSummary& summary) override
    {
        if (summary.iteration == 0)  // the evaluation at the starting point
            return ceres::SOLVER_CONTINUE;
        for (Eigen::Index i = 0; i < uv_.rows(); ++i)
            uv_.row(i) << x_[2 * i], x_[2 * i + 1];
        return options_.on_iteration(summary.iteration, arap_energy(faces_, uv_))
                   ? ceres::SOLVER_CONTINUE
                   : ceres::SOLVER_TERMINATE_SUCCESSFULLY;
    }

private:
    const std::vector<ArapFace>& faces_;
    const std::vector<double>& x_;
    Eigen::MatrixX2d uv_;  // pinned rows hold their targets throughout
    const ArapOptions& options_;
};

}  // namespace

ArapSummary arap_ceres(const Mesh& mesh, const std::vector<ArapFace>& faces, Eigen::MatrixX2d& uv,
                       const std::vector<bool>& is_pinned, const ArapOptions& options)
{
    const int n = static_cast<int>(mesh.n_vertices());
    // Ceres wants contiguous parameter blocks: (u, v) per vertex and one angle per face, each
    // angle initialised from the closest rotation of the initial map.
    std::vector<double> x(2 * n);
    for (int i = 0; i < n; ++i)
    {
        x[2 * i] = uv(i, 0);
        x[2 * i + 1] = uv(i, 1);
    }
    std::vector<double> angles(faces.size());
    for (std::size_t t = 0; t < faces.size(); ++t)
        angles[t] = closest_rotation_angle(arap_jacobian(faces[t], uv));

    ceres::Problem problem;
    for (std::size_t t = 0; t < faces.size(); ++t)
    {
        const ArapFace& f = faces[t];
        problem.AddResidualBlock(ArapFaceResidual::create(f.X_inv, f.area), nullptr, &x[2 * f.v[0]],
                                 &x[2 * f.v[1]], &x[2 * f.v[2]], &angles[t]);
    }
    int n_free = 0;
    for (int i = 0; i < n; ++i)
    {
        if (!problem.HasParameterBlock(&x[2 * i]))
            continue;
        if (is_pinned[i])
            problem.SetParameterBlockConstant(&x[2 * i]);
        else
            ++n_free;
    }

    ArapSummary summary;
    summary.initial_energy = summary.final_energy = arap_energy(faces, uv);
    if (n_free == 0)
    {
        summary.converged = true;
        summary.report = "Ceres: every vertex is pinned";
        return summary;
    }

    ceres::Solver::Options solver_options;
    solver_options.minimizer_type = ceres::TRUST_REGION;
    solver_options.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
    solver_options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
    solver_options.sparse_linear_algebra_library_type =
        ceres::IsSparseLinearAlgebraLibraryTypeAvailable(ceres::SUITE_SPARSE) ? ceres::SUITE_SPARSE
                                                                              : ceres::EIGEN_SPARSE;
    solver_options.num_threads = options.threads;
    solver_options.max_num_iterations = options.max_iterations;
    solver_options.function_tolerance = options.tolerance;
    // Ceres' defaults (1e-10, 1e-8) would stop before a tight function tolerance is reached.
    solver_options.gradient_tolerance = std::min(1e-10, 1e-4 * options.tolerance);
    solver_options.parameter_tolerance = std::min(1e-8, options.tolerance);
    solver_options.logging_type = ceres::SILENT;
    solver_options.minimizer_progress_to_stdout = false;

    EnergyReporter reporter(faces, x, uv, options);
    if (options.on_iteration)
    {
        solver_options.update_state_every_iteration = true;
        solver_options.callbacks.push_back(&reporter);
    }

    std::string error;
    if (!solver_options.IsValid(&error))
        throw SolverError("arap: invalid Ceres options: " + error);
    ceres::Solver::Summary ceres_summary;
    ceres::Solve(solver_options, &problem, &ceres_summary);
    if (!ceres_summary.IsSolutionUsable())
        throw SolverError("arap: Ceres failed: " + ceres_summary.BriefReport());

    for (int i = 0; i < n; ++i)
        if (!is_pinned[i])
            uv.row(i) << x[2 * i], x[2 * i + 1];
    // iterations[0] is the evaluation at the starting point, not a step.
    summary.iterations = static_cast<int>(ceres_summary.iterations.size()) - 1;
    summary.final_energy = arap_energy(faces, uv);
    summary.converged = ceres_summary.termination_type == ceres::CONVERGENCE;
    summary.report = ceres_summary.BriefReport();
    return summary;
}

}  // namespace vessel::detail
