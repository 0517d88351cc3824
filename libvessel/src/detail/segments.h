#pragma once
// Predicates on plane segments shared by the map's overlap tests.

#include <Eigen/Core>

#include <algorithm>

namespace vessel::detail {

//! Twice the signed area of the triangle (p, q, r): > 0 when counter-clockwise.
inline double orient(const Eigen::Vector2d& p, const Eigen::Vector2d& q, const Eigen::Vector2d& r)
{
    return (q.x() - p.x()) * (r.y() - p.y()) - (q.y() - p.y()) * (r.x() - p.x());
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

}  // namespace vessel::detail
