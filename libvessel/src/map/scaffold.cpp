#include "detail/scaffold.h"

#include "vessel/core/errors.h"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Delaunay_mesh_face_base_2.h>
#include <CGAL/Delaunay_mesh_size_criteria_2.h>
#include <CGAL/Delaunay_mesher_no_edge_refinement_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <queue>
#include <string>

namespace vessel::detail {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
// Vertex index into x; -1 for the vertices the mesher adds (Steiner points).
struct VertexId
{
    int id = -1;
};
using VertexBase = CGAL::Triangulation_vertex_base_with_info_2<VertexId, Kernel>;
using FaceInfoBase = CGAL::Triangulation_face_base_with_info_2<int, Kernel>;  // nesting depth
using FaceBase = CGAL::Delaunay_mesh_face_base_2<
    Kernel, CGAL::Constrained_triangulation_face_base_2<Kernel, FaceInfoBase>>;
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

ScaffoldMesh scaffold_triangles(const Eigen::VectorXd& x, const std::vector<int>& boundary,
                                const std::array<int, 4>& box, const Eigen::Vector2d& inside,
                                int first_steiner, double shape_bound)
{
    if (!(shape_bound > 0.0 && shape_bound <= kPolishScaffoldShape))
        throw InvalidInputError("scaffold: the shape bound must be in (0, 0.125], got " +
                                std::to_string(shape_bound));
    Cdt cdt;
    const auto insert = [&](int v) {
        auto handle = cdt.insert(Kernel::Point_2(x[2 * v], x[2 * v + 1]));
        handle->info().id = v;
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
    // Quality refinement of the free space only (the map's inside is excluded by a seed); the
    // boundary edges are never split, as they are the map's own edges.
    using Criteria = CGAL::Delaunay_mesh_size_criteria_2<Cdt>;
    CGAL::Delaunay_mesher_no_edge_refinement_2<Cdt, Criteria> mesher(cdt, Criteria(shape_bound));
    const std::array<Kernel::Point_2, 1> seeds = {Kernel::Point_2(inside.x(), inside.y())};
    mesher.set_seeds(seeds.begin(), seeds.end(), false);
    mesher.refine_mesh();
    mark_depths(cdt);
    ScaffoldMesh scaffold;
    const auto index = [&](Cdt::Vertex_handle v) {
        if (v->info().id < 0)
        {
            v->info().id = first_steiner + static_cast<int>(scaffold.steiner.size());
            scaffold.steiner.emplace_back(CGAL::to_double(v->point().x()),
                                          CGAL::to_double(v->point().y()));
        }
        return v->info().id;
    };
    for (auto f : cdt.finite_face_handles())
        if (f->info() == 1)  // CGAL's faces are counter-clockwise
            scaffold.triangles.push_back({index(f->vertex(0)), index(f->vertex(1)), index(f->vertex(2))});
    return scaffold;
}

}  // namespace vessel::detail
