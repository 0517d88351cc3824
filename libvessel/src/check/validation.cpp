#include "vessel/check/validation.h"

#include "detail/edge_groups.h"
#include "detail/flat_caps.h"
#include "detail/orient.h"
#include "detail/union_find.h"
#include "vessel/core/errors.h"
#include "vessel/core/properties.h"
#include "vessel/cut/boundary.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <sstream>

namespace vessel {

namespace {

using Triangle = std::array<int, 3>;

using detail::UnionFind;

[[noreturn]] void refuse(const std::string& what)
{
    throw InvalidInputError("not a valid vessel tree surface: " + what);
}

std::string plural(std::size_t n, const std::string& word)
{
    if (n == 1)
        return "1 " + word;
    const std::string vertex = "vertex";
    if (word.size() >= vertex.size() && word.compare(word.size() - vertex.size(), vertex.size(), vertex) == 0)
        return std::to_string(n) + " " + word.substr(0, word.size() - vertex.size()) + "vertices";
    return std::to_string(n) + " " + word + "s";
}

struct Triangulated
{
    std::vector<Triangle> triangles;
    std::vector<int> source_face;  // input face of each triangle
    std::size_t polygons = 0;
};

Triangulated triangulate(const RawMesh& raw, const TreeSurfaceOptions& options)
{
    Triangulated out;
    out.triangles.reserve(raw.faces.size());
    const int n = static_cast<int>(raw.points.size());
    for (std::size_t f = 0; f < raw.faces.size(); ++f)
    {
        const auto& face = raw.faces[f];
        if (face.size() < 3)
            refuse("face " + std::to_string(f) + " has only " + plural(face.size(), "corner") +
                   "; remove it");
        for (std::size_t i = 0; i < face.size(); ++i)
        {
            if (face[i] < 0 || face[i] >= n)
                refuse("face " + std::to_string(f) + " refers to vertex " +
                       std::to_string(face[i]) + " but the file has " + plural(n, "vertex") +
                       "; the file is corrupt");
            for (std::size_t j = i + 1; j < face.size(); ++j)
                if (face[i] == face[j])
                    refuse("face " + std::to_string(f) + " uses vertex " +
                           std::to_string(face[i]) +
                           " twice (degenerate face); remove degenerate faces first");
        }
        if (face.size() > 3)
        {
            if (!options.triangulate_polygons)
                refuse("face " + std::to_string(f) + " has " + plural(face.size(), "corner") +
                       "; triangulate the surface first (or allow vessel-flatten to do it: drop "
                       "--refuse-polygons)");
            ++out.polygons;
        }
        for (std::size_t i = 1; i + 1 < face.size(); ++i)
        {
            out.triangles.push_back({face[0], face[i], face[i + 1]});
            out.source_face.push_back(static_cast<int>(f));
        }
    }
    return out;
}

void check_coordinates(const RawMesh& raw)
{
    for (std::size_t i = 0; i < raw.points.size(); ++i)
        if (!raw.points[i].allFinite())
            refuse("vertex " + std::to_string(i) +
                   " has a NaN or infinite coordinate (in a binary PLY also a double beyond "
                   "float's 3.4e38, which OpenMesh reads as infinite); fix or remove it in the "
                   "source");
}

void check_degenerate(const RawMesh& raw, const Triangulated& tri,
                      const TreeSurfaceOptions& options)
{
    double edge_sum = 0.0;
    for (const auto& t : tri.triangles)
        for (int k = 0; k < 3; ++k)
            edge_sum += (raw.points[t[k]] - raw.points[t[(k + 1) % 3]]).norm();
    const double h = edge_sum / (3.0 * static_cast<double>(tri.triangles.size()));
    const double min_area = options.degenerate_area_factor * h * h;
    std::size_t count = 0;
    std::size_t first = 0;
    for (std::size_t i = 0; i < tri.triangles.size(); ++i)
    {
        const auto& t = tri.triangles[i];
        const double area = 0.5 * (raw.points[t[1]] - raw.points[t[0]])
                                       .cross(raw.points[t[2]] - raw.points[t[0]])
                                       .norm();
        if (area <= min_area && count++ == 0)
            first = i;
    }
    if (count > 0)
        refuse(plural(count, "degenerate (zero-area) face") + ", first is face " +
               std::to_string(tri.source_face[first]) +
               "; remove degenerate faces (vessel-flatten --repair, or MeshLab 'Remove Zero Area "
               "Faces')");
}

// "(x, y, z)" of a vertex, to locate a defect in a message.
std::string position(const Eigen::Vector3d& p)
{
    std::ostringstream out;
    out << "(" << p.x() << ", " << p.y() << ", " << p.z() << ")";
    return out.str();
}

// A number in a message, to 3 significant digits.
std::string number(double x)
{
    std::ostringstream out;
    out.precision(3);
    out << x;
    return out.str();
}

// A vertex far outside the rest of the surface (a corrupt coordinate such as 1e38) made every
// other face look degenerate beside its long edges, or overflowed the areas to infinity, and
// was reported as that; it is named instead. The scale is robust to a few such vertices: the
// median distance (largest coordinate difference, which cannot overflow) of the used vertices
// from their coordinate-wise median.
void check_far_vertices(const RawMesh& raw, const Triangulated& tri,
                        const TreeSurfaceOptions& options)
{
    if (options.far_vertex_factor <= 0.0)
        return;
    std::vector<char> used(raw.points.size(), 0);
    for (const auto& t : tri.triangles)
        for (const int v : t)
            used[v] = 1;
    std::vector<int> ids;
    for (std::size_t i = 0; i < used.size(); ++i)
        if (used[i])
            ids.push_back(static_cast<int>(i));
    const auto median = [](std::vector<double> values) {
        const auto middle = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
        std::nth_element(values.begin(), middle, values.end());
        return *middle;
    };
    Eigen::Vector3d centre;
    std::vector<double> values(ids.size());
    for (int k = 0; k < 3; ++k)
    {
        for (std::size_t i = 0; i < ids.size(); ++i)
            values[i] = raw.points[ids[i]][k];
        centre[k] = median(values);
    }
    for (std::size_t i = 0; i < ids.size(); ++i)
        values[i] = (raw.points[ids[i]] - centre).lpNorm<Eigen::Infinity>();
    const double typical = median(values);
    if (!(typical > 0.0))
        return;  // most vertices at one point: the zero-area check names the faces
    std::size_t count = 0;
    std::size_t farthest = 0;
    for (std::size_t i = 0; i < ids.size(); ++i)
        if (values[i] > options.far_vertex_factor * typical)
        {
            if (count++ == 0 || values[i] > values[farthest])
                farthest = i;
        }
    if (count == 0)
        return;
    const int v = ids[farthest];
    const std::string where = "vertex " + std::to_string(v) + " at " + position(raw.points[v]);
    const std::string scale = "(median " + number(typical) + " along an axis)";
    if (count == 1)
        refuse(where + " lies " + number(values[farthest] / typical) +
               " times as far from the middle of the surface as its vertices typically do " +
               scale + "; its coordinate looks corrupt: fix or remove it in the source");
    refuse(plural(count, "vertex") + " lie over " + number(options.far_vertex_factor) +
           " times as far from the middle of the surface as its vertices typically do " + scale +
           ", the farthest " + where + "; their coordinates look corrupt: fix them in the source");
}

// Two triangles with the same three vertices (in either winding) are duplicates; they would
// otherwise be reported as non-manifold edges, which hides the simple fix. Duplicates share the
// edge between their two smallest vertices, so each edge's triangles are compared there; the
// first reported is the copy with the smallest vertex triple. \p edges: the edge_groups() of
// tri.triangles as triangulated (not re-wound).
void check_duplicates(const Triangulated& tri, const detail::EdgeGroups& edges)
{
    std::size_t count = 0;
    int first = -1, original = -1;
    std::vector<std::pair<int, int>> third;  // (third vertex, triangle) of an edge's triangles
    for (std::size_t e = 0; e < edges.size(); ++e)
    {
        if (edges.count(e) < 2)
            continue;
        const int hi = edges.edge[e][1];
        third.clear();
        for (int i = 0; i < edges.count(e); ++i)
        {
            // Before any re-winding, corner c runs along the edge from corner c % 3: the
            // triangle's third vertex is the one after the edge.
            const int c = edges.begin(e)[i];
            const int other = tri.triangles[static_cast<std::size_t>(c / 3)][(c % 3 + 2) % 3];
            if (other > hi)  // the edge joins its two smallest vertices
                third.emplace_back(other, c / 3);
        }
        std::sort(third.begin(), third.end());
        for (std::size_t i = 1; i < third.size(); ++i)
            if (third[i].first == third[i - 1].first && count++ == 0)
            {
                original = third[i - 1].second;
                first = third[i].second;
            }
    }
    if (count > 0)
        refuse(plural(count, "duplicate face") + " (same three vertices as another face), first is "
               "face " + std::to_string(tri.source_face[first]) + " (a copy of face " +
               std::to_string(tri.source_face[original]) +
               "); remove them (vessel-flatten --repair, or MeshLab 'Remove Duplicate Faces')");
}

// Boundary vertices at exactly the same position as another boundary vertex: the surface was
// split along a seam (e.g. vmtk's branch clipper) and its pieces only touch there.
void check_coincident_borders(const RawMesh& raw, std::vector<int> border)
{
    std::sort(border.begin(), border.end());
    border.erase(std::unique(border.begin(), border.end()), border.end());
    const auto& P = raw.points;
    std::sort(border.begin(), border.end(), [&](int a, int b) {
        return std::lexicographical_compare(P[a].data(), P[a].data() + 3, P[b].data(),
                                            P[b].data() + 3);
    });
    std::size_t count = 0;
    int first_a = -1, first_b = -1;
    for (std::size_t i = 0; i < border.size();)
    {
        std::size_t j = i + 1;
        while (j < border.size() && P[border[j]] == P[border[i]])
            ++j;
        if (j - i > 1)
        {
            // Report the group with the lowest vertex index, by its two lowest indices.
            std::vector<int> group(border.begin() + i, border.begin() + j);
            std::sort(group.begin(), group.end());
            if (count == 0 || group[0] < first_a)
                first_a = group[0], first_b = group[1];
            count += j - i;
        }
        i = j;
    }
    if (count == 0)
        return;
    refuse("coincident boundary loops: " + plural(count, "boundary vertex") +
           " lie exactly on other boundary vertices (first: vertices " + std::to_string(first_a) +
           " and " + std::to_string(first_b) + " at " + position(P[first_a]) +
           "), so pieces of the surface only touch along a seam; stitch them (vessel-flatten "
           "--repair; where holes in the wall touch at a vertex, which --repair splits, fill "
           "them too: --repair --fill-holes MAX_PERIMETER)");
}

// Checks edges and vertices for 2-manifoldness and consistent orientation and that no boundary
// loops coincide; returns the edge-connected component of every triangle (a union-find root).
// \p edges: the edge_groups() of tri.triangles.
std::vector<int> check_manifold(const RawMesh& raw, const Triangulated& tri,
                                const detail::EdgeGroups& edges)
{
    const auto& T = tri.triangles;
    const std::size_t n = raw.points.size();
    // Triangle c / 3's corner that starts edge e, which runs from it to the next corner; and
    // whether it runs from the smaller vertex to the larger. (The corner's own c % 3 is the
    // edge's before the triangles were re-wound.)
    struct Run
    {
        int triangle;
        int local;
        bool forward;
    };
    const auto run = [&](std::size_t e, int i) {
        const int t = edges.begin(e)[i] / 3;
        const auto& tri_t = T[static_cast<std::size_t>(t)];
        const auto [lo, hi] = edges.edge[e];
        for (int k = 0; k < 3; ++k)
        {
            const int from = tri_t[k], to = tri_t[(k + 1) % 3];
            if ((from == lo && to == hi) || (from == hi && to == lo))
                return Run{t, k, from == lo};
        }
        return Run{t, -1, false};  // unreachable: the group holds the triangle's edge
    };
    // The name of edge e, for messages (made only when refusing).
    const auto edge_name = [&](std::size_t e) {
        return "(" + std::to_string(edges.edge[e][0]) + ", " + std::to_string(edges.edge[e][1]) +
               ")";
    };
    // Faces per edge first: an edge with three faces also looks mis-oriented, and the
    // non-manifold edge is the defect to report.
    for (std::size_t e = 0; e < edges.size(); ++e)
        if (edges.count(e) > 2)
            refuse("non-manifold edge " + edge_name(e) + " (from " +
                   position(raw.points[edges.edge[e][0]]) + " to " +
                   position(raw.points[edges.edge[e][1]]) + ") is shared by " +
                   plural(edges.count(e), "face") + " (faces " +
                   std::to_string(tri.source_face[edges.begin(e)[0] / 3]) + ", " +
                   std::to_string(tri.source_face[edges.begin(e)[1] / 3]) + ", " +
                   std::to_string(tri.source_face[edges.begin(e)[2] / 3]) +
                   "); repair the surface so each edge has at most two faces");

    UnionFind faces(T.size());
    UnionFind fans(3 * T.size());  // corner (t, k) = 3t + k; unions across interior edges
    std::vector<int> border;       // the vertices of edges with one face
    for (std::size_t e = 0; e < edges.size(); ++e)
    {
        if (edges.count(e) == 1)
            border.insert(border.end(), edges.edge[e].begin(), edges.edge[e].end());
        if (edges.count(e) != 2)
            continue;
        const Run c0 = run(e, 0);
        const Run c1 = run(e, 1);
        if (c0.forward == c1.forward)
            refuse("inconsistent orientation: faces " +
                   std::to_string(tri.source_face[c0.triangle]) + " and " +
                   std::to_string(tri.source_face[c1.triangle]) + " run the same way along edge " +
                   edge_name(e) +
                   "; orient the faces consistently (e.g. MeshLab 'Re-Orient all faces "
                   "coherently')");
        faces.unite(c0.triangle, c1.triangle);
        // Opposite runs: corner `local` of c0 and corner `local + 1` of c1 are the same vertex.
        fans.unite(3 * c0.triangle + c0.local, 3 * c1.triangle + (c1.local + 1) % 3);
        fans.unite(3 * c0.triangle + (c0.local + 1) % 3, 3 * c1.triangle + c1.local);
    }
    std::sort(border.begin(), border.end());

    std::vector<int> first_fan(n, -1);
    for (std::size_t t = 0; t < T.size(); ++t)
        for (int k = 0; k < 3; ++k)
        {
            const int root = fans.find(static_cast<int>(3 * t + k));
            int& seen = first_fan[T[t][k]];
            if (seen < 0)
                seen = root;
            else if (seen != root)
            {
                // Open fans meeting at a vertex are most often holes in the wall that touch
                // (missing triangles side by side): --repair splits the vertex, then the holes
                // can be filled.
                const int v = T[t][k];
                const bool open = std::binary_search(border.begin(), border.end(), v);
                refuse("non-manifold vertex " + std::to_string(v) + " at " +
                       position(raw.points[v]) +
                       ": its faces form several fans that touch only at this vertex; split or "
                       "remove the pinched part" +
                       (open ? std::string(" (where holes in the wall touch, as here on the "
                                           "boundary, vessel-flatten --repair --fill-holes "
                                           "MAX_PERIMETER splits the vertex and fills them)")
                             : std::string()));
            }
        }
    check_coincident_borders(raw, std::move(border));

    std::vector<int> component(T.size());
    for (std::size_t t = 0; t < T.size(); ++t)
        component[t] = faces.find(static_cast<int>(t));
    return component;
}

// Refuses several components or, with `keep_largest_component`, keeps the largest (noted).
void select_component(Triangulated& tri, const std::vector<int>& component,
                      const TreeSurfaceOptions& options, std::vector<std::string>& notes)
{
    std::vector<std::size_t> size(component.size(), 0);
    std::vector<std::size_t> sizes;
    for (const int root : component)
        ++size[root];
    for (const std::size_t n : size)
        if (n > 0)
            sizes.push_back(n);
    if (sizes.size() < 2)
        return;
    std::sort(sizes.rbegin(), sizes.rend());
    std::ostringstream list;
    for (std::size_t i = 0; i < std::min<std::size_t>(sizes.size(), 4); ++i)
        list << (i ? ", " : "") << sizes[i];
    if (sizes.size() > 4)
        list << ", ...";
    if (!options.keep_largest_component)
        refuse(plural(sizes.size(), "connected component") + " (faces per component: " +
               list.str() + "); keep only the vessel surface (one piece), e.g. with "
               "vessel-flatten --largest-component");
    const int largest = static_cast<int>(std::max_element(size.begin(), size.end()) - size.begin());
    Triangulated kept;
    kept.polygons = tri.polygons;
    for (std::size_t t = 0; t < component.size(); ++t)
        if (component[t] == largest)
        {
            kept.triangles.push_back(tri.triangles[t]);
            kept.source_face.push_back(tri.source_face[t]);
        }
    notes.push_back("kept the largest of " + plural(sizes.size(), "connected component") +
                    " (faces per component: " + list.str() + "); dropped " +
                    plural(tri.triangles.size() - kept.triangles.size(), "face"));
    tri = std::move(kept);
}

Mesh build(const RawMesh& raw, const Triangulated& tri, bool reverse)
{
    const auto& T = tri.triangles;
    Mesh mesh;
    auto input_index = OpenMesh::VProp<int>(mesh, prop::input_index);
    auto input_face = OpenMesh::FProp<int>(mesh, prop::input_face);
    std::vector<int> handle(raw.points.size(), -1);
    for (const auto& t : T)
        for (int k = 0; k < 3; ++k)
            if (handle[t[k]] < 0)
            {
                auto v = mesh.add_vertex(to_openmesh(raw.points[t[k]]));
                handle[t[k]] = v.idx();
                input_index[v] = t[k];
            }
    mesh.reserve(mesh.n_vertices(), 3 * T.size() / 2, T.size());
    for (std::size_t i = 0; i < T.size(); ++i)
    {
        const auto& t = T[i];
        VertexHandle a(handle[t[0]]), b(handle[t[1]]), c(handle[t[2]]);
        if (reverse)
            std::swap(b, c);
        const auto f = mesh.add_face(a, b, c);
        if (!f.is_valid())
            throw TopologyError("make_tree_surface: OpenMesh refused a face that passed the "
                                "manifold checks; please report this mesh");
        input_face[f] = tri.source_face[i];
    }
    return mesh;
}

// Volume enclosed after closing every boundary loop with a fan around its centroid; positive
// when the faces are wound so that normals point out of the lumen.
double closed_volume(const Mesh& mesh, const std::vector<BoundaryLoop>& loops)
{
    double six_volume = 0.0;
    for (auto f : mesh.faces())
    {
        auto h = f.halfedge();
        six_volume += to_eigen(mesh.point(h.from()))
                          .dot(to_eigen(mesh.point(h.to())).cross(to_eigen(mesh.point(h.next().to()))));
    }
    for (const auto& loop : loops)
        for (auto h : loop.halfedges)
            six_volume += to_eigen(mesh.point(mesh.from_vertex_handle(h)))
                              .dot(to_eigen(mesh.point(mesh.to_vertex_handle(h))).cross(loop.centroid));
    return six_volume / 6.0;
}

// Boundary loops of a few edges, much shorter than the largest loop, are holes in the wall (a
// missing triangle or two), not vessel ends: the pipeline would cut to each as an outlet, at a
// cost that grows with the number of holes and with a map whose area distortion grows with it
// too (docs/bad-input.md). The message suggests a --fill-holes perimeter above every hole's
// and, where possible, below every vessel end's.
void check_holes(const std::vector<BoundaryLoop>& loops, const TreeSurfaceOptions& options)
{
    if (options.hole_max_edges <= 0 || loops.size() < 2)
        return;
    const double largest = loops.front().arc_length;  // loops are sorted longest first
    std::vector<const BoundaryLoop*> holes;
    double shortest_end = largest;
    for (const auto& loop : loops)
    {
        if (static_cast<int>(loop.halfedges.size()) <= options.hole_max_edges &&
            loop.arc_length < options.hole_perimeter_fraction * largest)
            holes.push_back(&loop);
        else
            shortest_end = std::min(shortest_end, loop.arc_length);
    }
    if (holes.empty())
        return;
    const double longest_hole = holes.front()->arc_length;
    // 1.2 times the longest hole, rounded up to two significant digits, unless that reaches a
    // vessel end; then halfway between.
    const double step = std::pow(10.0, std::floor(std::log10(1.2 * longest_hole)) - 1.0);
    double fill = std::ceil(1.2 * longest_hole / step) * step;
    if (fill >= shortest_end)
        fill = 0.5 * (longest_hole + shortest_end);
    std::ostringstream perimeters;
    perimeters << "perimeter " << number(holes.back()->arc_length);
    if (number(longest_hole) != number(holes.back()->arc_length))
        perimeters << " to " << number(longest_hole);
    refuse(plural(holes.size(), "boundary loop") + " of at most " +
           plural(static_cast<std::size_t>(options.hole_max_edges), "edge") + " and under " +
           number(options.hole_perimeter_fraction) + " times the largest loop's perimeter (" +
           number(largest) + ") look like holes in the wall, not vessel ends (" +
           perimeters.str() + (holes.size() > 1 ? ", the longest" : "") + " around " +
           position(holes.front()->centroid) + "); fill them (vessel-flatten --fill-holes " +
           number(fill) + ", CGAL hole filling of the loops shorter than that) or in the source");
}

// The flat caps' faces dropped from \p tri (TreeSurfaceOptions::remove_flat_caps), noted; the
// caps as detail/flat_caps.h's criteria find them.
void remove_flat_caps(const RawMesh& raw, Triangulated& tri, TreeSurface& out)
{
    std::vector<detail::FlatCap> caps = detail::find_flat_caps(
        raw.points, tri.triangles, detail::kFlatCapCoplanarDeg, detail::kFlatCapMinRimDeg,
        detail::kFlatCapMeanRimDeg, detail::kFlatCapMinRimEdges);
    if (caps.empty())
        return;
    std::vector<char> drop(tri.triangles.size(), 0);
    std::size_t faces = 0;
    for (const auto& cap : caps)
        for (const int t : cap.triangles)
        {
            drop[t] = 1;
            ++faces;
        }
    Triangulated kept;
    kept.polygons = tri.polygons;
    for (std::size_t t = 0; t < tri.triangles.size(); ++t)
        if (!drop[t])
        {
            kept.triangles.push_back(tri.triangles[t]);
            kept.source_face.push_back(tri.source_face[t]);
        }
    tri = std::move(kept);
    std::sort(caps.begin(), caps.end(),
              [](const auto& a, const auto& b) { return a.area > b.area; });
    std::string areas;
    for (std::size_t i = 0; i < caps.size(); ++i)
        areas += (i == 0 ? "" : i + 1 == caps.size() ? " and " : ", ") + number(caps[i].area);
    out.removed_caps = static_cast<int>(caps.size());
    out.notes.push_back("removed " + plural(caps.size(), "flat cap") + " (" +
                        plural(faces, "face") + "; area" + (caps.size() > 1 ? "s " : " ") + areas +
                        (caps.size() > 1 ? ", largest first" : "") + ")");
}

// Winds all faces alike (issue 6: inconsistent orientation is fixed with a warning); refuses a
// surface that cannot be (a Moebius strip).
void orient(Triangulated& tri, const detail::EdgeGroups& edges, TreeSurface& out)
{
    const detail::Orientation o = detail::orient_consistently(tri.triangles, edges);
    if (o.conflict_a >= 0)
        refuse("the surface is not orientable (like a Moebius strip): faces " +
               std::to_string(tri.source_face[o.conflict_a]) + " and " +
               std::to_string(tri.source_face[o.conflict_b]) +
               " cannot both be wound to agree with their neighbours, so no side of the wall is "
               "outside; check the segmentation for a twisted or self-glued piece");
    if (o.reversed == 0)
        return;
    out.reoriented_faces = o.reversed;
    out.notes.push_back("re-oriented " + plural(static_cast<std::size_t>(o.reversed), "face") +
                        " to agree with their neighbours");
}

}  // namespace

TreeSurface make_tree_surface(const RawMesh& raw, const TreeSurfaceOptions& options)
{
    if (raw.faces.empty())
        refuse("the mesh has no faces; expected a triangulated vessel wall");
    check_coordinates(raw);
    Triangulated tri = triangulate(raw, options);
    check_far_vertices(raw, tri, options);
    check_degenerate(raw, tri, options);
    const detail::EdgeGroups edges = detail::edge_groups(tri.triangles, raw.points.size());
    check_duplicates(tri, edges);
    TreeSurface out;
    if (options.orient_consistently)
        orient(tri, edges, out);
    select_component(tri, check_manifold(raw, tri, edges), options, out.notes);
    if (options.remove_flat_caps)
        remove_flat_caps(raw, tri, out);

    out.input_vertices = static_cast<int>(raw.points.size());
    out.mesh = build(raw, tri, false);
    const auto loops = boundary_loops(out.mesh);
    if (loops.empty())
        refuse(options.remove_flat_caps
                   ? "the surface is closed (no open ends) and has no flat cap to remove (a "
                     "planar patch meeting the wall at a sharp rim); open each vessel end in "
                     "the source, e.g. by clipping it with vmtksurfaceclipper"
                   : "the surface is closed (no open ends); remove the caps at the inlet and "
                     "outlets so each vessel end is an open boundary loop (flat caps: "
                     "vessel-flatten --remove-caps)");
    const long chi = static_cast<long>(out.mesh.n_vertices()) -
                     static_cast<long>(out.mesh.n_edges()) +
                     static_cast<long>(out.mesh.n_faces());
    const long genus = (2 - chi - static_cast<long>(loops.size())) / 2;
    if (genus > 0)
        refuse("genus " + std::to_string(genus) + " (Euler characteristic " +
               std::to_string(chi) + " with " + plural(loops.size(), "boundary loop") +
               "): the surface has handles (e.g. touching branches fused together); remove them");
    check_holes(loops, options);

    if (tri.polygons > 0)
        out.notes.push_back("triangulated " + plural(tri.polygons, "polygon") +
                            " with more than 3 corners");
    const std::size_t unused = raw.points.size() - out.mesh.n_vertices();
    if (unused > 0)
        out.notes.push_back("ignored " + plural(unused, "vertex") + " not used by any face");
    if (options.orient_outward && closed_volume(out.mesh, loops) < 0.0)
    {
        out.mesh = build(raw, tri, true);
        out.notes.push_back("the surface was wound inward (normals into the lumen); reversed the "
                            "winding of all faces");
    }
    return out;
}

TreeSurface load_tree_surface(const std::string& path, const TreeSurfaceOptions& options)
{
    return make_tree_surface(read_raw_mesh(path), options);
}

}  // namespace vessel
