// relax_area(): nonlinear Gauss-Seidel, one projected Newton step per vertex and sweep
// (detail/vertex_newton.h), with a guard that keeps the boundary simple, and coarse-grid
// corrections from the level the map was carried from (detail/coarse_correction.h).
#include "vessel/map/multilevel.h"

#include "detail/boundary_guard.h"
#include "detail/centre_pull.h"
#include "detail/coarse_correction.h"
#include "detail/map_distortion.h"
#include "detail/vertex_newton.h"
#include "vessel/core/errors.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <utility>

namespace vessel {

namespace {

// flat_quality()'s mean |log area| (normalized: the map scaled to the surface's area) of the
// map x over the faces \p ops, none flipped (relax_area() flips none). Summed in two fixed
// halves, one per thread where there are two: the same bits whatever the thread count.
double mean_abs_log_area(const std::vector<detail::FaceOperator>& ops, const double* x, int threads)
{
    std::vector<std::pair<double, double>> areas(ops.size());  // (map, surface) per face
    const std::array<std::size_t, 3> part{0, ops.size() / 2, ops.size()};
    std::array<double, 2> area3{}, area2{}, sum{};
    const auto halves = [&](const auto& body) {
        detail::parallel_chunks(2, std::min(threads, 2),
                                [&](std::size_t begin, std::size_t end, int) {
                                    for (std::size_t p = begin; p < end; ++p)
                                        body(p);
                                });
    };
    halves([&](std::size_t p) {
        for (std::size_t f = part[p]; f < part[p + 1]; ++f)
        {
            // det J = the face's map area over its surface area
            areas[f] = {detail::jacobian(ops[f], x).determinant() * ops[f].area, ops[f].area};
            area2[p] += areas[f].first;
            area3[p] += areas[f].second;
        }
    });
    const double total3 = area3[0] + area3[1];
    if (!(total3 > 0.0))
        return 0.0;
    const double shift = std::log((area2[0] + area2[1]) / total3);
    halves([&](std::size_t p) {
        sum[p] = detail::normalized_log_area_sum(areas.data() + part[p], areas.data() + part[p + 1],
                                                 shift);
    });
    return (sum[0] + sum[1]) / total3;
}

// The look pulls (centre_pull.h) in the sweeps: each pulled set's vertex sum, kept up to date
// as its vertices step one after another, so that a vertex's step sees the pulls' energy, its
// gradient and the Gauss-Newton curvature of its own share of each centre.
class SweepPulls
{
public:
    SweepPulls(const std::vector<CentrePull>& pulls, const double* x, int n)
        : pulls_(pulls), sums_(pulls.size()), of_(static_cast<std::size_t>(n))
    {
        reset(x);
        for (std::size_t j = 0; j < pulls.size(); ++j)
            for (int which = 0; which < (pulls[j].kind == PullKind::Order ? 2 : 1); ++which)
                for (int v : set(j, which))
                    of_[static_cast<std::size_t>(v)].push_back({static_cast<int>(j), which});
    }

    //! The sums again from the map \p x (after a coarse-grid correction moved every vertex).
    void reset(const double* x)
    {
        for (std::size_t j = 0; j < pulls_.size(); ++j)
            for (int which = 0; which < 2; ++which)
            {
                Eigen::Vector2d sum = Eigen::Vector2d::Zero();
                if (which == 0 || pulls_[j].kind == PullKind::Order)
                    for (int v : set(j, which))
                        sum += Eigen::Vector2d(x[2 * v], x[2 * v + 1]);
                sums_[j][static_cast<std::size_t>(which)] = sum;
            }
    }

    bool pulls(int v) const { return !of_[static_cast<std::size_t>(v)].empty(); }

    //! All the pulls' energy.
    double energy() const
    {
        double e = 0.0;
        for (std::size_t j = 0; j < pulls_.size(); ++j)
            e += term(j, -1, Eigen::Vector2d::Zero(), nullptr, nullptr);
        return e;
    }

    //! The energy of the pulls on v with v moved by \p by from where the sums have it, adding
    //! their gradient and Gauss-Newton Hessian by v's position where those are not null.
    double at(int v, const Eigen::Vector2d& by, Eigen::Vector2d* grad, Eigen::Matrix2d* hess) const
    {
        double e = 0.0;
        for (const auto& [j, which] : of_[static_cast<std::size_t>(v)])
            e += term(static_cast<std::size_t>(j), which, by, grad, hess);
        return e;
    }

    //! v moved by \p by.
    void moved(int v, const Eigen::Vector2d& by)
    {
        for (const auto& [j, which] : of_[static_cast<std::size_t>(v)])
            sums_[static_cast<std::size_t>(j)][static_cast<std::size_t>(which)] += by;
    }

private:
    const std::vector<int>& set(std::size_t j, int which) const
    {
        return which == 0 ? pulls_[j].vertices : pulls_[j].second;
    }
    // Set `which` of pull j's centre relative to its origin, set `moving` moved by `by`.
    Eigen::Vector2d centre(std::size_t j, int which, int moving, const Eigen::Vector2d& by) const
    {
        const double n = static_cast<double>(set(j, which).size());
        return (sums_[j][static_cast<std::size_t>(which)] +
                (which == moving ? by : Eigen::Vector2d::Zero())) / n -
               pulls_[j].origin;
    }
    // Pull j's energy W r^2 (where it is active) with set `moving` moved by `by` (one vertex
    // of it moved by `by`), adding 2 W r dr/dp and 2 W dr/dp dr/dp^T, dr/dp = dr/dc / |set|.
    double term(std::size_t j, int moving, const Eigen::Vector2d& by, Eigen::Vector2d* grad,
                Eigen::Matrix2d* hess) const
    {
        const CentrePull& pull = pulls_[j];
        const detail::PullResidual res = detail::pull_residual(
            pull, centre(j, 0, moving, by),
            pull.kind == PullKind::Order ? centre(j, 1, moving, by) : Eigen::Vector2d::Zero());
        if (!res.active)
            return 0.0;
        if (moving >= 0 && (grad || hess))
        {
            const Eigen::Vector2d u = (moving == 0 ? res.by_first : res.by_second) /
                                      static_cast<double>(set(j, moving).size());
            if (grad)
                *grad += 2.0 * pull.weight * res.r * u;
            if (hess)
                *hess += 2.0 * pull.weight * u * u.transpose();
        }
        return pull.weight * res.r * res.r;
    }

    const std::vector<CentrePull>& pulls_;
    std::vector<std::array<Eigen::Vector2d, 2>> sums_;
    std::vector<std::vector<std::pair<int, int>>> of_;  // (pull, set) per vertex
};

}  // namespace

RelaxSummary relax_area(const Mesh& mesh, Eigen::MatrixX2d& uv, const Pins& pins,
                        double area_weight, const MultilevelOptions& options,
                        const CoarseMesh* coarser, const Eigen::MatrixX2d* coarser_uv,
                        bool keep_boundary_simple, const CoarseMesh* below,
                        const Eigen::MatrixX2d* below_uv, const std::vector<CentrePull>* pulls)
{
    options.validate();
    if (uv.rows() != static_cast<Eigen::Index>(mesh.n_vertices()))
        throw InvalidInputError("relax_area: the map has " + std::to_string(uv.rows()) +
                                " rows for " + std::to_string(mesh.n_vertices()) + " vertices");
    if (!(area_weight >= 0.0 && area_weight < 1.0))
        throw InvalidInputError("relax_area: area_weight must be in [0, 1), got " +
                                std::to_string(area_weight));
    const std::vector<int> pinned = pin_index(mesh, pins, "relax_area");
    const std::vector<detail::FaceOperator> ops = detail::face_operators(mesh);
    const detail::VertexEnergy energy(ops, area_weight);
    Eigen::VectorXd xv = detail::interleaved(uv);
    double* x = xv.data();

    // The faces around each vertex (compressed rows).
    const int n = static_cast<int>(mesh.n_vertices());
    std::vector<int> first(n + 1, 0);
    for (const auto& op : ops)
        for (int v : op.corner)
            ++first[v + 1];
    for (int v = 0; v < n; ++v)
        first[v + 1] += first[v];
    std::vector<detail::Corner> corners(first[n]);
    {
        std::vector<int> next(first.begin(), first.end() - 1);
        for (int f = 0; f < static_cast<int>(ops.size()); ++f)
            for (int k = 0; k < 3; ++k)
                corners[next[ops[f].corner[k]]++] = {f, k};
    }

    RelaxSummary summary;
    double total_area = 0.0;
    for (const auto& op : ops)
    {
        const double e = energy.face(op, x);
        if (!std::isfinite(e))
            throw InvalidInputError("relax_area: the map has a flipped or degenerate face; "
                                    "untangle it first (untangle.h)");
        summary.energy_before += e;
        total_area += op.area;
    }
    const double minimum = 2.0 * total_area;  // every face an isometry
    // The look pulls on the guarded boundary, whose vertices step one after another (the
    // pulled sets are boundary loops); none where the boundary may cross (no restart there).
    std::optional<SweepPulls> sweep_pulls;
    std::function<double(const Eigen::VectorXd&)> pull_energy;
    if (pulls && !pulls->empty() && keep_boundary_simple)
    {
        detail::require_centre_pull_vertices(*pulls, n, "relax_area");
        sweep_pulls.emplace(*pulls, x, n);
        summary.energy_before += sweep_pulls->energy();
        pull_energy = [pulls](const Eigen::VectorXd& y) {
            return detail::centre_pull_energy(*pulls, y);
        };
    }
    double current = summary.energy_before;

    detail::BoundaryGuard guard(mesh);
    std::unique_ptr<detail::CoarseCorrection> correction;
    if (coarser && coarser_uv && options.coarse_corrections > 0)
    {
        if (coarser->coarse_of.size() != static_cast<std::size_t>(n) ||
            coarser_uv->rows() != static_cast<Eigen::Index>(coarser->mesh.n_vertices()))
            throw InvalidInputError("relax_area: the coarser level (" +
                                    std::to_string(coarser->coarse_of.size()) + " fine vertices, " +
                                    std::to_string(coarser_uv->rows()) + " map rows for " +
                                    std::to_string(coarser->mesh.n_vertices()) +
                                    " coarse vertices) does not match the mesh of " +
                                    std::to_string(n) + " vertices and its map");
        Eigen::SparseMatrix<double> below_interpolation;
        const auto direct = static_cast<std::size_t>(options.direct_correction_vertices);
        if (below && below_uv && coarser->mesh.n_vertices() > direct)
        {
            if (below->coarse_of.size() != coarser->mesh.n_vertices() ||
                below_uv->rows() != static_cast<Eigen::Index>(below->mesh.n_vertices()))
                throw InvalidInputError(
                    "relax_area: the level below the coarser one (" +
                    std::to_string(below->coarse_of.size()) + " vertices above it, " +
                    std::to_string(below_uv->rows()) + " map rows for " +
                    std::to_string(below->mesh.n_vertices()) +
                    " vertices) does not match the coarser level of " +
                    std::to_string(coarser->mesh.n_vertices()) + " vertices and its map");
            below_interpolation =
                detail::coarse_interpolation(below->mesh, below->coarse_of, *below_uv, *coarser_uv);
        }
        correction = std::make_unique<detail::CoarseCorrection>(
            ops, detail::coarse_interpolation(coarser->mesh, coarser->coarse_of, *coarser_uv, uv),
            pinned, area_weight, std::move(below_interpolation));
    }
    // Only vertices that may still lower the energy are visited: those that lowered it in the
    // last sweep by more than a tenth of a vertex's share of what the stopping rule asks of a
    // sweep and, but for the guarded boundary vertices, by more than a tenth of the mean
    // decrease of the vertices that stepped in it; and their neighbours, whose stars changed.
    // A sweep's decrease is concentrated on few vertices (most of them lower the energy by
    // orders of magnitude less than the mean), and every vertex steps again after a coarse-grid
    // correction, which moves them all. A boundary vertex's step is capped by the guard
    // (BoundaryGuard::max_step()), so its decrease in one sweep does not tell how far it has
    // still to go (docs/benchmarks.md "Coarse-to-fine").
    // Without coarse-grid corrections every vertex steps in every sweep: the visited set then
    // only narrows, and the sweeps stall on the map's area error, whose steps lower the energy
    // too little to keep their vertices visited (docs/benchmarks.md, "A pulled carry's finest
    // level").
    constexpr double kActiveShareOfMean = 0.1;
    const bool narrow = static_cast<bool>(correction);
    std::vector<char> active(n, 1), next(n, 0);
    // The free interior vertices by colour, no two of a colour in one face: a vertex's step
    // reads and writes its star alone, so the vertices of a colour step in parallel and in any
    // order to the same result (multicolour Gauss-Seidel; Adams 2001, "A distributed memory
    // unstructured Gauss-Seidel algorithm for multigrid smoothers"). The guarded boundary
    // vertices, whose steps test the other boundary edges, step one after another.
    const auto is_free = [&](int v) { return pinned[v] < 0 && first[v] != first[v + 1]; };
    std::vector<int> boundary_vertices;
    std::vector<std::vector<int>> colours;
    {
        std::vector<int> colour(n, -1);
        std::vector<char> taken;
        for (int v = 0; v < n; ++v)
        {
            if (!is_free(v))
                continue;
            if (keep_boundary_simple && (guard.on_boundary(v) || (sweep_pulls && sweep_pulls->pulls(v))))
            {
                boundary_vertices.push_back(v);
                continue;
            }
            taken.assign(taken.size(), 0);
            for (int c = first[v]; c < first[v + 1]; ++c)
                for (int w : ops[corners[c].face].corner)
                    if (colour[w] >= 0)
                    {
                        if (colour[w] >= static_cast<int>(taken.size()))
                            taken.resize(colour[w] + 1, 0);
                        taken[colour[w]] = 1;
                    }
            int c = 0;
            while (c < static_cast<int>(taken.size()) && taken[c])
                ++c;
            colour[v] = c;
            if (c >= static_cast<int>(colours.size()))
                colours.resize(c + 1);
            colours[c].push_back(v);
        }
    }
    const int threads = detail::face_threads(ops.size());
    std::vector<std::vector<Eigen::Vector3d>> scratch(static_cast<std::size_t>(threads));
    // Each vertex's decrease in this sweep (0 where it did not step), summed in the colour's
    // order: the sweep's total, and with it the stopping rule, is then the same bits whatever
    // the thread count.
    std::vector<double> lowered_at(n, 0.0);
    for (int sweep = 0; sweep < options.relax_sweeps; ++sweep)
    {
        if (keep_boundary_simple)
            guard.rebuild(x);
        const double threshold =
            0.1 * options.tolerance * std::max(current - minimum, 0.0) / std::max(n, 1);
        // One vertex's step: the energy it lowered (0: not moved).
        const auto step_vertex = [&](int v, bool boundary, std::vector<Eigen::Vector3d>& ds) {
            const detail::Corner* begin = corners.data() + first[v];
            const detail::Corner* end = corners.data() + first[v + 1];
            const Eigen::Vector2d from(x[2 * v], x[2 * v + 1]);
            if (boundary && sweep_pulls && sweep_pulls->pulls(v))
            {
                const double by = detail::vertex_newton_step(
                    energy, begin, end, x, v, guard.max_step(),
                    [&](const Eigen::Vector2d& p) { return guard.allows(x, v, from, p); }, ds,
                    [&](const Eigen::Vector2d& p, Eigen::Vector2d* grad, Eigen::Matrix2d* hess) {
                        return sweep_pulls->at(v, p - from, grad, hess);
                    });
                sweep_pulls->moved(v, Eigen::Vector2d(x[2 * v], x[2 * v + 1]) - from);
                return by;
            }
            return detail::vertex_newton_step(
                energy, begin, end, x, v,
                boundary ? guard.max_step() : std::numeric_limits<double>::infinity(),
                [&](const Eigen::Vector2d& p) { return !boundary || guard.allows(x, v, from, p); },
                ds);
        };
        double lowered = 0.0;
        for (const std::vector<int>& members : colours)
        {
            detail::parallel_chunks(
                members.size(), members.size() < 2048 ? 1 : threads,
                [&](std::size_t begin, std::size_t end, int t) {
                    for (std::size_t i = begin; i < end; ++i)
                        lowered_at[members[i]] =
                            active[members[i]] ? step_vertex(members[i], false, scratch[t]) : 0.0;
                });
            for (int v : members)
                lowered += lowered_at[v];
        }
        for (int v : boundary_vertices)
        {
            lowered_at[v] = active[v] ? step_vertex(v, true, scratch[0]) : 0.0;
            lowered += lowered_at[v];
        }
        if (narrow)
        {
            std::size_t stepped = 0;
            for (const std::vector<int>& members : colours)
                for (int v : members)
                    stepped += active[v];
            for (int v : boundary_vertices)
                stepped += active[v];
            const double active_above =
                std::max(threshold, kActiveShareOfMean * lowered /
                                        static_cast<double>(std::max<std::size_t>(stepped, 1)));
            for (int v = 0; v < n; ++v)
                if (lowered_at[v] >
                    (keep_boundary_simple && guard.on_boundary(v) ? threshold : active_above))
                    for (int c = first[v]; c < first[v + 1]; ++c)
                        for (int w : ops[corners[c].face].corner)
                            next[w] = 1;
            active.swap(next);
            std::fill(next.begin(), next.end(), 0);
        }
        current -= lowered;
        summary.sweeps = sweep + 1;
        // A coarse-grid correction after every second sweep (the sweeps first smooth what the
        // carry left), and where the sweeps would stop: they converge no further, the coarse
        // step may.
        const bool converged = lowered <= options.tolerance * std::max(current - minimum, 0.0);
        bool corrected = false;
        if (correction && summary.corrections < options.coarse_corrections &&
            (summary.sweeps % 2 == 0 || converged))
        {
            const double by = correction->step(
                energy, xv, keep_boundary_simple ? &guard : nullptr, current, pull_energy);
            x = xv.data();
            if (sweep_pulls)
                sweep_pulls->reset(x);
            ++summary.corrections;
            corrected = true;
            if (by > 0.0)
            {
                std::fill(active.begin(), active.end(), 1);  // every star changed
                lowered += by;
            }
        }
        summary.last_decrease = lowered;
        if (options.on_sweep)
            options.on_sweep(summary.sweeps);
        if (corrected && options.area_tolerance > 0.0 &&
            mean_abs_log_area(ops, x, threads) <= options.area_tolerance)
        {
            summary.area_within_tolerance = true;
            break;
        }
        if (lowered <= options.tolerance * std::max(current - minimum, 0.0))
            break;
    }
    summary.energy_after = current;
    detail::deinterleave(xv, uv);
    return summary;
}

}  // namespace vessel
