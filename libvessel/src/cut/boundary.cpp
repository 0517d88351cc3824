#include "vessel/cut/boundary.h"

#include <algorithm>

namespace vessel {

std::vector<BoundaryLoop> boundary_loops(const Mesh& mesh)
{
    std::vector<char> visited(mesh.n_halfedges(), 0);
    std::vector<BoundaryLoop> loops;
    for (auto start : mesh.halfedges())
    {
        if (!start.is_boundary() || visited[start.idx()])
            continue;
        BoundaryLoop loop;
        auto h = start;
        do
        {
            visited[h.idx()] = 1;
            loop.halfedges.push_back(h);
            loop.vertices.push_back(h.from());
            const Eigen::Vector3d a = to_eigen(mesh.point(h.from()));
            const Eigen::Vector3d b = to_eigen(mesh.point(h.to()));
            const double length = (b - a).norm();
            loop.arc_length += length;
            loop.centroid += 0.5 * length * (a + b);
            h = h.next();
        } while (h != start && loop.halfedges.size() <= mesh.n_halfedges());
        if (loop.arc_length > 0.0)
            loop.centroid /= loop.arc_length;
        loops.push_back(std::move(loop));
    }
    std::stable_sort(loops.begin(), loops.end(), [](const BoundaryLoop& a, const BoundaryLoop& b) {
        return a.arc_length > b.arc_length;
    });
    return loops;
}

}  // namespace vessel
