// The hierarchy of coarse-to-fine maps (multilevel.h): rounds of shortest-edge halfedge
// collapses on independent sets, as in Hormann, Labsik and Greiner 2001 ("Remeshing
// triangulated surfaces with optimal parameterizations"), so that the kept vertices spread
// evenly and each round costs O(|V|).
//
// The decimation works on arrays (the faces with their halfedges' indices, each vertex's faces
// listed again at the start of every round) rather than on a half-edge mesh, and makes exactly
// the collapses, faces and vertex order that OpenMesh's collapse() and garbage_collection()
// (OpenMesh 9, PolyConnectivity) make on a copy of the mesh built face by face: ties between
// equally short edges (the two halfedges of one edge, above all) go by OpenMesh's halfedge
// numbering, and a vertex's faces are listed from its outgoing halfedge, both kept here as
// OpenMesh changes them. The levels are then the half-edge implementation's, bit for bit; the
// coarse solve of a many-outlet tree from its Tutte start is sensitive to the coarse mesh, and
// another, equally valid choice of ties moved such trees' maps (docs/benchmarks.md,
// "Coarse-to-fine").
//
// A round's collapses are an independent set (no collapse starts or ends at a vertex of the one
// ring of an earlier collapse's target), so every test a later collapse of the round makes reads
// stars no earlier one changed, except through faces it removed (skipped as dead) or whose
// corner it moved from v0 to v1 (read from the face array, which is current). Only v1's list is
// out of date until the next round, and no later collapse of the round reads it.

#include "vessel/map/multilevel.h"

#include "detail/face_jacobian.h"
#include "vessel/core/errors.h"

#include <algorithm>
#include <array>
#include <limits>
#include <stdexcept>
#include <string>

namespace vessel {

namespace {

// One collapse a round may make: v0 into v1 along the halfedge of that OpenMesh index, the
// edge's squared length.
struct Candidate
{
    double length = 0.0;
    int halfedge = -1;
    int v0 = -1, v1 = -1;
    bool operator<(const Candidate& other) const
    {
        return length < other.length || (length == other.length && halfedge < other.halfedge);
    }
};

// A vertex's faces, each as its index, the vertex's corner in it and the two other corners
// a, b (the face reads (v, a, b) counter-clockwise); for a boundary vertex `boundary_to` is the
// neighbour its boundary halfedge goes to (a b that is no face's a), else -1. Once ordered
// (Decimation::order()), in OpenMesh's order: clockwise from the vertex's outgoing halfedge,
// each next face's b this face's a.
struct Fan
{
    std::vector<int> face, corner, a, b;
    int boundary_to = -1;
    int boundary_back = -1;         // a boundary vertex's other boundary neighbour (an a no b)
    std::size_t boundary_face = 0;  // the face whose b is boundary_to

    std::size_t size() const { return face.size(); }
    void clear()
    {
        face.clear();
        corner.clear();
        a.clear();
        b.clear();
        boundary_to = boundary_back = -1;
    }
    void add(int f, int k, const std::array<int, 3>& c)
    {
        face.push_back(f);
        corner.push_back(k);
        a.push_back(c[(k + 1) % 3]);
        b.push_back(c[(k + 2) % 3]);
    }
    // boundary_to, boundary_face and boundary_back of a boundary vertex's faces, all listed.
    void find_boundary()
    {
        for (std::size_t i = 0; i < size(); ++i)
        {
            if (std::find(a.begin(), a.end(), b[i]) == a.end())
            {
                boundary_to = b[i];
                boundary_face = i;
            }
            if (std::find(b.begin(), b.end(), a[i]) == b.end())
                boundary_back = a[i];
        }
    }
    void swap_faces(std::size_t i, std::size_t j)
    {
        std::swap(face[i], face[j]);
        std::swap(corner[i], corner[j]);
        std::swap(a[i], a[j]);
        std::swap(b[i], b[j]);
    }
    // The faces holding the edge to w (1: a boundary edge, 0: no edge).
    int edge_faces(int w) const
    {
        return static_cast<int>(std::count(a.begin(), a.end(), w) +
                                std::count(b.begin(), b.end(), w));
    }
};

class Decimation
{
public:
    Decimation(const Mesh& fine, const std::vector<VertexHandle>& keep);

    // Each vertex's live faces, listed again (start of a round).
    void index_faces();
    // The shortest edge v may go along (a boundary vertex only along the boundary, and not
    // into a kept vertex), the first in OpenMesh's order of equal ones; v0 < 0 if none.
    Candidate candidate(int v, Fan& scratch) const;
    // Whether v0 may go into v1: OpenMesh's TriConnectivity::is_collapse_ok (the link
    // condition: a disk stays a disk), a boundary vertex only along the boundary and not into
    // a kept one, no new chord where asked, and every face that stays turning by less than 60
    // degrees and staying non-degenerate.
    bool allowed(int v0, int v1, bool no_new_chords);
    // v0 into v1 (allowed() said yes just before): the record of the collapse; every vertex
    // whose star changed marked in \p touched.
    Collapse collapse(int v0, int v1, std::vector<char>& touched);
    // The decimated mesh into \p coarse, compacted as OpenMesh's garbage_collection() does.
    void write(CoarseMesh& coarse) const;

    std::size_t vertices() const { return vertex_alive_.size(); }

private:
    template <class Visit>
    void for_faces(int v, const Visit& visit) const
    {
        for (int i = start_[v]; i < start_[v + 1]; ++i)
            if (const int f = incident_[i]; face_alive_[f])
                visit(f);
    }
    // v's corner in face f.
    int corner_of(int f, int v) const
    {
        const auto& c = faces_[f];
        return c[0] == v ? 0 : c[1] == v ? 1 : 2;
    }
    // v's live faces into \p out, unordered, without the boundary search.
    void list(int v, Fan& out) const;
    // v's live faces into \p out, unordered, with the boundary search for a boundary vertex.
    void gather(int v, Fan& out) const;
    // \p fan (gathered for v) into OpenMesh's order.
    void order(int v, Fan& fan) const;
    // The OpenMesh index of the halfedge v -> w, from v's fan (w a neighbour).
    int halfedge(const Fan& fan, int w) const;
    // The outgoing halfedge OpenMesh gives a vertex of faces \p fan once its star is made: the
    // boundary one for a boundary vertex, else \p otherwise.
    int outgoing(const Fan& fan, int otherwise) const;
    const OpenMesh::Vec3d& point(int v) const { return points_[v]; }

    const OpenMesh::Vec3d* points_;  // the fine mesh's
    std::vector<std::array<int, 3>> faces_;
    std::vector<std::array<int, 3>> halfedges_;  // OpenMesh index of corner k -> corner k + 1
    std::vector<char> face_alive_, vertex_alive_, locked_;
    std::vector<int> outgoing_;  // each vertex's outgoing halfedge (OpenMesh's choice)
    std::vector<char> boundary_;  // whether a vertex is on the boundary
    std::vector<int> start_, incident_;
    Fan fan0_, fan1_, fan_w_;  // allowed()'s, kept for collapse()
    Fan fan_v1_;               // collapse()'s
};

Decimation::Decimation(const Mesh& fine, const std::vector<VertexHandle>& keep)
    : points_(fine.points()), vertex_alive_(fine.n_vertices(), 1), locked_(fine.n_vertices(), 0)
{
    // OpenMesh's halfedge numbering and each vertex's outgoing halfedge as add_face() leaves
    // them, read off a copy built face by face (each face's corners from its halfedge on).
    OpenMesh::TriMesh_ArrayKernelT<> copy;
    copy.reserve(fine.n_vertices(), fine.n_edges(), fine.n_faces());
    for (std::size_t v = 0; v < fine.n_vertices(); ++v)
        copy.add_vertex(OpenMesh::Vec3f(0, 0, 0));
    for (auto f : fine.faces())
    {
        auto h = f.halfedge();
        copy.add_face(OpenMesh::VertexHandle(h.from().idx()), OpenMesh::VertexHandle(h.to().idx()),
                      OpenMesh::VertexHandle(h.next().to().idx()));
    }
    faces_.resize(copy.n_faces());
    halfedges_.resize(copy.n_faces());
    for (auto f : copy.faces())
    {
        auto h = f.halfedge();
        for (int k = 0; k < 3; ++k, h = h.next())
        {
            faces_[f.idx()][k] = h.from().idx();
            halfedges_[f.idx()][k] = h.idx();
        }
    }
    outgoing_.resize(copy.n_vertices());
    boundary_.resize(copy.n_vertices());
    for (auto v : copy.vertices())
    {
        outgoing_[v.idx()] = v.halfedge().idx();
        boundary_[v.idx()] = v.is_boundary();
    }
    face_alive_.assign(faces_.size(), 1);
    for (VertexHandle v : keep)
        locked_[v.idx()] = 1;
}

void Decimation::index_faces()
{
    const std::size_t n = vertex_alive_.size();
    start_.assign(n + 1, 0);
    for (std::size_t f = 0; f < faces_.size(); ++f)
        if (face_alive_[f])
            for (int v : faces_[f])
                ++start_[v + 1];
    for (std::size_t v = 0; v < n; ++v)
        start_[v + 1] += start_[v];
    incident_.resize(start_[n]);
    std::vector<int> next(start_.begin(), start_.end() - 1);
    for (std::size_t f = 0; f < faces_.size(); ++f)
        if (face_alive_[f])
            for (int v : faces_[f])
                incident_[next[v]++] = static_cast<int>(f);
}

void Decimation::list(int v, Fan& out) const
{
    out.clear();
    for_faces(v, [&](int f) { out.add(f, corner_of(f, v), faces_[f]); });
}

void Decimation::gather(int v, Fan& out) const
{
    list(v, out);
    if (boundary_[v])
        out.find_boundary();
}

void Decimation::order(int v, Fan& fan) const
{
    // The first face: after the boundary halfedge v -> boundary_to, else the face of v's
    // outgoing halfedge.
    std::size_t first = fan.boundary_face;
    if (fan.boundary_to < 0)
        for (std::size_t i = 0; i < fan.size(); ++i)
            if (halfedges_[fan.face[i]][fan.corner[i]] == outgoing_[v])
                first = i;
    if (fan.size() > 0)
        fan.swap_faces(0, first);
    for (std::size_t i = 0; i + 1 < fan.size(); ++i)
        for (std::size_t j = i + 1; j < fan.size(); ++j)
            if (fan.b[j] == fan.a[i])
            {
                fan.swap_faces(i + 1, j);
                break;
            }
}

int Decimation::halfedge(const Fan& fan, int w) const
{
    for (std::size_t i = 0; i < fan.size(); ++i)
        if (fan.a[i] == w)
            return halfedges_[fan.face[i]][fan.corner[i]];
    for (std::size_t i = 0; i < fan.size(); ++i)
        if (fan.b[i] == w)  // the boundary halfedge: the opposite of w -> v, at corner + 2
            return halfedges_[fan.face[i]][(fan.corner[i] + 2) % 3] ^ 1;
    return -1;
}

Candidate Decimation::candidate(int v, Fan& fan) const
{
    Candidate best{std::numeric_limits<double>::infinity(), -1, -1, -1};
    if (locked_[v] || !vertex_alive_[v])
        return best;
    if (!boundary_[v])
    {
        // Each neighbour is one face's a: the first strictly shortest unless two tie.
        bool tie = false;
        for_faces(v, [&](int f) {
            const int k = corner_of(f, v);
            const int w = faces_[f][(k + 1) % 3];
            const double length = (point(w) - point(v)).sqrnorm();
            if (length < best.length)
            {
                best = {length, halfedges_[f][k], v, w};
                tie = false;
            }
            else if (length == best.length)
                tie = true;
        });
        if (!tie)
            return best;
        best = {std::numeric_limits<double>::infinity(), -1, -1, -1};
    }
    gather(v, fan);
    const bool boundary = fan.boundary_to >= 0;
    // The first strictly shortest in OpenMesh's order (the boundary halfedge first): found
    // unordered, and again in order where two neighbours are exactly as near.
    bool tie = false;
    const auto consider = [&](int w) {
        if (boundary && (fan.edge_faces(w) != 1 || locked_[w]))
            return;
        const double length = (point(w) - point(v)).sqrnorm();
        if (length < best.length)
        {
            best = {length, -1, v, w};
            tie = false;
        }
        else if (length == best.length)
            tie = true;
    };
    const auto scan = [&] {
        if (boundary)
            consider(fan.boundary_to);
        for (int a : fan.a)
            consider(a);
    };
    scan();
    if (tie)
    {
        order(v, fan);
        best = {std::numeric_limits<double>::infinity(), -1, -1, -1};
        scan();
    }
    if (best.v0 >= 0)
        best.halfedge = halfedge(fan, best.v1);
    return best;
}

bool Decimation::allowed(int v0, int v1, bool no_new_chords)
{
    if (locked_[v0])
        return false;
    gather(v0, fan0_);
    gather(v1, fan1_);
    const bool b0 = fan0_.boundary_to >= 0, b1 = fan1_.boundary_to >= 0;
    const int edge = fan0_.edge_faces(v1);
    if (edge == 0)
        return false;
    if (b0 && (edge != 1 || locked_[v1]))
        return false;
    // The faces (v0, v1, vl) and (v1, v0, vr) of the edge.
    int vl = -1, vr = -1;
    for (std::size_t i = 0; i < fan0_.size(); ++i)
    {
        if (fan0_.a[i] == v1)
            vl = fan0_.b[i];
        if (fan0_.b[i] == v1)
            vr = fan0_.a[i];
    }
    // A face whose two other edges are both on the boundary would leave a dangling edge.
    if (vl >= 0 && fan1_.edge_faces(vl) == 1 && fan0_.edge_faces(vl) == 1)
        return false;
    if (vr >= 0 && fan0_.edge_faces(vr) == 1 && fan1_.edge_faces(vr) == 1)
        return false;
    if (vl == vr)
        return false;
    const auto neighbour_of_v1 = [&](int w) { return fan1_.edge_faces(w) > 0; };
    for (const std::vector<int>* corners : {&fan0_.a, &fan0_.b})
        for (int w : *corners)
            if (w != vl && w != vr && w != v1 && neighbour_of_v1(w))
                return false;
    if (b0 && b1 && edge != 1)
        return false;
    if (no_new_chords && b1)
    {
        // v0's other boundary neighbour is joined to v1 by a boundary edge; any other
        // boundary neighbour of v0 not yet joined to v1 would be joined by a chord.
        const int across = !b0 ? -1 : fan0_.boundary_to != v1 ? fan0_.boundary_to
                                                               : fan0_.boundary_back;
        for (const std::vector<int>* corners : {&fan0_.a, &fan0_.b})
            for (int w : *corners)
                if (w != v1 && w != across && !neighbour_of_v1(w))
                {
                    gather(w, fan_w_);
                    if (fan_w_.boundary_to >= 0)
                        return false;
                }
    }
    const OpenMesh::Vec3d p1 = point(v1);
    for (int f : fan0_.face)
    {
        const auto& c = faces_[f];
        if (c[0] == v1 || c[1] == v1 || c[2] == v1)
            continue;  // removed with the collapse
        const OpenMesh::Vec3d pa = point(c[0]), pb = point(c[1]), pc = point(c[2]);
        const OpenMesh::Vec3d before = (pb - pa) % (pc - pa);
        const OpenMesh::Vec3d qa = c[0] == v0 ? p1 : pa, qb = c[1] == v0 ? p1 : pb,
                              qc = c[2] == v0 ? p1 : pc;
        const OpenMesh::Vec3d after = (qb - qa) % (qc - qa);
        const double na = after.norm(), nb = before.norm();
        if (!(na > 1e-12 * nb) || (before | after) < 0.5 * na * nb)
            return false;
    }
    return true;
}

int Decimation::outgoing(const Fan& fan, int otherwise) const
{
    return fan.boundary_to >= 0 ? halfedge(fan, fan.boundary_to) : otherwise;
}

Collapse Decimation::collapse(int v0, int v1, std::vector<char>& touched)
{
    Collapse record{v0, v1, -1, {}};
    Fan& fan = fan0_;
    order(v0, fan);
    if (fan.boundary_to >= 0)
        record.across = fan.boundary_to != v1 ? fan.boundary_to : fan.boundary_back;
    int left = -1, right = -1, vl = -1, vr = -1;
    record.faces.reserve(fan.size());
    for (std::size_t i = 0; i < fan.size(); ++i)
    {
        record.faces.push_back({fan.a[i], fan.b[i]});
        if (fan.a[i] == v1)
        {
            left = fan.face[i];
            vl = fan.b[i];
        }
        if (fan.b[i] == v1)
        {
            right = fan.face[i];
            vr = fan.a[i];
        }
    }
    const auto slot = [&](int f, int from, int to) {
        const auto& c = faces_[f];
        for (int k = 0; k < 3; ++k)
            if (c[k] == from && c[(k + 1) % 3] == to)
                return k;
        return -1;
    };
    // OpenMesh's collapse_loop(): the edge v1-vl keeps its halfedges, v1 -> vl taking the
    // place of v0 -> vl in the face across v0-vl; likewise vr -> v1 that of vr -> v0.
    const int b = left >= 0 ? halfedges_[left][slot(left, v1, vl)] : -1;
    const int e = right >= 0 ? halfedges_[right][slot(right, vr, v1)] : -1;
    for (std::size_t i = 0; i < fan.size(); ++i)
    {
        const int f = fan.face[i];
        if (f == left || f == right)
        {
            face_alive_[f] = 0;
            continue;
        }
        if (left >= 0)
            if (const int k = slot(f, v0, vl); k >= 0)
                halfedges_[f][k] = b;
        if (right >= 0)
            if (const int k = slot(f, vr, v0); k >= 0)
                halfedges_[f][k] = e;
        faces_[f][fan.corner[i]] = v1;
    }
    vertex_alive_[v0] = 0;
    boundary_[v1] = fan0_.boundary_to >= 0 || fan1_.boundary_to >= 0;
    // The vertices' outgoing halfedges as collapse_loop() and adjust_outgoing_halfedge() leave
    // them: the boundary one where there is one. v1's faces are its listed ones and v0's until
    // the next round's listing.
    list(v1, fan_v1_);
    for (std::size_t i = 0; i < fan.size(); ++i)
        if (fan.face[i] != left && fan.face[i] != right)
            fan_v1_.add(fan.face[i], fan.corner[i], faces_[fan.face[i]]);
    if (boundary_[v1])
        fan_v1_.find_boundary();
    outgoing_[v1] = outgoing(fan_v1_, right >= 0 ? e ^ 1 : b);
    if (left >= 0)
    {
        gather(vl, fan_w_);
        outgoing_[vl] = outgoing(fan_w_, b ^ 1);
    }
    if (right >= 0)
    {
        gather(vr, fan_w_);
        outgoing_[vr] = outgoing(fan_w_, e);
    }
    touched[v1] = 1;
    for (const Fan* around : {&fan0_, &fan1_})
        for (const std::vector<int>* corners : {&around->a, &around->b})
            for (int w : *corners)
                touched[w] = 1;
    return record;
}

void Decimation::write(CoarseMesh& coarse) const
{
    // OpenMesh's garbage_collection(): the first dead element swapped with the last live one,
    // over and over.
    const auto compact = [](const std::vector<char>& alive) {
        std::vector<int> order(alive.size());
        for (std::size_t i = 0; i < order.size(); ++i)
            order[i] = static_cast<int>(i);
        if (order.empty())
            return order;
        std::size_t i0 = 0, i1 = order.size() - 1;
        while (true)
        {
            while (alive[order[i0]] && i0 < i1)
                ++i0;
            while (!alive[order[i1]] && i0 < i1)
                --i1;
            if (i0 >= i1)
                break;
            std::swap(order[i0], order[i1]);
        }
        order.resize(alive[order[i0]] ? i0 + 1 : i0);
        return order;
    };
    coarse.fine_of = compact(vertex_alive_);
    coarse.coarse_of.assign(vertex_alive_.size(), -1);
    for (std::size_t c = 0; c < coarse.fine_of.size(); ++c)
        coarse.coarse_of[coarse.fine_of[c]] = static_cast<int>(c);
    const std::vector<int> faces = compact(face_alive_);
    coarse.mesh.reserve(coarse.fine_of.size(), coarse.fine_of.size() + faces.size(),
                        faces.size());
    for (int v : coarse.fine_of)
        coarse.mesh.add_vertex(point(v));
    for (int f : faces)
    {
        const auto& c = faces_[f];
        const auto corner = [&](int k) { return VertexHandle(coarse.coarse_of[c[k]]); };
        if (!coarse.mesh.add_face(corner(0), corner(1), corner(2)).is_valid())
            throw std::logic_error("coarsen: a decimated face could not be added (a collapse "
                                   "broke the mesh's manifoldness)");
    }
}

// coarsen() into \p coarse (empty on entry): an OpenMesh mesh has no move constructor, so a
// CoarseMesh returned and then moved into a vector would copy its mesh.
void coarsen_into(const Mesh& fine, int target_vertices, const std::vector<VertexHandle>& keep,
                  bool no_new_chords, CoarseMesh& coarse)
{
    Decimation work(fine, keep);
    const std::size_t n = work.vertices();
    const std::size_t target = static_cast<std::size_t>(std::max(target_vertices, 3));
    std::size_t alive = n;
    // Each round's candidates are found and sorted on two threads where that pays, each over
    // a run of vertices, then merged: the keys (length, halfedge) are distinct, so the order
    // is the one a single sort gives.
    const int threads = detail::face_threads(fine.n_faces());
    std::array<std::vector<Candidate>, 2> found;
    std::vector<Candidate> candidates;
    std::vector<char> touched(n);
    std::vector<Collapse> collapses;
    collapses.reserve(n - std::min(target, n));
    std::vector<std::size_t> rounds;
    while (alive > target)
    {
        rounds.push_back(collapses.size());
        work.index_faces();
        detail::parallel_chunks(n, threads, [&](std::size_t begin, std::size_t end, int t) {
            Fan scratch;
            found[t].clear();
            for (std::size_t v = begin; v < end; ++v)
                if (const Candidate c = work.candidate(static_cast<int>(v), scratch); c.v0 >= 0)
                    found[t].push_back(c);
            std::sort(found[t].begin(), found[t].end());
        });
        candidates.clear();
        for (int t = 0; t < threads; ++t)
            candidates.insert(candidates.end(), found[t].begin(), found[t].end());
        if (threads > 1)
            std::inplace_merge(candidates.begin(), candidates.begin() + found[0].size(),
                               candidates.end());
        std::fill(touched.begin(), touched.end(), 0);
        std::size_t collapsed = 0;
        for (const Candidate& c : candidates)
        {
            if (touched[c.v0] || touched[c.v1] || !work.allowed(c.v0, c.v1, no_new_chords))
                continue;
            collapses.push_back(work.collapse(c.v0, c.v1, touched));
            ++collapsed;
            if (--alive <= target)
                break;
        }
        if (collapsed == 0)
        {
            rounds.pop_back();
            break;
        }
    }
    coarse.collapses = std::move(collapses);
    coarse.rounds = std::move(rounds);
    work.write(coarse);
}

}  // namespace

CoarseMesh coarsen(const Mesh& fine, int target_vertices, const std::vector<VertexHandle>& keep,
                   bool no_new_chords)
{
    CoarseMesh coarse;
    coarsen_into(fine, target_vertices, keep, no_new_chords, coarse);
    return coarse;
}

std::vector<CoarseMesh> coarsen_levels(const Mesh& fine, int coarse_vertices,
                                       std::vector<VertexHandle> keep, std::size_t boundary_levels,
                                       bool no_new_chords)
{
    if (coarse_vertices < 3)
        throw InvalidInputError("coarsen_levels: coarse_vertices must be >= 3, got " +
                                std::to_string(coarse_vertices));
    // A quarter per level: each level's sweeps then face an error of about twice its edge
    // length, which Gauss-Seidel removes in a few tens of sweeps.
    constexpr std::size_t kRatio = 4;
    std::vector<CoarseMesh> levels;
    // Room for every level (a quarter each: 32 levels are 4^32 vertices): `above` points into
    // the vector, and a reallocation would copy every level's mesh.
    levels.reserve(32);
    for (const Mesh* above = &fine;;)
    {
        std::vector<VertexHandle> level_keep = keep;
        if (levels.size() < boundary_levels)
            for (VertexHandle v : above->vertices())
                if (above->is_boundary(v))
                    level_keep.push_back(v);
        const std::size_t floor =
            static_cast<std::size_t>(coarse_vertices) + (level_keep.size() - keep.size());
        if (above->n_vertices() <= floor)
            break;
        const std::size_t target = std::max(floor, above->n_vertices() / kRatio);
        CoarseMesh& level = levels.emplace_back();
        coarsen_into(*above, static_cast<int>(target), level_keep, no_new_chords, level);
        if (level.mesh.n_vertices() == above->n_vertices())
        {
            levels.pop_back();
            break;  // nothing could be collapsed
        }
        for (VertexHandle& v : keep)
            v = VertexHandle(level.coarse_of[v.idx()]);
        above = &level.mesh;
    }
    return levels;
}

}  // namespace vessel
