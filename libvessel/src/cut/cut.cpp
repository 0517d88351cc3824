#include "vessel/cut/cut.h"

#include "vessel/core/errors.h"
#include "vessel/core/properties.h"

#include <algorithm>
#include <string>
#include <unordered_set>
#include <utility>

namespace vessel {

namespace {

[[noreturn]] void throw_bad_edge(const std::string& what, int edge, const std::string& hint)
{
    throw InvalidInputError("cut_along_edges: " + what + " (edge " + std::to_string(edge) + "); " +
                            hint);
}

// Rejects the seam before anything is modified, so a throw leaves the mesh untouched.
void validate_seam(const Mesh& mesh, const std::vector<EdgeHandle>& seam)
{
    std::unordered_set<int> seen;
    seen.reserve(2 * seam.size());
    const int n_edges = static_cast<int>(mesh.n_edges());
    for (const EdgeHandle e : seam)
    {
        if (!e.is_valid() || e.idx() >= n_edges)
            throw_bad_edge(
                "seam edge handle is invalid, the mesh has " + std::to_string(n_edges) + " edges",
                e.idx(), "pass handles of edges of this mesh");
        if (mesh.has_edge_status() && mesh.status(e).deleted())
            throw_bad_edge("seam edge is deleted", e.idx(), "pass edges that are in use");
        if (!seen.insert(e.idx()).second)
            throw_bad_edge("seam edge appears more than once", e.idx(),
                           "remove duplicate edges from the seam");
        if (mesh.is_boundary(e))
            throw_bad_edge("seam edge is already on the boundary", e.idx(),
                           "seams consist of interior edges; drop boundary edges from the seam");
    }
}

// The origin property, created as the identity map if missing. This is the only O(|V|) step and
// it runs once per mesh: later cuts find the property and duplicates inherit it by copy.
void ensure_origin(Mesh& mesh)
{
    OpenMesh::VPropHandleT<int> origin;
    if (mesh.get_property_handle(origin, prop::origin))
        return;
    if (mesh._get_vprop(prop::origin) != nullptr)
        throw InvalidInputError(std::string("cut_along_edges: vertex property ") + prop::origin +
                                " exists but is not of type int; remove it or store "
                                "input vertex indices as int");
    mesh.add_property(origin, prop::origin);
    for (const auto v : mesh.vertices())
        mesh.property(origin, v) = v.idx();
}

// A boundary halfedge entering a vertex on the cut; it marks the start of one fan of faces.
struct Entry
{
    int vertex;
    HalfedgeHandle h;
};

}  // namespace

CutSummary cut_along_edges(Mesh& mesh, const std::vector<EdgeHandle>& seam)
{
    validate_seam(mesh, seam);
    ensure_origin(mesh);

    CutSummary summary;
    if (seam.empty())
        return summary;

    // 1. Record the boundary halfedges that already enter the seam's vertices. This circulates
    //    before any link changes, while the one-rings are still consistent. The input is assumed
    //    vertex-manifold (one fan per vertex), as after add_face() or a previous cut.
    std::vector<int> cut_vertices;
    cut_vertices.reserve(2 * seam.size());
    for (const EdgeHandle e : seam)
    {
        const HalfedgeHandle h = mesh.halfedge_handle(e, 0);
        cut_vertices.push_back(mesh.to_vertex_handle(h).idx());
        cut_vertices.push_back(mesh.from_vertex_handle(h).idx());
    }
    std::sort(cut_vertices.begin(), cut_vertices.end());
    cut_vertices.erase(std::unique(cut_vertices.begin(), cut_vertices.end()), cut_vertices.end());

    std::vector<Entry> entries;
    entries.reserve(2 * seam.size() + cut_vertices.size());
    for (const int vi : cut_vertices)
    {
        const VertexHandle v(vi);
        for (auto it = mesh.cvih_iter(v); it.is_valid(); ++it)
            if (mesh.is_boundary(*it))
                entries.push_back({vi, *it});
    }

    // 2. Open each seam edge: a new edge takes the place of o in o's face and o becomes a boundary
    //    halfedge. Face cycles stay consistent throughout; boundary links are fixed in step 3.
    //    new_edge()/new_vertex() grow OpenMesh's arrays geometrically, so their cost is amortized
    //    O(1); callers cutting a freshly copied mesh repeatedly may reserve() first.
    for (const EdgeHandle e : seam)
    {
        const HalfedgeHandle o = mesh.halfedge_handle(e, 0);
        const HalfedgeHandle o_opp = mesh.opposite_halfedge_handle(o);
        const FaceHandle f = mesh.face_handle(o);
        const HalfedgeHandle o_prev = mesh.prev_halfedge_handle(o);
        const HalfedgeHandle o_next = mesh.next_halfedge_handle(o);

        const HalfedgeHandle n =
            mesh.new_edge(mesh.from_vertex_handle(o), mesh.to_vertex_handle(o));
        const HalfedgeHandle n_opp = mesh.opposite_halfedge_handle(n);
        mesh.set_next_halfedge_handle(o_prev, n);
        mesh.set_next_halfedge_handle(n, o_next);
        mesh.set_face_handle(n, f);
        if (mesh.halfedge_handle(f) == o)
            mesh.set_halfedge_handle(f, n);
        mesh.set_boundary(o);
        mesh.set_boundary(n_opp);

        // n plays o's role in f and n_opp runs alongside o_opp, so they take their properties.
        mesh.copy_all_properties(e, mesh.edge_handle(n), true);
        mesh.copy_all_properties(o, n, true);
        mesh.copy_all_properties(o_opp, n_opp, true);

        entries.push_back({mesh.to_vertex_handle(o).idx(), o});
        entries.push_back({mesh.to_vertex_handle(n_opp).idx(), n_opp});
        ++summary.seam_edges;
    }

    // 3 + 4. Each boundary halfedge b entering v starts a fan: rotating x = opp(prev(x)) from
    //    opp(b) crosses the fan's faces up to the first outgoing boundary halfedge, which is
    //    next(b). The walk reads only face links, so stale boundary links do not matter. Every
    //    fan after the first at v gets its own copy of v.
    std::stable_sort(entries.begin(), entries.end(),
                     [](const Entry& a, const Entry& b) { return a.vertex < b.vertex; });
    const std::size_t max_steps = mesh.n_halfedges();
    std::vector<HalfedgeHandle> entering;
    for (std::size_t i = 0; i < entries.size(); ++i)
    {
        const VertexHandle v(entries[i].vertex);
        const bool first_fan = i == 0 || entries[i - 1].vertex != entries[i].vertex;
        const HalfedgeHandle b = entries[i].h;

        entering.assign(1, b);
        HalfedgeHandle x = mesh.opposite_halfedge_handle(b);
        while (!mesh.is_boundary(x))
        {
            const HalfedgeHandle y = mesh.prev_halfedge_handle(x);
            entering.push_back(y);
            x = mesh.opposite_halfedge_handle(y);
            if (entering.size() > max_steps)
                throw TopologyError("cut_along_edges: one-ring of vertex " +
                                    std::to_string(v.idx()) +
                                    " does not close; the input mesh is not manifold there");
        }
        mesh.set_next_halfedge_handle(b, x);

        VertexHandle owner = v;
        if (!first_fan)
        {
            // new_vertex() may reallocate the point array, so pass a copy, not point(v).
            const Mesh::Point p = mesh.point(v);
            owner = mesh.new_vertex(p);
            mesh.copy_all_properties(v, owner, true);
            for (const HalfedgeHandle h : entering)
                mesh.set_vertex_handle(h, owner);
            ++summary.duplicated_vertices;
        }
        // is_boundary(v) looks only at this handle, so it must be an outgoing boundary halfedge.
        mesh.set_halfedge_handle(owner, x);
    }
    return summary;
}

}  // namespace vessel
