#include "vessel/map/multilevel.h"

#include "detail/cell_grid.h"
#include "detail/face_jacobian.h"
#include "detail/segments.h"
#include "detail/vertex_newton.h"
#include "vessel/core/errors.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>

namespace vessel {

void MultilevelOptions::validate() const
{
    if (coarse_vertices < 0 || (coarse_vertices > 0 && coarse_vertices < 100))
        throw InvalidInputError("MultilevelOptions: coarse_vertices must be 0 (off) or >= 100, got " +
                                std::to_string(coarse_vertices));
    if (relax_sweeps < 0)
        throw InvalidInputError("MultilevelOptions: relax_sweeps must be >= 0, got " +
                                std::to_string(relax_sweeps));
    if (coarse_corrections < 0)
        throw InvalidInputError("MultilevelOptions: coarse_corrections must be >= 0, got " +
                                std::to_string(coarse_corrections));
    if (direct_correction_vertices < 0)
        throw InvalidInputError("MultilevelOptions: direct_correction_vertices must be >= 0, got " +
                                std::to_string(direct_correction_vertices));
    if (!(tolerance >= 0.0 && std::isfinite(tolerance)))
        throw InvalidInputError("MultilevelOptions: tolerance must be >= 0 and finite, got " +
                                std::to_string(tolerance));
    if (!(area_tolerance >= 0.0 && std::isfinite(area_tolerance)))
        throw InvalidInputError("MultilevelOptions: area_tolerance must be >= 0 and finite, got " +
                                std::to_string(area_tolerance));
    if (!(max_energy_ratio > 1.0 && std::isfinite(max_energy_ratio)))
        throw InvalidInputError("MultilevelOptions: max_energy_ratio must be > 1 and finite, got " +
                                std::to_string(max_energy_ratio));
}

namespace {

double orientation(const Eigen::MatrixX2d& uv, int a, int b, int c)
{
    return detail::orient(uv.row(a).transpose(), uv.row(b).transpose(), uv.row(c).transpose());
}

// Whether every face of a re-inserted vertex keeps its orientation, by more than rounding: a
// face whose area is below 1e-8 of its two edges' squared lengths counts as flat (points on one
// boundary chord), and a flat face would leave the next vertex no place.
bool star_positive(const Eigen::MatrixX2d& uv, const Collapse& collapse)
{
    for (const auto& [a, b] : collapse.faces)
    {
        const double scale =
            (uv.row(a) - uv.row(collapse.v0)).squaredNorm() + (uv.row(b) - uv.row(collapse.v0)).squaredNorm();
        if (!(orientation(uv, collapse.v0, a, b) > 1e-8 * scale))
            return false;
    }
    return true;
}

// Where the map's local affine fit over the vertex's one ring puts it: the ring's 3D positions
// in the tangent plane of the ring's faces, least squares for uv = c + B q, the vertex at q = 0.
Eigen::Vector2d fitted_position(const Mesh& fine, const Eigen::MatrixX2d& uv,
                                const Collapse& collapse)
{
    const Eigen::Vector3d p0 = to_eigen(fine.point(VertexHandle(collapse.v0)));
    Eigen::Vector3d normal = Eigen::Vector3d::Zero();
    for (const auto& [a, b] : collapse.faces)
        normal += (to_eigen(fine.point(VertexHandle(a))) - p0)
                      .cross(to_eigen(fine.point(VertexHandle(b))) - p0);
    if (normal.norm() == 0.0)
        return uv.row(collapse.v1).transpose();
    normal.normalize();
    const Eigen::Vector3d t1 = normal.unitOrthogonal(), t2 = normal.cross(t1);
    Eigen::Matrix3d normal_matrix = Eigen::Matrix3d::Zero();
    Eigen::Matrix<double, 3, 2> right = Eigen::Matrix<double, 3, 2>::Zero();
    const auto add = [&](int w) {
        const Eigen::Vector3d d = to_eigen(fine.point(VertexHandle(w))) - p0;
        const Eigen::Vector3d row(1.0, d.dot(t1), d.dot(t2));
        normal_matrix += row * row.transpose();
        right += row * uv.row(w);
    };
    for (const auto& [a, b] : collapse.faces)
    {
        add(a);
        add(b);
    }
    const Eigen::LDLT<Eigen::Matrix3d> solve(normal_matrix);
    if (solve.info() != Eigen::Success || !(solve.rcond() > 1e-12))
        return uv.row(collapse.v1).transpose();
    return solve.solve(right).row(0).transpose();
}

// settle()'s buffers, kept across calls (one per thread).
struct SettleScratch
{
    std::vector<detail::FaceOperator> ops;
    std::vector<detail::Corner> corners;
    std::vector<double> x;
    std::vector<Eigen::Vector3d> ds;
};

// A few projected Newton steps of a re-inserted interior vertex within its star (Sander et
// al. 2001 optimize each split vertex the same way): it leaves no sliver for the next ones.
void settle(const Mesh& fine, const Collapse& collapse, double area_weight, Eigen::MatrixX2d& uv,
            SettleScratch& scratch)
{
    const std::size_t n = collapse.faces.size();
    std::vector<detail::FaceOperator>& ops = scratch.ops;
    std::vector<detail::Corner>& corners = scratch.corners;
    std::vector<double>& x = scratch.x;
    ops.resize(n);
    corners.resize(n);
    x.resize(2 * (2 * n + 1));
    const auto p = [&](int v) { return to_eigen(fine.point(VertexHandle(v))); };
    x[0] = uv(collapse.v0, 0);
    x[1] = uv(collapse.v0, 1);
    for (std::size_t i = 0; i < n; ++i)
    {
        const auto [a, b] = collapse.faces[i];
        const int la = static_cast<int>(1 + 2 * i), lb = la + 1;
        x[2 * la] = uv(a, 0);
        x[2 * la + 1] = uv(a, 1);
        x[2 * lb] = uv(b, 0);
        x[2 * lb + 1] = uv(b, 1);
        ops[i] = detail::face_operator(p(collapse.v0), p(a), p(b), {0, la, lb});
        corners[i] = {static_cast<int>(i), 0};
    }
    const detail::VertexEnergy energy(ops, area_weight);
    std::vector<Eigen::Vector3d>& ds = scratch.ds;
    const auto any = [](const Eigen::Vector2d&) { return true; };
    for (int step = 0; step < 3; ++step)
        if (detail::vertex_newton_step(energy, corners.data(), corners.data() + n, x.data(), 0,
                                       std::numeric_limits<double>::infinity(), any, ds) <= 0.0)
            break;
    uv(collapse.v0, 0) = x[0];
    uv(collapse.v0, 1) = x[1];
}

// The carried map's boundary edges while prolongate() undoes the collapses, in a uniform grid,
// so that a boundary vertex's candidate places can be tested against every other boundary edge
// near them (multilevel.h). Indices are the fine mesh's.
class GrowingBoundary
{
public:
    // \p tested false: every place is clear (a map allowed to overlap itself).
    GrowingBoundary(const CoarseMesh& coarse, const Eigen::MatrixX2d& uv, bool tested)
    {
        for (auto h : coarse.mesh.halfedges())
            if (h.is_boundary())
                add(coarse.fine_of[h.from().idx()], coarse.fine_of[h.to().idx()]);
        if (edges_.empty() || !tested)
            return;
        Eigen::Vector2d lo = uv.row(edges_[0].a).transpose(), hi = lo;
        double length = 0.0;
        for (const Edge& e : edges_)
        {
            lo = lo.cwiseMin(uv.row(e.a).transpose());
            hi = hi.cwiseMax(uv.row(e.a).transpose());
            length += (uv.row(e.b) - uv.row(e.a)).norm();
        }
        // Cells about twice the mean boundary edge, at most ~4 per edge in all.
        const Eigen::Vector2d span = (hi - lo).cwiseMax(1e-12);
        grid_.cell = std::max(2.0 * length / static_cast<double>(edges_.size()),
                              std::sqrt(span.x() * span.y() / (4.0 * static_cast<double>(edges_.size()))));
        grid_.origin = lo;
        grid_.nx = static_cast<int>(span.x() / grid_.cell) + 1;
        grid_.ny = static_cast<int>(span.y() / grid_.cell) + 1;
        cells_.assign(grid_.size(), {});
        for (int e = 0; e < static_cast<int>(edges_.size()); ++e)
            enter(e, uv);
    }

    // Whether a boundary vertex put back at p between v1 and `across` keeps its two edges off
    // every other boundary edge.
    bool clear(const Eigen::MatrixX2d& uv, int v1, int across, const Eigen::Vector2d& p) const
    {
        return clear_of(uv, v1, across, uv.row(v1).transpose(), p) &&
               clear_of(uv, across, v1, p, uv.row(across).transpose());
    }

    // Replace the edge between v1 and `across` by the two through v0 (at its place in uv).
    void split(const Eigen::MatrixX2d& uv, int v0, int v1, int across)
    {
        const auto found = edge_of_.find(key(v1, across));
        if (found == edge_of_.end())
            return;  // not a boundary edge of this map (the caller's fallbacks keep going)
        const Edge old = edges_[found->second];
        edges_[found->second].alive = false;
        edge_of_.erase(found);
        for (const auto& [a, b] : {std::array<int, 2>{old.a, v0}, std::array<int, 2>{v0, old.b}})
        {
            add(a, b);
            if (!cells_.empty())
                enter(static_cast<int>(edges_.size()) - 1, uv);
        }
    }

private:
    struct Edge
    {
        int a = 0, b = 0;
        bool alive = true;
    };

    static long long key(int a, int b)
    {
        return static_cast<long long>(std::min(a, b)) << 32 | static_cast<unsigned>(std::max(a, b));
    }

    void add(int a, int b)
    {
        edge_of_[key(a, b)] = static_cast<int>(edges_.size());
        edges_.push_back({a, b, true});
    }

    // The cells of the box of segment pq (CellGrid: clamped to the grid, consistently for
    // entries and queries, so two segments that meet share a cell).
    template <class F>
    void for_cells(const Eigen::Vector2d& p, const Eigen::Vector2d& q, const F& f) const
    {
        grid_.for_cells(p.cwiseMin(q), p.cwiseMax(q), 0.0, f);
    }

    void enter(int e, const Eigen::MatrixX2d& uv)
    {
        for_cells(uv.row(edges_[e].a).transpose(), uv.row(edges_[e].b).transpose(),
                  [&](std::size_t c) { cells_[c].push_back(e); });
    }

    // Whether segment pq, from vertex `from` (its edges not tested) and replacing the edge
    // (from, other), meets no other live boundary edge.
    bool clear_of(const Eigen::MatrixX2d& uv, int from, int other, const Eigen::Vector2d& p,
                  const Eigen::Vector2d& q) const
    {
        if (cells_.empty())
            return true;
        bool clear = true;
        for_cells(p, q, [&](std::size_t c) {
            for (int e : cells_[c])
            {
                const Edge& edge = edges_[e];
                if (!clear || !edge.alive || edge.a == from || edge.b == from ||
                    key(edge.a, edge.b) == key(from, other))
                    continue;
                if (detail::segments_intersect(p, q, uv.row(edge.a).transpose(),
                                               uv.row(edge.b).transpose()))
                    clear = false;
            }
        });
        return clear;
    }

    std::vector<Edge> edges_;
    std::unordered_map<long long, int> edge_of_;
    std::vector<std::vector<int>> cells_;
    detail::CellGrid grid_;
};

}  // namespace

Eigen::MatrixX2d prolongate(const Mesh& fine, const CoarseMesh& coarse,
                            const Eigen::MatrixX2d& coarse_uv, double area_weight,
                            bool keep_boundary_simple)
{
    if (coarse_uv.rows() != static_cast<Eigen::Index>(coarse.fine_of.size()) ||
        coarse.coarse_of.size() != fine.n_vertices())
        throw InvalidInputError("prolongate: the coarse map or mesh does not match the fine mesh");
    Eigen::MatrixX2d uv = Eigen::MatrixX2d::Zero(fine.n_vertices(), 2);
    for (std::size_t c = 0; c < coarse.fine_of.size(); ++c)
        uv.row(coarse.fine_of[c]) = coarse_uv.row(c);
    GrowingBoundary boundary(coarse, uv, keep_boundary_simple);
    // Undo the collapses, the last first: each vertex comes back into the star it left, whose
    // other vertices are all placed: a boundary vertex onto (or just inside) the edge it was
    // cut from, an interior one at the fitted position; where a face of its star would flip
    // there, near its collapse target along a direction into the star's wedge at the target
    // (every face of the star is positive there; Sander et al. 2001, "Texture mapping
    // progressive meshes").
    // One collapse undone; an interior one (across < 0) reads its star and writes its own row
    // of uv alone (settle()'s scratch is the caller's).
    const auto undo = [&](const Collapse& collapse, SettleScratch& scratch) {
        const Eigen::Vector2d target = uv.row(collapse.v1).transpose();
        if (collapse.across >= 0)
        {
            // A boundary vertex goes back onto the boundary edge it was cut from, at its 3D
            // fraction of the way (or nearer the target if a face would flip there): the
            // boundary keeps its shape, so it stays simple.
            const auto p = [&](int v) { return to_eigen(fine.point(VertexHandle(v))); };
            const double to_target = (p(collapse.v0) - p(collapse.v1)).norm();
            const double to_across = (p(collapse.v0) - p(collapse.across)).norm();
            const Eigen::Vector2d edge = uv.row(collapse.across).transpose() - target;
            // On the edge if possible, else off it by as little as will do, inward: to the side
            // of the star's faces (the faces are counter-clockwise, so (v0, across, x) has x
            // left of the edge); the least lift keeps clear of a close opposite boundary.
            Eigen::Vector2d inward(-edge.y(), edge.x());
            for (const auto& [a, b] : collapse.faces)
                if (b == collapse.across)
                    inward = -inward;
            // A star of one face (v0, v1, across) is an ear over the coarse edge: it is
            // positive only with v0 on the edge's outer side.
            if (collapse.faces.size() == 1)
                inward = -inward;
            bool placed = false;
            const double s0 = to_target / std::max(to_target + to_across, 1e-300);
            // the fractions tried: the 3D one, then halfway nearer either end, alternately
            std::array<double, 21> fractions;
            fractions[0] = s0;
            for (int k = 1; k <= 10; ++k)
            {
                fractions[2 * k - 1] = s0 / std::ldexp(1.0, k);
                fractions[2 * k] = 1.0 - (1.0 - s0) / std::ldexp(1.0, k);
            }
            for (double lift : {0.0, 1e-4, 1e-3, 1e-2})
            {
                for (const double s : fractions)
                {
                    const Eigen::Vector2d trial = target + s * edge + lift * inward;
                    uv.row(collapse.v0) = trial.transpose();
                    if ((placed = star_positive(uv, collapse) &&
                                  boundary.clear(uv, collapse.v1, collapse.across, trial)))
                        break;
                }
                if (placed)
                    break;
            }
            if (placed)
            {
                boundary.split(uv, collapse.v0, collapse.v1, collapse.across);
                return;
            }
            // Where the coarse boundary turns sharply at the target, no point of the edge
            // keeps the star positive: the point of the star's kernel nearest the edge's,
            // among rays from the target at halving radii.
            const Eigen::Vector2d wanted = target + s0 * edge;
            double reach = 0.0, best = std::numeric_limits<double>::infinity();
            for (const auto& [a, b] : collapse.faces)
                reach = std::max({reach, (uv.row(a).transpose() - target).norm(),
                                  (uv.row(b).transpose() - target).norm()});
            Eigen::Vector2d chosen = target;
            for (int k = 0; k < 64; ++k)
            {
                const double angle = 2.0 * M_PI * k / 64.0;
                const Eigen::Vector2d ray(std::cos(angle), std::sin(angle));
                for (double r = 0.5; r > 1e-4; r *= 0.5)
                {
                    const Eigen::Vector2d trial = target + r * reach * ray;
                    uv.row(collapse.v0) = trial.transpose();
                    if (star_positive(uv, collapse) && (trial - wanted).norm() < best &&
                        boundary.clear(uv, collapse.v1, collapse.across, trial))
                    {
                        best = (trial - wanted).norm();
                        chosen = trial;
                    }
                }
            }
            if (std::isfinite(best))
            {
                uv.row(collapse.v0) = chosen.transpose();
                boundary.split(uv, collapse.v0, collapse.v1, collapse.across);
                return;
            }
        }
        const Eigen::Vector2d fitted = fitted_position(fine, uv, collapse);
        uv.row(collapse.v0) = fitted.transpose();
        if (collapse.across < 0 && star_positive(uv, collapse))
        {
            settle(fine, collapse, area_weight, uv, scratch);
            return;
        }
        // Near the target, only the faces (v0, v1, b) and (v0, a, v1) can flip: each asks the
        // direction d of v0 from v1 to keep b - v1 clockwise and a - v1 counter-clockwise of it.
        Eigen::Vector2d cw = Eigen::Vector2d::Zero(), ccw = Eigen::Vector2d::Zero();
        for (const auto& [a, b] : collapse.faces)
        {
            if (a == collapse.v1)
                cw = (uv.row(b).transpose() - target).normalized();
            if (b == collapse.v1)
                ccw = (uv.row(a).transpose() - target).normalized();
        }
        const auto cross = [](const Eigen::Vector2d& p, const Eigen::Vector2d& q) {
            return p.x() * q.y() - p.y() * q.x();
        };
        Eigen::Vector2d d;
        if (cw.isZero())
            d = Eigen::Vector2d(ccw.y(), -ccw.x());  // boundary: the clockwise normal of a - v1
        else if (ccw.isZero())
            d = Eigen::Vector2d(-cw.y(), cw.x());
        else
            d = cross(cw, ccw) > 0.0 ? Eigen::Vector2d(cw + ccw) : Eigen::Vector2d(-(cw + ccw));
        if (d.isZero() || !d.allFinite())
            d = Eigen::Vector2d(-cw.y(), cw.x());
        double reach = 0.0;  // the star's size at the target
        for (const auto& [a, b] : collapse.faces)
            reach = std::max({reach, (uv.row(a).transpose() - target).norm(),
                              (uv.row(b).transpose() - target).norm()});
        d = d.normalized() * reach;
        bool placed = false;
        for (double t = 0.5; t > 1e-12 && !placed; t *= 0.5)
        {
            uv.row(collapse.v0) = (target + t * d).transpose();
            placed = star_positive(uv, collapse);
        }
        if (placed && collapse.across < 0)
            settle(fine, collapse, area_weight, uv, scratch);
        if (collapse.across >= 0)
            boundary.split(uv, collapse.v0, collapse.v1, collapse.across);
    };
    // Round by round, the last first. No two collapses of a round are within one ring of each
    // other (coarsen()), so none reads a vertex another one of its round places: the boundary
    // vertices one after another (they share the growing boundary's grid), then the interior
    // ones on two threads, to the same map as one after another.
    // Without a valid record of the rounds (a CoarseMesh not made by coarsen()), each
    // collapse is a round of its own.
    const std::vector<std::size_t>& made = coarse.rounds;
    const std::size_t total = coarse.collapses.size();
    const bool recorded = !made.empty() && made.front() == 0 && made.back() < total &&
                          std::is_sorted(made.begin(), made.end());
    std::vector<std::size_t> single;
    if (!recorded)
        for (std::size_t c = 0; c < total; ++c)
            single.push_back(c);
    const std::vector<std::size_t>& rounds = recorded ? made : single;
    const int threads = detail::face_threads(fine.n_faces());  // 1 or 2
    std::vector<SettleScratch> scratch(static_cast<std::size_t>(threads));
    std::vector<const Collapse*> interior;
    for (std::size_t r = rounds.size(); r-- > 0;)
    {
        const std::size_t begin = rounds[r];
        const std::size_t end = r + 1 < rounds.size() ? rounds[r + 1] : total;
        interior.clear();
        for (std::size_t c = end; c-- > begin;)
        {
            if (coarse.collapses[c].across >= 0)
                undo(coarse.collapses[c], scratch[0]);
            else
                interior.push_back(&coarse.collapses[c]);
        }
        detail::parallel_chunks(interior.size(), interior.size() < 2048 ? 1 : threads,
                                [&](std::size_t first, std::size_t last, int t) {
                                    for (std::size_t i = first; i < last; ++i)
                                        undo(*interior[i], scratch[static_cast<std::size_t>(t)]);
                                });
    }
    return uv;
}

}  // namespace vessel
