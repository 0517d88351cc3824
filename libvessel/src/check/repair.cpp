// CGAL is confined to this file: it is heavy to compile, and no CGAL type appears in a header.
// Hole fairing solves with Eigen's SparseLU, which CGAL offers only with this defined.
#ifndef CGAL_EIGEN3_ENABLED
#define CGAL_EIGEN3_ENABLED
#endif
#include "vessel/check/repair.h"

#include "vessel/core/errors.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/border.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/repair_degeneracies.h>
#include <CGAL/Polygon_mesh_processing/repair_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/stitch_borders.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/boost/graph/helpers.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <sstream>

namespace vessel {

namespace {

namespace PMP = CGAL::Polygon_mesh_processing;
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using SurfaceMesh = CGAL::Surface_mesh<Point>;
using Polygon = std::vector<std::size_t>;

// Counts what CGAL's soup orientation does.
struct OrientationCounter : PMP::Default_orientation_visitor
{
    std::size_t* reversed = nullptr;
    void polygon_orientation_reversed(std::size_t) { ++*reversed; }
};

std::string count_of(std::size_t n, const std::string& one, const std::string& many)
{
    return std::to_string(n) + " " + (n == 1 ? one : many);
}

bool is_readable(const RawMesh& raw)
{
    for (const auto& p : raw.points)
        if (!p.allFinite())
            return false;
    for (const auto& face : raw.faces)
        for (const int i : face)
            if (i < 0 || static_cast<std::size_t>(i) >= raw.points.size())
                return false;
    return true;
}

// Removes polygons with fewer than three distinct corners (CGAL's orientation needs proper
// polygons); returns how many.
std::size_t remove_repeated_corners(std::vector<Polygon>& polygons)
{
    const auto before = polygons.size();
    polygons.erase(std::remove_if(polygons.begin(), polygons.end(),
                                  [](Polygon p) {
                                      std::sort(p.begin(), p.end());
                                      return p.size() < 3 ||
                                             std::adjacent_find(p.begin(), p.end()) != p.end();
                                  }),
                   polygons.end());
    return before - polygons.size();
}

RawMesh to_raw(const SurfaceMesh& mesh)
{
    RawMesh raw;
    std::vector<int> index(mesh.number_of_vertices() + mesh.number_of_removed_vertices(), -1);
    for (auto v : mesh.vertices())
    {
        if (mesh.is_isolated(v))
            continue;
        index[v.idx()] = static_cast<int>(raw.points.size());
        const Point& p = mesh.point(v);
        raw.points.emplace_back(p.x(), p.y(), p.z());
    }
    for (auto f : mesh.faces())
    {
        auto& face = raw.faces.emplace_back();
        for (auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh))
            face.push_back(index[v.idx()]);
    }
    return raw;
}

// Fills the boundary loops of perimeter below \p below; counts into \p s.
void fill_holes(SurfaceMesh& mesh, double below, RepairSummary& s)
{
    using Halfedge = SurfaceMesh::Halfedge_index;
    std::vector<Halfedge> cycles;
    PMP::extract_boundary_cycles(mesh, std::back_inserter(cycles));
    // Perimeters first: filling one hole adds faces but leaves the other loops' halfedges.
    std::vector<Halfedge> holes;
    std::vector<double> perimeters;
    for (const Halfedge h : cycles)
    {
        double perimeter = 0.0;
        for (const Halfedge b : CGAL::halfedges_around_face(h, mesh))
            perimeter += std::sqrt(CGAL::to_double(
                CGAL::squared_distance(mesh.point(mesh.source(b)), mesh.point(mesh.target(b)))));
        if (perimeter < below)
        {
            holes.push_back(h);
            perimeters.push_back(perimeter);
        }
    }
    for (std::size_t i = 0; i < holes.size(); ++i)
    {
        std::vector<SurfaceMesh::Face_index> faces;
        std::vector<SurfaceMesh::Vertex_index> vertices;
        PMP::triangulate_refine_and_fair_hole(mesh, holes[i], std::back_inserter(faces),
                                              std::back_inserter(vertices));
        if (faces.empty())
        {
            ++s.unfilled_holes;
            continue;
        }
        ++s.filled_holes;
        s.longest_filled_hole = std::max(s.longest_filled_hole, perimeters[i]);
        s.hole_faces += faces.size();
        s.hole_vertices += vertices.size();
    }
}

}  // namespace

void RepairOptions::validate() const
{
    if (!std::isfinite(fill_holes_below) || fill_holes_below < 0.0)
        throw InvalidInputError("RepairOptions: fill_holes_below must be a perimeter of 0 or "
                                "more (mesh units), got " + std::to_string(fill_holes_below));
}

std::vector<std::string> RepairSummary::notes() const
{
    std::vector<std::string> out;
    if (degenerate_faces > 0)
        out.push_back("repair: removed " + count_of(degenerate_faces, "degenerate face", "degenerate faces"));
    if (duplicate_faces > 0)
        out.push_back("repair: removed " + count_of(duplicate_faces, "duplicate face", "duplicate faces"));
    if (reoriented_faces > 0)
        out.push_back("repair: reversed the winding of " +
                      count_of(reoriented_faces, "face", "faces") + " to agree with " +
                      (reoriented_faces == 1 ? "its" : "their") + " neighbours");
    if (split_vertices > 0)
        out.push_back("repair: split " + count_of(split_vertices, "non-manifold vertex", "non-manifold vertices"));
    if (stitched_edges > 0)
        out.push_back("repair: stitched " +
                      count_of(stitched_edges, "pair of coincident boundary edges",
                               "pairs of coincident boundary edges"));
    if (removed_vertices > 0)
        out.push_back("repair: removed " +
                      count_of(removed_vertices, "vertex", "vertices") +
                      " (merged by stitching or no longer used)");
    if (filled_holes > 0)
    {
        std::ostringstream longest;
        longest.precision(3);
        longest << longest_filled_hole;
        out.push_back("repair: filled " + count_of(filled_holes, "hole", "holes") +
                      " (perimeter up to " + longest.str() + ") with " +
                      count_of(hole_faces, "face", "faces") + " and " +
                      count_of(hole_vertices, "new vertex", "new vertices"));
    }
    if (unfilled_holes > 0)
        out.push_back("repair: could not fill " + count_of(unfilled_holes, "hole", "holes") +
                      " (CGAL found no triangulation)");
    return out;
}

RepairedMesh repair_raw_mesh(const RawMesh& raw, const RepairOptions& options)
{
    options.validate();
    RepairedMesh out;
    if (!is_readable(raw))
    {
        out.mesh = raw;
        return out;
    }
    std::vector<Point> points;
    points.reserve(raw.points.size());
    for (const auto& p : raw.points)
        points.emplace_back(p.x(), p.y(), p.z());
    std::vector<Polygon> polygons;
    polygons.reserve(raw.faces.size());
    for (const auto& face : raw.faces)
        polygons.emplace_back(face.begin(), face.end());

    RepairSummary& s = out.summary;
    if (options.remove_degenerate_faces)
        s.degenerate_faces += remove_repeated_corners(polygons);
    if (options.remove_duplicate_faces)
        s.duplicate_faces = PMP::merge_duplicate_polygons_in_polygon_soup(
            points, polygons, PMP::parameters::require_same_orientation(false));
    const std::size_t input_points = points.size();
    if (options.orient)
    {
        OrientationCounter counter;
        counter.reversed = &s.reoriented_faces;
        PMP::orient_polygon_soup(points, polygons, PMP::parameters::visitor(counter));
        s.split_vertices = points.size() - input_points;
    }
    if (!PMP::is_polygon_soup_a_polygon_mesh(polygons))
    {
        // Still not a mesh CGAL can build (e.g. orientation was not requested): stop here and
        // let the validation name the defect.
        out.mesh.points.reserve(points.size());
        for (const auto& p : points)
            out.mesh.points.emplace_back(p.x(), p.y(), p.z());
        for (const auto& polygon : polygons)
            out.mesh.faces.emplace_back(polygon.begin(), polygon.end());
        return out;
    }
    SurfaceMesh mesh;
    PMP::polygon_soup_to_polygon_mesh(points, polygons, mesh);
    if (options.stitch_borders)
        s.stitched_edges = PMP::stitch_borders(mesh);
    if (options.remove_degenerate_faces && CGAL::is_triangle_mesh(mesh))
    {
        const std::size_t faces = mesh.number_of_faces();
        PMP::remove_degenerate_faces(mesh);
        s.degenerate_faces += faces - mesh.number_of_faces();
    }
    if (options.fill_holes_below > 0.0 && CGAL::is_triangle_mesh(mesh))
    {
        mesh.set_recycle_garbage(false);  // new vertices after the others, not in freed slots
        fill_holes(mesh, options.fill_holes_below, s);
    }
    out.mesh = to_raw(mesh);
    s.removed_vertices = points.size() + s.hole_vertices - out.mesh.points.size();
    return out;
}

}  // namespace vessel
