#include "detail/scaffold.h"

#include "vessel/core/errors.h"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Delaunay_mesh_face_base_2.h>
#include <CGAL/Delaunay_mesh_size_criteria_2.h>
#include <CGAL/Delaunay_mesher_no_edge_refinement_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <cstdlib>
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

int flip_to_delaunay(const Eigen::VectorXd& x, const std::vector<int>& boundary,
                     const std::array<int, 4>& box, std::vector<std::array<int, 3>>& triangles)
{
    const int vertices = static_cast<int>(x.size() / 2);
    const auto point = [&](int v) { return Kernel::Point_2(x[2 * v], x[2 * v + 1]); };
    // Each vertex's place on its ring (the boundary, or the box; -1 elsewhere): an edge is
    // constrained where its ends are neighbours on one ring.
    std::vector<int> place(static_cast<std::size_t>(vertices), -1);
    const int ring = static_cast<int>(boundary.size());
    for (int i = 0; i < ring; ++i)
        place[static_cast<std::size_t>(boundary[static_cast<std::size_t>(i)])] = i;
    for (int i = 0; i < 4; ++i)
        place[static_cast<std::size_t>(box[static_cast<std::size_t>(i)])] = ring + i;
    const auto constrained = [&](int a, int b) {
        const int pa = place[static_cast<std::size_t>(a)], pb = place[static_cast<std::size_t>(b)];
        if (pa < 0 || pb < 0 || (pa < ring) != (pb < ring))
            return false;
        const int size = pa < ring ? ring : 4;
        const int gap = std::abs(pa - pb);
        return gap == 1 || gap == size - 1;
    };
    // Half-edge h = 3 t + i runs from corner i of triangle t to corner i + 1; twin[h] is the
    // opposite half-edge of the neighbouring triangle, -1 where there is none. The twins are
    // found among the half-edges leaving each vertex (a counting sort by their start).
    const auto from = [&](int h) { return triangles[static_cast<std::size_t>(h / 3)][h % 3]; };
    const auto to = [&](int h) {
        return triangles[static_cast<std::size_t>(h / 3)][(h % 3 + 1) % 3];
    };
    const int half_edges = static_cast<int>(3 * triangles.size());
    std::vector<int> start(static_cast<std::size_t>(vertices) + 1, 0);
    for (int h = 0; h < half_edges; ++h)
        ++start[static_cast<std::size_t>(from(h)) + 1];
    for (int v = 0; v < vertices; ++v)
        start[static_cast<std::size_t>(v) + 1] += start[static_cast<std::size_t>(v)];
    std::vector<int> leaving(static_cast<std::size_t>(half_edges));
    {
        std::vector<int> next(start.begin(), start.end() - 1);
        for (int h = 0; h < half_edges; ++h)
            leaving[static_cast<std::size_t>(next[static_cast<std::size_t>(from(h))]++)] = h;
    }
    std::vector<int> twin(static_cast<std::size_t>(half_edges), -1);
    for (int h = 0; h < half_edges; ++h)
    {
        const int b = to(h), a = from(h);
        for (int k = start[static_cast<std::size_t>(b)]; k < start[static_cast<std::size_t>(b) + 1];
             ++k)
            if (const int g = leaving[static_cast<std::size_t>(k)]; to(g) == a)
                twin[static_cast<std::size_t>(h)] = g;
    }
    std::vector<int> stack;
    stack.reserve(static_cast<std::size_t>(half_edges));
    for (int h = 0; h < half_edges; ++h)
        if (twin[static_cast<std::size_t>(h)] > h)
            stack.push_back(h);
    const auto link = [&](int h, int g) {
        twin[static_cast<std::size_t>(h)] = g;
        if (g >= 0)
            twin[static_cast<std::size_t>(g)] = h;
    };
    int flips = 0;
    while (!stack.empty())
    {
        const int h = stack.back();
        stack.pop_back();
        const int g = twin[static_cast<std::size_t>(h)];
        const int a = from(h), b = to(h);
        if (g < 0 || constrained(a, b))
            continue;
        const int t1 = h / 3, t2 = g / 3, i = h % 3, j = g % 3;
        const int c = triangles[static_cast<std::size_t>(t1)][(i + 2) % 3];  // t1 = (a, b, c)
        const int d = triangles[static_cast<std::size_t>(t2)][(j + 2) % 3];  // t2 = (b, a, d)
        const Kernel::Point_2 pa = point(a), pb = point(b), pc = point(c), pd = point(d);
        if (CGAL::orientation(pa, pb, pc) != CGAL::LEFT_TURN ||
            CGAL::side_of_oriented_circle(pa, pb, pc, pd) != CGAL::ON_POSITIVE_SIDE ||
            CGAL::orientation(pa, pd, pc) != CGAL::LEFT_TURN ||
            CGAL::orientation(pd, pb, pc) != CGAL::LEFT_TURN)
            continue;
        // The quadrilateral a, d, b, c: diagonal c-d instead of a-b, as t1 = (a, d, c) and
        // t2 = (d, b, c).
        const int bc = twin[static_cast<std::size_t>(3 * t1 + (i + 1) % 3)];
        const int ca = twin[static_cast<std::size_t>(3 * t1 + (i + 2) % 3)];
        const int ad = twin[static_cast<std::size_t>(3 * t2 + (j + 1) % 3)];
        const int db = twin[static_cast<std::size_t>(3 * t2 + (j + 2) % 3)];
        triangles[static_cast<std::size_t>(t1)] = {a, d, c};
        triangles[static_cast<std::size_t>(t2)] = {d, b, c};
        link(3 * t1, ad);
        link(3 * t1 + 1, 3 * t2 + 2);
        link(3 * t1 + 2, ca);
        link(3 * t2, db);
        link(3 * t2 + 1, bc);
        for (int e : {3 * t1, 3 * t1 + 2, 3 * t2, 3 * t2 + 1})
            stack.push_back(e);
        ++flips;
    }
    return flips;
}

}  // namespace vessel::detail
