#include "vessel/map/untangle.h"

#include "detail/face_jacobian.h"
#include "vessel/core/errors.h"
#include "detail/uv_rows.h"

#include <ceres/gradient_problem.h>
#include <ceres/gradient_problem_solver.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace vessel {

void UntangleOptions::validate() const
{
    if (rings < 1)
        throw InvalidInputError("UntangleOptions: rings must be >= 1");
    if (max_rounds < 1)
        throw InvalidInputError("UntangleOptions: max_rounds must be >= 1");
    if (max_iterations < 1 || max_epsilon_steps < 1)
        throw InvalidInputError("UntangleOptions: max_iterations and max_epsilon_steps must be >= 1");
    if (!(area_weight >= 0.0 && area_weight < 1.0))
        throw InvalidInputError("UntangleOptions: area_weight must be in [0, 1)");
}

namespace {

using detail::FaceOperator;

double chi(double D, double eps)
{
    return 0.5 * (D + std::sqrt(eps * eps + D * D));
}

// The regularized energy over the faces of a region, as a function of its free vertices' uv.
class RegionEnergy final : public ceres::FirstOrderFunction
{
public:
    RegionEnergy(const std::vector<FaceOperator>& ops, std::vector<int> faces,
                 std::vector<int> free_vertices, Eigen::VectorXd& x, double lambda)
        : ops_(ops), faces_(std::move(faces)), free_(std::move(free_vertices)), x_(x),
          slot_(x.size() / 2, -1), lambda_(lambda)
    {
        for (std::size_t i = 0; i < free_.size(); ++i)
            slot_[free_[i]] = static_cast<int>(i);
    }

    void set_epsilon(double eps) { eps_ = eps; }
    int NumParameters() const override { return 2 * static_cast<int>(free_.size()); }

    void gather(double* parameters) const
    {
        for (std::size_t i = 0; i < free_.size(); ++i)
        {
            parameters[2 * i] = x_[2 * free_[i]];
            parameters[2 * i + 1] = x_[2 * free_[i] + 1];
        }
    }
    void scatter(const double* parameters) const
    {
        for (std::size_t i = 0; i < free_.size(); ++i)
        {
            x_[2 * free_[i]] = parameters[2 * i];
            x_[2 * free_[i] + 1] = parameters[2 * i + 1];
        }
    }

    bool Evaluate(const double* parameters, double* cost, double* gradient) const override
    {
        scatter(parameters);
        if (gradient)
            std::fill(gradient, gradient + NumParameters(), 0.0);
        double e = 0.0;
        for (int f : faces_)
        {
            const FaceOperator& op = ops_[f];
            const Eigen::Matrix2d J = detail::jacobian(op, x_.data());
            const double D = J.determinant();
            const double root = std::sqrt(eps_ * eps_ + D * D);
            const double c = 0.5 * (D + root);
            const double frob = J.squaredNorm();
            e += op.area * ((1.0 - lambda_) * frob + lambda_ * (D * D + 1.0)) / c;
            if (!gradient)
                continue;
            const double dc = c / root;  // d chi / dD
            Eigen::Matrix2d cof;
            cof << J(1, 1), -J(1, 0), -J(0, 1), J(0, 0);
            const Eigen::Matrix2d G =
                op.area * ((1.0 - lambda_) * (2.0 / c * J - frob * dc / (c * c) * cof) +
                           lambda_ * (2.0 * D / c - (D * D + 1.0) * dc / (c * c)) * cof);
            detail::add_face_gradient(op, G, slot_, gradient);
        }
        *cost = e;
        return std::isfinite(e);
    }

    double min_det() const
    {
        double d = std::numeric_limits<double>::infinity();
        for (int f : faces_)
            d = std::min(d, detail::jacobian(ops_[f], x_.data()).determinant());
        return d;
    }

private:
    const std::vector<FaceOperator>& ops_;
    std::vector<int> faces_;
    std::vector<int> free_;
    Eigen::VectorXd& x_;
    std::vector<int> slot_;
    double lambda_;
    double eps_ = 1.0;
};

std::vector<int> flipped_faces(const std::vector<FaceOperator>& ops, const Eigen::VectorXd& x)
{
    std::vector<int> flipped;
    for (std::size_t f = 0; f < ops.size(); ++f)
        if (!(detail::jacobian(ops[f], x.data()).determinant() > 0.0))
            flipped.push_back(static_cast<int>(f));
    return flipped;
}

// Vertices within `rings` edges of a flipped face (all vertices when rings < 0).
std::vector<char> grow_region(const Mesh& mesh, const std::vector<FaceOperator>& ops,
                              const std::vector<int>& flipped, int rings)
{
    std::vector<char> in(mesh.n_vertices(), rings < 0 ? 1 : 0);
    if (rings < 0)
        return in;
    std::vector<int> front;
    for (int f : flipped)
        for (int v : ops[f].corner)
            if (!in[v])
            {
                in[v] = 1;
                front.push_back(v);
            }
    for (int r = 0; r < rings; ++r)
    {
        std::vector<int> next;
        for (int v : front)
            for (auto w : mesh.vv_range(VertexHandle(v)))
                if (!in[w.idx()])
                {
                    in[w.idx()] = 1;
                    next.push_back(w.idx());
                }
        front.swap(next);
    }
    return in;
}

// Garanzha et al.'s schedule: minimize at fixed eps, then shrink eps according to how much the
// energy fell and how inverted the worst face still is. Stops once no face is inverted.
void minimize(const ceres::GradientProblem& problem, RegionEnergy& energy,
              const UntangleOptions& options)
{
    ceres::GradientProblemSolver::Options solver_options;
    solver_options.line_search_direction_type = ceres::LBFGS;
    solver_options.max_num_iterations = options.max_iterations;
    solver_options.logging_type = ceres::SILENT;
    solver_options.minimizer_progress_to_stdout = false;
    std::vector<double> p(energy.NumParameters());
    double d_min = energy.min_det();
    double eps = std::max(1e-3, 2.0 * std::abs(std::min(d_min, 0.0)));
    int polished = 0;
    for (int step = 0; step < options.max_epsilon_steps; ++step)
    {
        energy.set_epsilon(eps);
        energy.gather(p.data());
        double before = 0.0;
        energy.Evaluate(p.data(), &before, nullptr);
        ceres::GradientProblemSolver::Summary summary;
        ceres::Solve(solver_options, problem, p.data(), &summary);
        energy.scatter(p.data());
        double after = 0.0;
        energy.Evaluate(p.data(), &after, nullptr);
        d_min = energy.min_det();
        // Once untangled, steps at a smaller eps also even out the faces left nearly flat.
        if (d_min > 0.0 && polished++ == options.polish_steps)
            return;
        const double sigma = std::max(1.0 - after / before, 0.1);
        const double mu = (1.0 - sigma) * chi(d_min, eps);
        eps = d_min < mu ? 2.0 * std::sqrt(mu * (mu - d_min)) : 1e-12;
    }
}

}  // namespace

UntangleSummary untangle(const Mesh& mesh, Eigen::MatrixX2d& uv, const Pins& pins,
                         const UntangleOptions& options)
{
    options.validate();
    const int n = static_cast<int>(mesh.n_vertices());
    detail::require_uv_rows(mesh, uv, "untangle");
    const std::vector<int> pinned = pin_index(mesh, pins, "untangle");
    const std::vector<FaceOperator> ops = detail::face_operators(mesh);
    Eigen::VectorXd x = detail::interleaved(uv);

    UntangleSummary summary;
    std::vector<int> flipped = flipped_faces(ops, x);
    summary.flipped_before = static_cast<int>(flipped.size());
    int rings = options.rings;
    while (!flipped.empty() && summary.rounds < options.max_rounds)
    {
        const bool last = summary.rounds + 1 == options.max_rounds;
        const std::vector<char> region = grow_region(mesh, ops, flipped, last ? -1 : rings);
        const auto movable = [&](int v) { return region[v] && pinned[v] < 0; };
        std::vector<int> free_vertices, faces;
        for (int v = 0; v < n; ++v)
            if (movable(v))
                free_vertices.push_back(v);
        for (std::size_t f = 0; f < ops.size(); ++f)
            if (std::any_of(ops[f].corner.begin(), ops[f].corner.end(), movable))
                faces.push_back(static_cast<int>(f));
        ++summary.rounds;
        summary.free_vertices = static_cast<int>(free_vertices.size());
        auto* energy = new RegionEnergy(ops, std::move(faces), std::move(free_vertices), x,
                                        options.area_weight);
        const ceres::GradientProblem problem(energy);  // owns the energy
        minimize(problem, *energy, options);
        flipped = flipped_faces(ops, x);
        rings *= 2;
    }
    summary.flipped_after = static_cast<int>(flipped.size());
    detail::deinterleave(x, uv);
    summary.report = "untangle: " + std::to_string(summary.flipped_before) + " -> " +
                     std::to_string(summary.flipped_after) + " flipped triangles in " +
                     std::to_string(summary.rounds) + " round(s), " +
                     std::to_string(summary.free_vertices) + " vertices moved in the last";
    return summary;
}

}  // namespace vessel
