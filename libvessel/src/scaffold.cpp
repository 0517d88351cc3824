#include "detail/scaffold.h"

#include "vessel/errors.h"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <queue>

namespace vessel::detail {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using VertexBase = CGAL::Triangulation_vertex_base_with_info_2<int, Kernel>;
using FaceInfoBase = CGAL::Triangulation_face_base_with_info_2<int, Kernel>;  // nesting depth
using FaceBase = CGAL::Constrained_triangulation_face_base_2<Kernel, FaceInfoBase>;
using Tds = CGAL::Triangulation_data_structure_2<VertexBase, FaceBase>;
// Intersecting constraints are an error (a crossing boundary), not something to resolve.
using Cdt = CGAL::Constrained_Delaunay_triangulation_2<Kernel, Tds, CGAL::No_constraint_intersection_tag>;

// Depth of every finite face: 0 outside the box, 1 between the box and the map, 2 inside the
// map; found by a flood fill that steps one level deeper across each constrained edge.
void mark_depths(Cdt& cdt)
{
    for (auto f : cdt.all_face_handles())
        f->info() = -1;
    std::queue<std::pair<Cdt::Face_handle, int>> next_level;
    next_level.push({cdt.infinite_face(), 0});
    while (!next_level.empty())
    {
        auto [seed, depth] = next_level.front();
        next_level.pop();
        if (seed->info() != -1)
            continue;
        std::queue<Cdt::Face_handle> same;
        seed->info() = depth;
        same.push(seed);
        while (!same.empty())
        {
            auto f = same.front();
            same.pop();
            for (int i = 0; i < 3; ++i)
            {
                auto g = f->neighbor(i);
                if (g->info() != -1)
                    continue;
                if (cdt.is_constrained({f, i}))
                    next_level.push({g, depth + 1});
                else
                {
                    g->info() = depth;
                    same.push(g);
                }
            }
        }
    }
}

}  // namespace

std::vector<std::array<int, 3>> scaffold_triangles(const Eigen::VectorXd& x,
                                                   const std::vector<int>& boundary,
                                                   const std::array<int, 4>& box)
{
    Cdt cdt;
    const auto insert = [&](int v) {
        auto handle = cdt.insert(Kernel::Point_2(x[2 * v], x[2 * v + 1]));
        handle->info() = v;
        return handle;
    };
    try
    {
        std::vector<Cdt::Vertex_handle> ring;
        ring.reserve(boundary.size());
        for (int v : boundary)
            ring.push_back(insert(v));
        for (std::size_t i = 0; i < ring.size(); ++i)
            cdt.insert_constraint(ring[i], ring[(i + 1) % ring.size()]);
        std::array<Cdt::Vertex_handle, 4> corners;
        for (int i = 0; i < 4; ++i)
            corners[i] = insert(box[i]);
        for (int i = 0; i < 4; ++i)
            cdt.insert_constraint(corners[i], corners[(i + 1) % 4]);
    }
    catch (const std::exception&)
    {
        throw SolverError("scaffold: the map's boundary crosses itself; a scaffold needs a map "
                          "without overlaps to start from");
    }
    if (static_cast<std::size_t>(cdt.number_of_vertices()) != boundary.size() + 4)
        throw SolverError("scaffold: two boundary vertices of the map coincide");
    mark_depths(cdt);
    std::vector<std::array<int, 3>> triangles;
    for (auto f : cdt.finite_face_handles())
        if (f->info() == 1)  // CGAL's faces are counter-clockwise
            triangles.push_back({f->vertex(0)->info(), f->vertex(1)->info(), f->vertex(2)->info()});
    return triangles;
}

}  // namespace vessel::detail
