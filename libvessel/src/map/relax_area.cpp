// relax_area(): nonlinear Gauss-Seidel, one projected Newton step per vertex and sweep
// (detail/vertex_newton.h), with a guard that keeps the boundary simple.
#include "vessel/map/multilevel.h"

#include "detail/segments.h"
#include "detail/vertex_newton.h"
#include "vessel/core/errors.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace vessel {

namespace {

// Keeps the map's boundary simple while boundary vertices move: a uniform grid of the boundary
// edges, each entered in the cells of its box grown by `margin`. A vertex moves at most
// margin / 2 per sweep, so every edge stays inside its entered box until the grid is rebuilt
// (once per sweep), and a moved vertex's two edges need only be tested against the edges
// entered in the cells they cross.
class BoundaryGuard
{
public:
    explicit BoundaryGuard(const Mesh& mesh)
    {
        for (auto h : mesh.halfedges())
            if (h.is_boundary())
                edges_.push_back({h.from().idx(), h.to().idx()});
        next_.assign(mesh.n_vertices(), -1);
        prev_.assign(mesh.n_vertices(), -1);
        for (const auto& [a, b] : edges_)
        {
            next_[a] = b;
            prev_[b] = a;
        }
    }

    bool on_boundary(int v) const { return next_[v] >= 0; }
    double max_step() const { return 0.5 * margin_; }

    // Enter every boundary edge of the map x (interleaved) in the grid.
    void rebuild(const double* x)
    {
        if (edges_.empty())
            return;
        // Cells twice the map's mean boundary edge long.
        Eigen::Vector2d lo(x[2 * edges_[0][0]], x[2 * edges_[0][0] + 1]), hi = lo;
        double length = 0.0;
        for (const auto& e : edges_)
        {
            const Eigen::Vector2d a(x[2 * e[0]], x[2 * e[0] + 1]), b(x[2 * e[1]], x[2 * e[1] + 1]);
            lo = lo.cwiseMin(a);
            hi = hi.cwiseMax(a);
            length += (b - a).norm();
        }
        const double mean = length / static_cast<double>(edges_.size());
        cell_ = 2.0 * std::max(mean, 1e-12);
        margin_ = 0.5 * cell_;
        origin_ = lo - Eigen::Vector2d::Constant(cell_);
        const Eigen::Vector2d span = hi - lo + Eigen::Vector2d::Constant(2.0 * cell_);
        nx_ = std::max(1, static_cast<int>(std::ceil(span.x() / cell_)) + 1);
        ny_ = std::max(1, static_cast<int>(std::ceil(span.y() / cell_)) + 1);
        entries_.clear();
        for (int e = 0; e < static_cast<int>(edges_.size()); ++e)
            for_cells(segment_box(x, edges_[e][0], edges_[e][1]), margin_,
                      [&](long cell) { entries_.emplace_back(cell, e); });
        std::sort(entries_.begin(), entries_.end());
    }

    // Whether moving boundary vertex v to p keeps its two edges clear of every other edge.
    bool allows(const double* x, int v, const Eigen::Vector2d& p) const
    {
        for (const int w : {prev_[v], next_[v]})
        {
            const Eigen::Vector2d q(x[2 * w], x[2 * w + 1]);
            Box box{p.cwiseMin(q), p.cwiseMax(q)};
            bool clear = true;
            for_cells(box, 0.0, [&](long cell) {
                if (!clear)
                    return;
                auto it = std::lower_bound(entries_.begin(), entries_.end(),
                                           std::make_pair(cell, -1));
                for (; it != entries_.end() && it->first == cell; ++it)
                {
                    const auto& e = edges_[it->second];
                    if (e[0] == v || e[1] == v || e[0] == w || e[1] == w)
                        continue;
                    const Eigen::Vector2d a(x[2 * e[0]], x[2 * e[0] + 1]),
                        b(x[2 * e[1]], x[2 * e[1] + 1]);
                    if (detail::segments_intersect(p, q, a, b))
                    {
                        clear = false;
                        return;
                    }
                }
            });
            if (!clear)
                return false;
        }
        return true;
    }

private:
    struct Box
    {
        Eigen::Vector2d lo, hi;
    };

    Box segment_box(const double* x, int a, int b) const
    {
        const Eigen::Vector2d p(x[2 * a], x[2 * a + 1]), q(x[2 * b], x[2 * b + 1]);
        return {p.cwiseMin(q), p.cwiseMax(q)};
    }

    template <class Visit>
    void for_cells(const Box& box, double grow, const Visit& visit) const
    {
        const auto index = [&](double value, double origin, int n) {
            return std::clamp(static_cast<int>(std::floor((value - origin) / cell_)), 0, n - 1);
        };
        const int x0 = index(box.lo.x() - grow, origin_.x(), nx_);
        const int x1 = index(box.hi.x() + grow, origin_.x(), nx_);
        const int y0 = index(box.lo.y() - grow, origin_.y(), ny_);
        const int y1 = index(box.hi.y() + grow, origin_.y(), ny_);
        for (int i = x0; i <= x1; ++i)
            for (int j = y0; j <= y1; ++j)
                visit(static_cast<long>(i) * ny_ + j);
    }

    std::vector<std::array<int, 2>> edges_;
    std::vector<int> next_, prev_;
    std::vector<std::pair<long, int>> entries_;
    double cell_ = 1.0, margin_ = 0.5;
    Eigen::Vector2d origin_ = Eigen::Vector2d::Zero();
    int nx_ = 1, ny_ = 1;
};

}  // namespace

RelaxSummary relax_area(const Mesh& mesh, Eigen::MatrixX2d& uv, const Pins& pins,
                        double area_weight, const MultilevelOptions& options)
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
    double current = summary.energy_before;

    std::vector<Eigen::Vector3d> ds;
    BoundaryGuard guard(mesh);
    // Only vertices that may still lower the energy are visited: those that lowered it in the
    // last sweep by more than a tenth of a vertex's share of what the stopping rule asks of a
    // sweep, and their neighbours (whose stars changed).
    std::vector<char> active(n, 1), next(n, 0);
    for (int sweep = 0; sweep < options.relax_sweeps; ++sweep)
    {
        guard.rebuild(x);
        const double threshold =
            0.1 * options.tolerance * std::max(current - minimum, 0.0) / std::max(n, 1);
        double lowered = 0.0;
        for (int v = 0; v < n; ++v)
        {
            if (!active[v] || pinned[v] >= 0 || first[v] == first[v + 1])
                continue;
            const detail::Corner* begin = corners.data() + first[v];
            const detail::Corner* end = corners.data() + first[v + 1];
            const bool boundary = guard.on_boundary(v);
            const double step = detail::vertex_newton_step(
                energy, begin, end, x, v,
                boundary ? guard.max_step() : std::numeric_limits<double>::infinity(),
                [&](const Eigen::Vector2d& p) { return !boundary || guard.allows(x, v, p); }, ds);
            lowered += step;
            if (step > threshold)
                for (const detail::Corner* c = begin; c != end; ++c)
                    for (int w : ops[c->face].corner)
                        next[w] = 1;
        }
        active.swap(next);
        std::fill(next.begin(), next.end(), 0);
        current -= lowered;
        summary.sweeps = sweep + 1;
        if (options.on_sweep)
            options.on_sweep(summary.sweeps);
        if (lowered <= options.tolerance * std::max(current - minimum, 0.0))
            break;
    }
    summary.energy_after = current;
    detail::deinterleave(xv, uv);
    return summary;
}

}  // namespace vessel
