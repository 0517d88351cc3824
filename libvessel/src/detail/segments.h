#pragma once
// Plane predicates shared by the map's overlap tests, the coarse-grid interpolation and the
// map's arrow sampling: orientation, segment intersection, barycentric coordinates; and the
// search for meeting pairs among a boundary's segments.

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <unordered_map>
#include <utility>
#include <vector>

namespace vessel::detail {

//! Twice the signed area of the triangle (p, q, r): > 0 when counter-clockwise.
inline double orient(const Eigen::Vector2d& p, const Eigen::Vector2d& q, const Eigen::Vector2d& r)
{
    return (q.x() - p.x()) * (r.y() - p.y()) - (q.y() - p.y()) * (r.x() - p.x());
}

//! The barycentric coordinates \p w of p in the triangle (a, b, c) (w sums to 1; all >= 0
//! inside); false, \p w untouched, if the triangle is degenerate.
inline bool barycentric(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                        const Eigen::Vector2d& c, Eigen::Vector3d& w)
{
    const auto cross = [](const Eigen::Vector2d& x, const Eigen::Vector2d& y) {
        return x.x() * y.y() - x.y() * y.x();
    };
    const double area = cross(b - a, c - a);
    if (!(std::abs(area) > 0.0))
        return false;
    w[0] = cross(b - p, c - p) / area;
    w[1] = cross(c - p, a - p) / area;
    w[2] = 1.0 - w[0] - w[1];
    return true;
}

//! Whether r, known to lie on the line through p and q, lies within the segment's box.
inline bool on_segment(const Eigen::Vector2d& p, const Eigen::Vector2d& q, const Eigen::Vector2d& r)
{
    return std::min(p.x(), q.x()) <= r.x() && r.x() <= std::max(p.x(), q.x()) &&
           std::min(p.y(), q.y()) <= r.y() && r.y() <= std::max(p.y(), q.y());
}

//! Whether the closed segments ab and cd intersect (touching counts).
inline bool segments_intersect(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                               const Eigen::Vector2d& c, const Eigen::Vector2d& d)
{
    const double d1 = orient(c, d, a), d2 = orient(c, d, b);
    const double d3 = orient(a, b, c), d4 = orient(a, b, d);
    if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0)))
        return true;
    return (d1 == 0 && on_segment(c, d, a)) || (d2 == 0 && on_segment(c, d, b)) ||
           (d3 == 0 && on_segment(a, b, c)) || (d4 == 0 && on_segment(a, b, d));
}

//! Distance between the closed segments ab and cd (0 where they intersect).
inline double segment_distance(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                               const Eigen::Vector2d& c, const Eigen::Vector2d& d)
{
    if (segments_intersect(a, b, c, d))
        return 0.0;
    const auto to_segment = [](const Eigen::Vector2d& x, const Eigen::Vector2d& p,
                               const Eigen::Vector2d& q) {
        const Eigen::Vector2d pq = q - p;
        const double squared = pq.squaredNorm();
        const double t = squared > 0.0 ? std::clamp((x - p).dot(pq) / squared, 0.0, 1.0) : 0.0;
        return (x - p - t * pq).norm();
    };
    return std::min({to_segment(a, c, d), to_segment(b, c, d), to_segment(c, a, b),
                     to_segment(d, a, b)});
}

//! The first pair (l, k), l < k, of the segments [a[i], b[i]] for which meets(l, k) is true,
//! or {-1, -1}: near-linear, as only segments that share a cell of a uniform grid (cells two
//! mean segment lengths wide) are asked, k in increasing order, each k's cells i outer and j
//! inner, each cell's earlier segments in their order.
template <class Meets>
std::pair<int, int> first_meeting_segments(const std::vector<Eigen::Vector2d>& a,
                                           const std::vector<Eigen::Vector2d>& b,
                                           const Meets& meets)
{
    double total = 0.0;
    for (std::size_t k = 0; k < a.size(); ++k)
        total += (b[k] - a[k]).norm();
    const double cell = std::max(2.0 * total / static_cast<double>(a.size()), 1e-300);
    // Cell (i, j) -> one key; the shift is done unsigned (cells left of or below the origin
    // have negative indices, and shifting a negative signed value is undefined).
    const auto key = [](long long i, long long j) {
        return static_cast<long long>(static_cast<unsigned long long>(i) << 32 ^
                                      (static_cast<unsigned long long>(j) & 0xffffffffULL));
    };
    std::unordered_map<long long, std::vector<int>> grid;
    grid.reserve(2 * a.size());
    for (std::size_t k = 0; k < a.size(); ++k)
    {
        const long long i0 = std::floor(std::min(a[k].x(), b[k].x()) / cell);
        const long long i1 = std::floor(std::max(a[k].x(), b[k].x()) / cell);
        const long long j0 = std::floor(std::min(a[k].y(), b[k].y()) / cell);
        const long long j1 = std::floor(std::max(a[k].y(), b[k].y()) / cell);
        for (long long i = i0; i <= i1; ++i)
            for (long long j = j0; j <= j1; ++j)
            {
                std::vector<int>& bucket = grid[key(i, j)];
                for (int other : bucket)
                    if (meets(other, static_cast<int>(k)))
                        return {other, static_cast<int>(k)};
                bucket.push_back(static_cast<int>(k));
            }
    }
    return {-1, -1};
}

}  // namespace vessel::detail
