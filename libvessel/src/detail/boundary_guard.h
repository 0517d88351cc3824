#pragma once
// BoundaryGuard: keeps a map's boundary simple, and its parts apart, while vertices move one at a
// time (relax_area(), and the opening of near contacts after a coarse-to-fine carry).

#include "detail/cell_grid.h"
#include "detail/segments.h"
#include "vessel/core/mesh.h"

#include <Eigen/Core>

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>
#include <vector>

namespace vessel::detail {

// Keeps the map's boundary simple while boundary vertices move, and its parts apart: no move
// brings a boundary edge nearer another than a clearance (a hundredth of the mean boundary
// edge), or, where two were that near already, any nearer. Without it the area energy closes
// the gap between two branches laid side by side to a contact that the written map's rounded
// coordinates turn into overlapping triangles. A uniform grid of the boundary edges, each
// entered in the cells of its box grown by `margin`. A vertex moves at most
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
        const double cell = 2.0 * std::max(mean, 1e-12);
        margin_ = 0.5 * cell;
        clearance_ = 0.01 * mean;
        grid_.cell = cell;
        grid_.origin = lo - Eigen::Vector2d::Constant(cell);
        const Eigen::Vector2d span = hi - lo + Eigen::Vector2d::Constant(2.0 * cell);
        grid_.nx = std::max(1, static_cast<int>(std::ceil(span.x() / cell)) + 1);
        grid_.ny = std::max(1, static_cast<int>(std::ceil(span.y() / cell)) + 1);
        entries_.clear();
        for (int e = 0; e < static_cast<int>(edges_.size()); ++e)
        {
            const Box box = segment_box(x, edges_[e][0], edges_[e][1]);
            grid_.for_cells(box.lo, box.hi, margin_, [&](std::size_t c) {
                entries_.emplace_back(static_cast<long>(c), e);
            });
        }
        // Each cell's edges in increasing order: by a counting sort into per-cell runs where
        // the cells are not many more than the entries (a boundary whose map spans a square),
        // else sorted, each cell's run then found by a bisection.
        const std::size_t cells = grid_.size();
        cell_start_.clear();
        if (cells <= kDenseCellsPerEntry * entries_.size() + kDenseCells)
        {
            cell_start_.assign(cells + 1, 0);
            for (const auto& entry : entries_)
                ++cell_start_[static_cast<std::size_t>(entry.first) + 1];
            for (std::size_t c = 0; c < cells; ++c)
                cell_start_[c + 1] += cell_start_[c];
            cell_edges_.resize(entries_.size());
            std::vector<int> next(cell_start_.begin(), cell_start_.end() - 1);
            for (const auto& entry : entries_)  // in increasing edge order
                cell_edges_[static_cast<std::size_t>(
                    next[static_cast<std::size_t>(entry.first)]++)] = entry.second;
        }
        else
            std::sort(entries_.begin(), entries_.end());
    }

    // Whether moving boundary vertex v from `from` to p keeps its two edges clear of every
    // other edge (x: the map, where v's own entry is not read).
    bool allows(const double* x, int v, const Eigen::Vector2d& from, const Eigen::Vector2d& p) const
    {
        bool clear = true;
        for_near_edges(x, v, p, [&](const Eigen::Vector2d& q, const Eigen::Vector2d& a,
                                    const Eigen::Vector2d& b) {
            if (!clear)
                return;
            // No crossing, nor a gap narrowed under the clearance.
            const double gap = segment_distance(p, q, a, b);
            clear = gap >= clearance_ || (gap > 0.0 && gap >= segment_distance(from, q, a, b));
        });
        return clear;
    }

    //! The clearance of the last rebuild(): a hundredth of the map's mean boundary edge.
    double clearance() const { return clearance_; }
    //! The mean boundary edge of the map of the last rebuild().
    double mean_edge() const { return 0.5 * grid_.cell; }

    //! The boundary vertices at the ends of every two edges nearer each other than the clearance
    //! (sharing no vertex) in the map x of the last rebuild(), each vertex once.
    std::vector<int> near_contacts(const double* x) const { return near_pairs(x, clearance_); }

    //! As near_contacts(), for edges nearer each other than \p distance (at most the mean
    //! boundary edge: farther ones may be missed).
    std::vector<int> near_pairs(const double* x, double distance) const
    {
        std::vector<int> ends;
        const double reach = 1.01 * distance;  // as in for_near_edges()
        for (int e = 0; e < static_cast<int>(edges_.size()); ++e)
        {
            const Eigen::Vector2d a(x[2 * edges_[e][0]], x[2 * edges_[e][0] + 1]),
                b(x[2 * edges_[e][1]], x[2 * edges_[e][1] + 1]);
            const Box box = segment_box(x, edges_[e][0], edges_[e][1]);
            for_entries(box, distance, [&](int other) {
                const auto& f = edges_[other];
                if (other <= e || f[0] == edges_[e][0] || f[0] == edges_[e][1] ||
                    f[1] == edges_[e][0] || f[1] == edges_[e][1])
                    return;
                const Eigen::Vector2d c(x[2 * f[0]], x[2 * f[0] + 1]),
                    d(x[2 * f[1]], x[2 * f[1] + 1]);
                if (!boxes_within(box, c, d, reach))
                    return;
                if (segment_distance(a, b, c, d) < distance)
                    ends.insert(ends.end(), {edges_[e][0], edges_[e][1], f[0], f[1]});
            });
        }
        std::sort(ends.begin(), ends.end());
        ends.erase(std::unique(ends.begin(), ends.end()), ends.end());
        return ends;
    }

    //! The nearest any edge other than v's two comes to v's two edges with v at p (at most the
    //! clearance: nearer edges are not looked for).
    double gap(const double* x, int v, const Eigen::Vector2d& p) const
    {
        double nearest = clearance_;
        for_near_edges(x, v, p, [&](const Eigen::Vector2d& q, const Eigen::Vector2d& a,
                                    const Eigen::Vector2d& b) {
            nearest = std::min(nearest, segment_distance(p, q, a, b));
        });
        return nearest;
    }

private:
    struct Box
    {
        Eigen::Vector2d lo, hi;
    };

    // Whether segment ab's box comes within \p reach of \p box on both axes.
    static bool boxes_within(const Box& box, const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                             double reach)
    {
        return std::min(a.x(), b.x()) - box.hi.x() <= reach &&
               box.lo.x() - std::max(a.x(), b.x()) <= reach &&
               std::min(a.y(), b.y()) - box.hi.y() <= reach &&
               box.lo.y() - std::max(a.y(), b.y()) <= reach;
    }

    Box segment_box(const double* x, int a, int b) const
    {
        const Eigen::Vector2d p(x[2 * a], x[2 * a + 1]), q(x[2 * b], x[2 * b + 1]);
        return {p.cwiseMin(q), p.cwiseMax(q)};
    }

    // Calls visit(e) for each edge e entered in a cell that \p box grown by \p grow meets (an
    // edge may be visited more than once).
    template <class Visit>
    void for_entries(const Box& box, double grow, const Visit& visit) const
    {
        if (!cell_start_.empty())
        {
            grid_.for_cells(box.lo, box.hi, grow, [&](std::size_t c) {
                for (int i = cell_start_[c]; i < cell_start_[c + 1]; ++i)
                    visit(cell_edges_[static_cast<std::size_t>(i)]);
            });
            return;
        }
        grid_.for_cells(box.lo, box.hi, grow, [&](std::size_t c) {
            const long cell = static_cast<long>(c);
            auto it =
                std::lower_bound(entries_.begin(), entries_.end(), std::make_pair(cell, -1));
            for (; it != entries_.end() && it->first == cell; ++it)
                visit(it->second);
        });
    }

    // Calls visit(q, a, b) for each of v's two edges with v at p (q its other end) and each
    // edge ab that shares no vertex with it, is entered in a cell that the edge's box grown by
    // the clearance meets, and whose own box comes within the clearance of that box (an edge
    // may be visited more than once). The edges left out are farther than the clearance from
    // v's edge, as a segment is never nearer another than their boxes are; the callers ask only
    // of nearer ones. The boxes' gap is asked to exceed the clearance by a margin far above
    // rounding, so that no edge that segment_distance() puts within it is left out.
    template <class Visit>
    void for_near_edges(const double* x, int v, const Eigen::Vector2d& p, const Visit& visit) const
    {
        const double reach = 1.01 * clearance_;
        for (const int w : {prev_[v], next_[v]})
        {
            const Eigen::Vector2d q(x[2 * w], x[2 * w + 1]);
            const Eigen::Vector2d lo = p.cwiseMin(q), hi = p.cwiseMax(q);
            for_entries({lo, hi}, clearance_, [&](int other) {
                const auto& e = edges_[other];
                if (e[0] == v || e[1] == v || e[0] == w || e[1] == w)
                    return;
                const Eigen::Vector2d a(x[2 * e[0]], x[2 * e[0] + 1]),
                    b(x[2 * e[1]], x[2 * e[1] + 1]);
                if (!boxes_within({lo, hi}, a, b, reach))
                    return;
                visit(q, a, b);
            });
        }
    }

    std::vector<std::array<int, 2>> edges_;
    std::vector<int> next_, prev_;
    // The grid's per-cell runs are kept in an array over every cell while the cells number at
    // most kDenseCellsPerEntry per entry (plus kDenseCells): a boundary's cells, two mean edges
    // wide, number at most about (edges / 8)^2, so only a very long boundary falls back to the
    // sorted entries.
    static constexpr std::size_t kDenseCellsPerEntry = 16;
    static constexpr std::size_t kDenseCells = std::size_t{1} << 16;
    std::vector<std::pair<long, int>> entries_;  // (cell, edge) per entry
    std::vector<int> cell_start_;  // cell c's run: cell_edges_[start[c], start[c + 1])
    std::vector<int> cell_edges_;
    CellGrid grid_;
    double margin_ = 0.5, clearance_ = 0.0;
};

}  // namespace vessel::detail
