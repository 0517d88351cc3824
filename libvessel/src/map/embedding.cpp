#include "vessel/map/embedding.h"

#include "detail/segments.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>
#include <vector>

namespace vessel {

namespace {

struct Segment
{
    Eigen::Vector2d a, b;
    int from = -1, to = -1;  // vertex indices
    int halfedge = -1;
};

// Closed segments intersect (touching counts).
bool intersect(const Segment& s, const Segment& t)
{
    return detail::segments_intersect(s.a, s.b, t.a, t.b);
}

}  // namespace

std::pair<int, int> boundary_self_intersection(const Mesh& mesh, const Eigen::MatrixX2d& uv)
{
    std::vector<Segment> segments;
    double total = 0.0;
    for (auto h : mesh.halfedges())
        if (h.is_boundary())
        {
            Segment s;
            s.from = h.from().idx();
            s.to = h.to().idx();
            s.a = uv.row(s.from).transpose();
            s.b = uv.row(s.to).transpose();
            s.halfedge = h.idx();
            total += (s.b - s.a).norm();
            segments.push_back(s);
        }
    if (segments.size() < 4)
        return {-1, -1};
    const double cell = std::max(2.0 * total / segments.size(), 1e-300);
    // Cell (i, j) -> one key; the shift is done unsigned (cells left of or below the origin
    // have negative indices, and shifting a negative signed value is undefined).
    const auto key = [](long long i, long long j) {
        return static_cast<long long>(static_cast<unsigned long long>(i) << 32 ^
                                      (static_cast<unsigned long long>(j) & 0xffffffffULL));
    };
    std::unordered_map<long long, std::vector<int>> grid;
    grid.reserve(2 * segments.size());
    for (std::size_t k = 0; k < segments.size(); ++k)
    {
        const Segment& s = segments[k];
        const long long i0 = std::floor(std::min(s.a.x(), s.b.x()) / cell);
        const long long i1 = std::floor(std::max(s.a.x(), s.b.x()) / cell);
        const long long j0 = std::floor(std::min(s.a.y(), s.b.y()) / cell);
        const long long j1 = std::floor(std::max(s.a.y(), s.b.y()) / cell);
        for (long long i = i0; i <= i1; ++i)
            for (long long j = j0; j <= j1; ++j)
            {
                auto& bucket = grid[key(i, j)];
                for (int other : bucket)
                {
                    const Segment& t = segments[other];
                    const bool adjacent =
                        s.from == t.to || s.to == t.from || s.from == t.from || s.to == t.to;
                    if (!adjacent && intersect(s, t))
                        return {t.halfedge, s.halfedge};
                }
                bucket.push_back(static_cast<int>(k));
            }
    }
    return {-1, -1};
}

}  // namespace vessel
