#include "vessel/quality/overlap.h"

#include "vessel/core/errors.h"
#include "detail/segments.h"
#include "detail/uv_rows.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <algorithm>
#include <cmath>

namespace vessel {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_2;

// A triangle with its corners counter-clockwise as exact-predicate points; `empty` when the
// corners are collinear (no interior).
struct OrientedTriangle
{
    std::array<Point, 3> p;
    bool empty = false;
};

OrientedTriangle oriented(const Triangle2& t)
{
    OrientedTriangle o;
    for (int i = 0; i < 3; ++i)
        o.p[i] = Point(t[i].x(), t[i].y());
    const CGAL::Orientation turn = CGAL::orientation(o.p[0], o.p[1], o.p[2]);
    o.empty = turn == CGAL::COLLINEAR;
    if (turn == CGAL::RIGHT_TURN)
        std::swap(o.p[1], o.p[2]);
    return o;
}

// True when the line through one of a's edges has all of b on its outer closed side.
bool separated_by_edge_of(const OrientedTriangle& a, const OrientedTriangle& b)
{
    for (int i = 0; i < 3; ++i)
    {
        const Point& from = a.p[i];
        const Point& to = a.p[(i + 1) % 3];
        bool any_inside = false;
        // A shared corner is on the line; skipping it spares the exact fallback that the
        // filter needs for every zero determinant (neighbours share two corners).
        for (const Point& q : b.p)
            any_inside = any_inside || (q != from && q != to &&
                                        CGAL::orientation(from, to, q) == CGAL::LEFT_TURN);
        if (!any_inside)
            return true;
    }
    return false;
}

bool intersect(const OrientedTriangle& a, const OrientedTriangle& b)
{
    if (a.empty || b.empty)
        return false;
    return !separated_by_edge_of(a, b) && !separated_by_edge_of(b, a);
}

Triangle2 counter_clockwise(Triangle2 t)
{
    const Eigen::Vector2d e1 = t[1] - t[0], e2 = t[2] - t[0];
    if (e1.x() * e2.y() - e1.y() * e2.x() < 0.0)
        std::swap(t[1], t[2]);
    return t;
}

double polygon_area(const std::vector<Eigen::Vector2d>& poly)
{
    double twice = 0.0;
    for (std::size_t i = 0; i < poly.size(); ++i)
    {
        const auto& p = poly[i];
        const auto& q = poly[(i + 1) % poly.size()];
        twice += p.x() * q.y() - p.y() * q.x();
    }
    return 0.5 * std::abs(twice);
}

// Sutherland-Hodgman: clip a convex polygon by the left side of the line from `from` to `to`.
std::vector<Eigen::Vector2d> clip(const std::vector<Eigen::Vector2d>& poly,
                                  const Eigen::Vector2d& from, const Eigen::Vector2d& to)
{
    const Eigen::Vector2d d = to - from;
    const auto side = [&](const Eigen::Vector2d& p) {
        const Eigen::Vector2d r = p - from;
        return d.x() * r.y() - d.y() * r.x();
    };
    std::vector<Eigen::Vector2d> out;
    for (std::size_t i = 0; i < poly.size(); ++i)
    {
        const Eigen::Vector2d& p = poly[i];
        const Eigen::Vector2d& q = poly[(i + 1) % poly.size()];
        const double sp = side(p), sq = side(q);
        if (sp >= 0.0)
            out.push_back(p);
        if ((sp >= 0.0) != (sq >= 0.0))
            out.push_back(p + (sp / (sp - sq)) * (q - p));
    }
    return out;
}

struct Box
{
    Eigen::Vector2d lo, hi;
};

Box box_of(const Triangle2& t)
{
    Box b{t[0], t[0]};
    for (const auto& p : t)
    {
        b.lo = b.lo.cwiseMin(p);
        b.hi = b.hi.cwiseMax(p);
    }
    return b;
}

bool boxes_overlap(const Box& a, const Box& b)
{
    return a.lo.x() <= b.hi.x() && b.lo.x() <= a.hi.x() && a.lo.y() <= b.hi.y() &&
           b.lo.y() <= a.hi.y();
}

// Uniform grid over the triangles' bounding boxes; cell (i, j) has id j * nx + i.
class Grid
{
public:
    explicit Grid(const std::vector<Box>& boxes)
    {
        Box all = boxes.front();
        double size_sum = 0.0;
        for (const Box& b : boxes)
        {
            all.lo = all.lo.cwiseMin(b.lo);
            all.hi = all.hi.cwiseMax(b.hi);
            size_sum += (b.hi - b.lo).maxCoeff();
        }
        origin_ = all.lo;
        const Eigen::Vector2d extent = all.hi - all.lo;
        cell_ = std::max(size_sum / static_cast<double>(boxes.size()), 1e-12 * extent.maxCoeff());
        // Keep the cell count near the face count even for a map with a few huge faces.
        const double max_cells = 4.0 * static_cast<double>(boxes.size()) + 16.0;
        while ((extent.x() / cell_ + 1.0) * (extent.y() / cell_ + 1.0) > max_cells)
            cell_ *= 1.5;
        if (!(cell_ > 0.0))
            cell_ = 1.0;
        nx_ = static_cast<long>(extent.x() / cell_) + 1;
    }
    // Cell range [i0, i1] x [j0, j1] of a box.
    std::array<long, 4> range(const Box& b) const
    {
        const auto index = [&](double x, double o) {
            return static_cast<long>(std::floor((x - o) / cell_));
        };
        return {index(b.lo.x(), origin_.x()), index(b.hi.x(), origin_.x()),
                index(b.lo.y(), origin_.y()), index(b.hi.y(), origin_.y())};
    }
    long id(long i, long j) const { return j * nx_ + i; }

private:
    Eigen::Vector2d origin_;
    double cell_ = 1.0;
    long nx_ = 1;
};

// Whether the boundary of \p mesh is one loop through each of its vertices once, whose image
// in \p uv is a simple polygon: no two of its edges meet, decided exactly, except consecutive
// ones at their shared corner (and those not folded back along each other).
bool boundary_is_simple_loop(const Mesh& mesh, const Eigen::MatrixX2d& uv)
{
    std::vector<int> next(mesh.n_vertices(), -1);
    std::size_t edges = 0;
    int start = -1;
    for (auto h : mesh.halfedges())
        if (h.is_boundary())
        {
            if (next[h.from().idx()] >= 0)
                return false;  // a vertex twice on the boundary
            next[h.from().idx()] = h.to().idx();
            start = h.from().idx();
            ++edges;
        }
    if (edges < 3)
        return false;
    std::vector<int> loop;
    loop.reserve(edges);
    for (int v = start; loop.size() <= edges;)
    {
        loop.push_back(v);
        v = next[v];
        if (v < 0)
            return false;
        if (v == start)
            break;
    }
    if (loop.size() != edges)
        return false;  // more than one loop
    const auto point = [&](int v) { return Point(uv(v, 0), uv(v, 1)); };
    const std::size_t n = loop.size();
    std::vector<Eigen::Vector2d> a(n), b(n);  // edge k from loop[k] to the next
    for (std::size_t k = 0; k < n; ++k)
    {
        const Point before = point(loop[(k + n - 1) % n]), at = point(loop[k]),
                    after = point(loop[(k + 1) % n]);
        if (before == at || at == after)
            return false;
        // Consecutive edges folded back along each other share more than their corner.
        if (CGAL::orientation(before, at, after) == CGAL::COLLINEAR &&
            CGAL::angle(before, at, after) == CGAL::ACUTE)
            return false;
        a[k] = uv.row(loop[k]).transpose();
        b[k] = uv.row(loop[(k + 1) % n]).transpose();
    }
    const auto segment = [&](int k) {
        return Kernel::Segment_2(point(loop[k]), point(loop[(k + 1) % n]));
    };
    return detail::first_meeting_segments(a, b, [&](int l, int k) {
               const bool consecutive = (l + 1) % static_cast<int>(n) == k ||
                                        (k + 1) % static_cast<int>(n) == l;
               return !consecutive && CGAL::do_intersect(segment(l), segment(k));
           }).first < 0;
}

// Whether the map is one-to-one by a certificate instead of a test of every pair of faces:
// every face (\p triangles, one per face, corners in the mesh's order) turns the same way, none
// degenerate (exactly), and the boundary is a simple loop (boundary_is_simple_loop()). A point
// off the edges is then covered by as many faces as the boundary's image winds around it (the
// degree of a piecewise-linear map), 0 or 1 for a simple polygon, so no two faces' interiors
// meet (Lipman 2014, "Bijective mappings of meshes with boundary and the degree in mesh
// processing", SIAM J. Imaging Sciences 7(2)).
bool certified_one_to_one(const Mesh& mesh, const Eigen::MatrixX2d& uv,
                          const std::vector<Triangle2>& triangles)
{
    CGAL::Orientation turn = CGAL::COLLINEAR;
    for (const Triangle2& t : triangles)
    {
        const CGAL::Orientation o = CGAL::orientation(Point(t[0].x(), t[0].y()),
                                                      Point(t[1].x(), t[1].y()),
                                                      Point(t[2].x(), t[2].y()));
        if (o == CGAL::COLLINEAR || (turn != CGAL::COLLINEAR && o != turn))
            return false;
        turn = o;
    }
    return turn != CGAL::COLLINEAR && boundary_is_simple_loop(mesh, uv);
}

}  // namespace

bool interiors_intersect(const Triangle2& a, const Triangle2& b)
{
    return intersect(oriented(a), oriented(b));
}

double intersection_area(const Triangle2& a, const Triangle2& b)
{
    if (!interiors_intersect(a, b))
        return 0.0;
    const Triangle2 A = counter_clockwise(a), B = counter_clockwise(b);
    std::vector<Eigen::Vector2d> poly(A.begin(), A.end());
    for (int i = 0; i < 3 && !poly.empty(); ++i)
        poly = clip(poly, B[i], B[(i + 1) % 3]);
    return poly.size() < 3 ? 0.0 : polygon_area(poly);
}

namespace {

void require_finite_corners(const std::vector<Triangle2>& triangles)
{
    for (std::size_t f = 0; f < triangles.size(); ++f)
        for (const auto& p : triangles[f])
            if (!p.allFinite())
                throw InvalidInputError("find_overlaps: triangle " + std::to_string(f) +
                                        " has a non-finite corner; the map is broken");
}

double triangle_area(const Triangle2& t)
{
    const Eigen::Vector2d e1 = t[1] - t[0], e2 = t[2] - t[0];
    return 0.5 * std::abs(e1.x() * e2.y() - e1.y() * e2.x());
}

// find_overlaps() of triangles with finite corners: the grid search.
OverlapReport search_overlaps(const std::vector<Triangle2>& triangles)
{
    OverlapReport report;
    if (triangles.empty())
        return report;
    std::vector<Box> boxes;
    boxes.reserve(triangles.size());
    std::vector<OrientedTriangle> exact;
    exact.reserve(triangles.size());
    for (const Triangle2& t : triangles)
    {
        boxes.push_back(box_of(t));
        exact.push_back(oriented(t));
        report.map_area += triangle_area(t);
    }

    const Grid grid(boxes);
    std::vector<std::pair<long, int>> entries;  // (cell id, face)
    entries.reserve(2 * triangles.size());
    std::vector<std::array<long, 4>> ranges(triangles.size());
    for (std::size_t f = 0; f < triangles.size(); ++f)
    {
        ranges[f] = grid.range(boxes[f]);
        for (long j = ranges[f][2]; j <= ranges[f][3]; ++j)
            for (long i = ranges[f][0]; i <= ranges[f][1]; ++i)
                entries.emplace_back(grid.id(i, j), static_cast<int>(f));
    }
    std::sort(entries.begin(), entries.end());

    for (std::size_t begin = 0; begin < entries.size();)
    {
        std::size_t end = begin;
        while (end < entries.size() && entries[end].first == entries[begin].first)
            ++end;
        for (std::size_t x = begin; x < end; ++x)
            for (std::size_t y = x + 1; y < end; ++y)
            {
                const int f = entries[x].second, g = entries[y].second;
                if (!boxes_overlap(boxes[f], boxes[g]))
                    continue;
                // Decide each pair once: in the first cell (lowest j, then i) of the overlap of
                // their cell ranges.
                const auto& rf = ranges[f];
                const auto& rg = ranges[g];
                const long first = grid.id(std::max(rf[0], rg[0]), std::max(rf[2], rg[2]));
                if (first != entries[begin].first || !intersect(exact[f], exact[g]))
                    continue;
                report.pairs.emplace_back(std::min(f, g), std::max(f, g));
                report.overlap_area += intersection_area(triangles[f], triangles[g]);
            }
        begin = end;
    }
    std::sort(report.pairs.begin(), report.pairs.end());
    for (const auto& [f, g] : report.pairs)
    {
        report.triangles.push_back(f);
        report.triangles.push_back(g);
    }
    std::sort(report.triangles.begin(), report.triangles.end());
    report.triangles.erase(std::unique(report.triangles.begin(), report.triangles.end()),
                           report.triangles.end());
    report.overlap_fraction = report.map_area > 0.0 ? report.overlap_area / report.map_area : 0.0;
    return report;
}

}  // namespace

OverlapReport find_overlaps(const std::vector<Triangle2>& triangles)
{
    require_finite_corners(triangles);
    return search_overlaps(triangles);
}

OverlapReport find_overlaps(const Mesh& mesh, const Eigen::MatrixX2d& uv)
{
    detail::require_uv_rows(mesh, uv, "find_overlaps");
    std::vector<Triangle2> triangles;
    triangles.reserve(mesh.n_faces());
    for (auto f : mesh.faces())
    {
        Triangle2 t;
        int k = 0;
        for (auto v : f.vertices())
            t[k++] = uv.row(v.idx()).transpose();
        triangles.push_back(t);
    }
    require_finite_corners(triangles);
    if (!certified_one_to_one(mesh, uv, triangles))
        return search_overlaps(triangles);
    OverlapReport report;
    for (const Triangle2& t : triangles)
        report.map_area += triangle_area(t);
    return report;
}

}  // namespace vessel
