#include "vessel/map/embedding.h"

#include "detail/segments.h"

#include <vector>

namespace vessel {

std::pair<int, int> boundary_self_intersection(const Mesh& mesh, const Eigen::MatrixX2d& uv)
{
    std::vector<Eigen::Vector2d> a, b;  // the boundary edges' ends in the map
    std::vector<OpenMesh::SmartHalfedgeHandle> edges;
    for (auto h : mesh.halfedges())
        if (h.is_boundary())
        {
            a.push_back(uv.row(h.from().idx()).transpose());
            b.push_back(uv.row(h.to().idx()).transpose());
            edges.push_back(h);
        }
    if (edges.size() < 4)
        return {-1, -1};
    // Closed segments that meet (touching counts), but for neighbours along the boundary.
    const auto [l, k] = detail::first_meeting_segments(a, b, [&](int l, int k) {
        const int s0 = edges[k].from().idx(), s1 = edges[k].to().idx();
        const int t0 = edges[l].from().idx(), t1 = edges[l].to().idx();
        const bool adjacent = s0 == t1 || s1 == t0 || s0 == t0 || s1 == t1;
        return !adjacent && detail::segments_intersect(a[k], b[k], a[l], b[l]);
    });
    if (l < 0)
        return {-1, -1};
    return {edges[l].idx(), edges[k].idx()};
}

}  // namespace vessel
