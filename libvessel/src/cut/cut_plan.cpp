#include "vessel/cut/cut_plan.h"

#include "vessel/cut/cut_metrics.h"
#include "vessel/cut/cut_winding.h"
#include "vessel/core/errors.h"
#include "vessel/cut/streamline.h"
#include "vessel/cut/winding_bound.h"
#include "detail/edge_distance.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <functional>
#include <optional>
#include <queue>
#include <unordered_map>
#include <cmath>
#include <cstdint>
#include <limits>

namespace vessel {

void CutPlanOptions::validate() const
{
    if (!(tie_tolerance >= 0.0) || !std::isfinite(tie_tolerance))
        throw InvalidInputError("CutPlanOptions: tie_tolerance must be finite and >= 0");
    if (band_rings < 0)
        throw InvalidInputError("CutPlanOptions: band_rings must be >= 0");
    if (!(join_slack >= 0.0) || !std::isfinite(join_slack))
        throw InvalidInputError("CutPlanOptions: join_slack must be finite and >= 0");
    if (!(join_reach >= 0.0) || !std::isfinite(join_reach))
        throw InvalidInputError("CutPlanOptions: join_reach must be finite and >= 0");
    if (!(join_excess >= 0.0) || !std::isfinite(join_excess))
        throw InvalidInputError("CutPlanOptions: join_excess must be finite and >= 0");
    if (join_rings < 0)
        throw InvalidInputError("CutPlanOptions: join_rings must be >= 0");
    if (!(aligned_min_gain >= 0.0) || !std::isfinite(aligned_min_gain))
        throw InvalidInputError("CutPlanOptions: aligned_min_gain must be finite and >= 0");
    if (!(winding_min_gain_deg >= 0.0) || !std::isfinite(winding_min_gain_deg))
        throw InvalidInputError("CutPlanOptions: winding_min_gain_deg must be finite and >= 0");
    if (!(winding_max_alignment_loss >= 0.0) || !std::isfinite(winding_max_alignment_loss))
        throw InvalidInputError(
            "CutPlanOptions: winding_max_alignment_loss must be finite and >= 0");
    if (!(winding_target_deg >= 0.0) || !std::isfinite(winding_target_deg))
        throw InvalidInputError("CutPlanOptions: winding_target_deg must be finite and >= 0");
    if (!(winding_limit_deg >= 0.0) || !std::isfinite(winding_limit_deg))
        throw InvalidInputError(
            "CutPlanOptions: winding_limit_deg must be finite and >= 0");
}

std::vector<EdgeHandle> CutPlan::seam_edges(const Mesh& mesh) const
{
    std::vector<char> seen(mesh.n_edges(), 0);
    std::vector<EdgeHandle> edges;
    for (const auto* list : {&paths, &relief})
        for (const auto& path : *list)
            for (auto h : path.halfedges)
            {
                const auto e = mesh.edge_handle(h);
                if (!seen[e.idx()])
                {
                    seen[e.idx()] = 1;
                    edges.push_back(e);
                }
            }
    return edges;
}

Eigen::MatrixX3d winding_rate(const Mesh& mesh, const Eigen::MatrixX3d& direction,
                              const Eigen::VectorXd& k_max)
{
    const std::size_t nv = mesh.n_vertices();
    std::vector<Eigen::Vector3d> normals(nv, Eigen::Vector3d::Zero());
    for (std::size_t f = 0; f < mesh.n_faces(); ++f)
    {
        const HalfedgeHandle h = mesh.halfedge_handle(FaceHandle(static_cast<int>(f)));
        const HalfedgeHandle g = mesh.next_halfedge_handle(h);
        const int corner[3] = {mesh.from_vertex_handle(h).idx(), mesh.to_vertex_handle(h).idx(),
                               mesh.to_vertex_handle(g).idx()};
        const Eigen::Vector3d a = to_eigen(mesh.point(VertexHandle(corner[0])));
        const Eigen::Vector3d b = to_eigen(mesh.point(VertexHandle(corner[1])));
        const Eigen::Vector3d c = to_eigen(mesh.point(VertexHandle(corner[2])));
        const Eigen::Vector3d n = (b - a).cross(c - a);  // area-weighted
        for (int v : corner)
            normals[v] += n;
    }
    Eigen::MatrixX3d rate(nv, 3);
    for (std::size_t i = 0; i < nv; ++i)
    {
        const Eigen::Index r = static_cast<Eigen::Index>(i);
        const Eigen::Vector3d z(direction(r, 0), direction(r, 1), direction(r, 2));
        Eigen::Vector3d w = std::abs(k_max[r]) * normals[i].normalized().cross(z).normalized();
        if (!w.allFinite())
            w.setZero();
        rate(r, 0) = w.x();
        rate(r, 1) = w.y();
        rate(r, 2) = w.z();
    }
    return rate;
}

namespace {

// Breadth-first ring distance from \p seeds (0) out to \p max_rings edges into \p ring (-1 =
// farther), keeping smaller values already there; vertices \p skip(index) names are not
// entered. Each vertex whose value it lowers is appended to \p lowered, when given.
template <class Skip>
void grow_rings(const CutGraph& graph, const std::vector<VertexHandle>& seeds, int max_rings,
                Skip skip, std::vector<int>& ring, std::vector<int>* lowered = nullptr)
{
    std::vector<VertexHandle> front;
    const auto set = [&](int v, int r) {
        if (lowered && ring[v] < 0)
            lowered->push_back(v);
        ring[v] = r;
    };
    for (auto v : seeds)
        if (!skip(v.idx()))
        {
            if (ring[v.idx()] != 0)
                set(v.idx(), 0);
            front.push_back(v);
        }
    const auto neighbours = detail::graph_neighbours(graph);
    for (int r = 1; r <= max_rings && !front.empty(); ++r)
    {
        std::vector<VertexHandle> next;
        for (auto v : front)
            neighbours(v.idx(), [&](int w) {
                if (!skip(w) && (ring[w] < 0 || ring[w] > r))
                {
                    set(w, r);
                    next.push_back(VertexHandle(w));
                }
            });
        front.swap(next);
    }
}

// band_path()'s |V| arrays, kept across the outlets of one plan so that a band's search costs
// only the band: `ring` is -1 and `band.is_blocked` 1 everywhere between calls.
struct BandScratch
{
    explicit BandScratch(std::size_t nv) : ring(nv, -1) { band.is_blocked.assign(nv, 1); }
    std::vector<int> ring;
    std::vector<int> in_band;  // the vertices with ring >= 0 during a call
    PathQuery band;
};

// Distance along edges to the cut tree (0 on it) and the next vertex toward it
// (detail::EdgeDistance on the graph's arcs, which keep voh_range() order, with reused arrays),
// grown only near where a reader reads it (near_zones()); loop vertices (loop_of >= 0) are
// neither seeds nor passed through. The field is defined as the grows from each cut's vertices
// in turn (defer()), each lowering the distances it improves: the via of a vertex that two
// cuts reach at the same distance is the earlier cut's.
// A part of a path that reads the tree distance (cut_back(), band_path()): the box of its
// vertices and the largest read among them.
struct ReadZone
{
    Eigen::AlignedBox3d box;
    double read = 0.0;
};

// cut_back() and band_path() split their reading vertices into this many zones at most: a
// closer bound than their one box, for a few box distances per vertex visited.
constexpr std::size_t kReadZones = 8;

// \p count reading items, in order, split into at most kReadZones runs of consecutive items:
// a zone per run, its box grown by \p add(item, box) for each item and its read that of the
// run's first item, \p read_of(item).
template <class Add, class ReadOf>
std::vector<ReadZone> zones_along(std::size_t count, Add add, ReadOf read_of)
{
    const std::size_t n_zones = std::min(kReadZones, count);
    const std::size_t per_zone = (count + n_zones - 1) / n_zones;
    std::vector<ReadZone> zones;
    for (std::size_t k = 0; k < count; k += per_zone)
    {
        ReadZone zone;
        zone.read = read_of(k);
        for (std::size_t j = k; j < std::min(count, k + per_zone); ++j)
            add(j, zone.box);
        zones.push_back(zone);
    }
    return zones;
}

class TreeDistance
{
public:
    void reset(std::size_t nv)
    {
        nv_ = nv;
        grown_.clear();
        points_.clear();
    }

    // Adds \p seeds to the tree (their grow runs at each near_zones()).
    void defer(const Mesh& mesh, const std::vector<VertexHandle>& seeds,
               const std::vector<int>& loop_of)
    {
        grown_.push_back(seeds);
        for (auto s : seeds)
            if (loop_of[s.idx()] < 0)
                points_.push_back(to_eigen(mesh.point(s)));
    }

    // The field, exact (distance and via, as unbounded grows give them) at every vertex that
    // can lie on a shortest route from the tree to a point of a zone's box no longer than the
    // zone's read: all grows replayed into a scratch field in order, a vertex entered only while its
    // distance stays within its bound, the largest over the zones of
    // min(read, read + tolerance - straight distance to the zone's box) (\p tolerance for
    // rounding). Such a vertex's predecessors pass the same test (the straight distance to a
    // box drops by at most an edge's length), and the pops left are in the same (distance,
    // index) order, so they pick the same `via`; a vertex it does not reach lies farther than
    // every zone's read, or on no such route, and a value beyond a zone's read may be too high.
    // Valid until the next call.
    const detail::EdgeDistance& near_zones(const CutGraph& graph, const std::vector<int>& loop_of,
                                           const std::vector<ReadZone>& zones, double tolerance)
    {
        const Mesh& mesh = graph.mesh();
        scratch_.clear(nv_);
        // Each vertex's bound once (memo_, NaN = not yet), as it is asked for at every visit.
        if (memo_.size() != nv_)
            memo_.assign(nv_, std::numeric_limits<double>::quiet_NaN());
        for (int v : memoised_)
            memo_[v] = std::numeric_limits<double>::quiet_NaN();
        memoised_.clear();
        // A vertex farther from all the zones' box than the largest read is entered by none:
        // one box distance instead of one per zone for most of the tree's vertices.
        Eigen::AlignedBox3d all;
        double largest = -std::numeric_limits<double>::infinity();
        for (const auto& zone : zones)
        {
            all.extend(zone.box);
            largest = std::max(largest, zone.read);
        }
        const auto bound_at = [&](int v) {
            double& bound = memo_[v];
            if (std::isnan(bound))
            {
                const Eigen::Vector3d p = to_eigen(mesh.point(VertexHandle(v)));
                bound = -std::numeric_limits<double>::infinity();
                if (largest + tolerance - all.exteriorDistance(p) >= 0.0)
                    for (const auto& zone : zones)
                        bound = std::max(bound, std::min(zone.read, zone.read + tolerance -
                                                                        zone.box.exteriorDistance(p)));
                memoised_.push_back(v);
            }
            return bound;
        };
        const auto enter = [&](int v) { return loop_of[v] < 0 && bound_at(v) >= 0.0; };
        for (const auto& seeds : grown_)
            scratch_.grow_within(mesh, seeds, detail::graph_neighbours(graph), enter, bound_at);
        return scratch_;
    }

    // The points of the tree's vertices (the seeds off the loops), deferred ones included.
    const std::vector<Eigen::Vector3d>& points() const { return points_; }

private:
    detail::EdgeDistance scratch_;  // near_zones()
    std::vector<double> memo_;      // near_zones(): each vertex's bound
    std::vector<int> memoised_;     // the vertices with a bound in memo_
    std::size_t nv_ = 0;
    std::vector<std::vector<VertexHandle>> grown_;  // the seeds of each grow, in order
    std::vector<Eigen::Vector3d> points_;           // see points()
};

// CutRoute::Streamline for one cut: trace \p field from \p start until a face touches
// \p stop_at, then take the cheapest path of \p query from \p start inside the band of
// \p band_rings rings around the crossed faces. For a cut that ends on the cut tree (\p tree
// given) the trace is cut back to where it first comes within \p slack of its nearest
// approach to the tree, and the band also covers the shortest bridge from there to the tree.
// Empty when the trace does not arrive or the band holds no route. \p loop_of as in
// TreeDistance.
// \p winding_rate: plan_cuts()'s, read by the band's search.
std::optional<GraphPath> band_path(CutGraph& graph, PathQuery& query, BandScratch& scratch,
                                   const Eigen::MatrixX3d& winding_rate,
                                   const Eigen::MatrixX3d& field, VertexHandle start,
                                   const std::vector<char>& stop_at, int band_rings,
                                   TreeDistance* tree, const std::vector<int>& loop_of,
                                   double slack)
{
    const Mesh& mesh = graph.mesh();
    const Streamline line = trace_streamline(mesh, field, start, stop_at);
    std::size_t n_faces = line.faces.size();
    if (n_faces == 0 || (!tree && line.stop != StreamlineStop::Target))
        return std::nullopt;
    std::vector<VertexHandle> seeds;
    if (tree)
    {
        // The tree distance at the trace's corners, read through zones along the trace with a
        // trial read: exact at every corner within it (TreeDistance::near_zones()). Every face
        // within the slack of the nearest approach must lie within the read; if not, read as
        // far as that (or, while no corner is reached, twice as far, up to 64 slacks, then
        // without limit).
        std::vector<double> near(n_faces);
        std::vector<int> corner(n_faces, -1);
        double nearest = std::numeric_limits<double>::infinity();
        const detail::EdgeDistance* reached = nullptr;
        std::vector<ReadZone> zones = zones_along(
            n_faces,
            [&](std::size_t i, Eigen::AlignedBox3d& box) {
                for (auto v : mesh.fv_range(line.faces[i]))
                    box.extend(to_eigen(mesh.point(v)));
            },
            [](std::size_t) { return 0.0; });  // set by each trial read
        const auto approach = [&](double read) {
            for (auto& zone : zones)
                zone.read = read;
            reached = &tree->near_zones(graph, loop_of, zones, 1e-9 * read);
            nearest = std::numeric_limits<double>::infinity();
            for (std::size_t i = 0; i < n_faces; ++i)
            {
                near[i] = std::numeric_limits<double>::infinity();
                corner[i] = -1;
                for (auto v : mesh.fv_range(line.faces[i]))
                    if (reached->dist[v.idx()] < near[i])
                    {
                        near[i] = reached->dist[v.idx()];
                        corner[i] = v.idx();
                    }
                nearest = std::min(nearest, near[i]);
            }
        };
        double read = 3.0 * slack;
        approach(read);
        while (!(nearest + slack <= read))
        {
            read = std::isfinite(nearest) ? nearest + slack
                   : read < 64.0 * slack  ? 2.0 * read
                                          : std::numeric_limits<double>::infinity();
            approach(read);  // without limit, every reachable corner: the loop ends
        }
        if (!std::isfinite(nearest))
            return std::nullopt;
        n_faces = 0;
        while (near[n_faces] > nearest + slack)
            ++n_faces;
        for (int v = corner[n_faces]; v >= 0; v = reached->via[v])
            seeds.push_back(VertexHandle(v));
        ++n_faces;
    }
    for (auto v : line.vertices)
        seeds.push_back(v);
    for (std::size_t i = 0; i < n_faces; ++i)
        for (auto v : mesh.fv_range(line.faces[i]))
            seeds.push_back(v);
    std::vector<int>& ring = scratch.ring;
    scratch.in_band.clear();
    grow_rings(graph, seeds, band_rings, [](int) { return false; }, ring, &scratch.in_band);

    // The band's query: the outlet's targets (lent by \p query for the search), every vertex
    // outside the band blocked, and the loop's other vertices: the cut opens its loop at `start`
    // only, with no step along the rim (boundary edges).
    PathQuery& band = scratch.band;
    band.sources = {start};
    band.tie_tolerance = query.tie_tolerance;
    band.is_target.swap(query.is_target);
    for (int v : scratch.in_band)
        band.is_blocked[v] = query.is_blocked.empty() ? 0 : query.is_blocked[v];
    for (auto v : query.sources)
        if (v != start)
            band.is_blocked[v.idx()] = 1;
    std::optional<GraphPath> path;
    try
    {
        path = graph.shortest_path(band, winding_rate);
    }
    catch (const InvalidInputError&)
    {
        // no target inside the band
    }
    band.is_target.swap(query.is_target);
    for (int v : scratch.in_band)
    {
        band.is_blocked[v] = 1;
        ring[v] = -1;
    }
    return path;
}

// The cut-tree vertices within (1 + slack) x the edge-path distance from \p loop to the nearest
// one, plus \p extra, found by a Dijkstra from the loop that neither enters other loops nor
// passes the tree.
std::vector<VertexHandle> near_tree_vertices(const Mesh& mesh, const std::vector<char>& on_tree,
                                             const std::vector<int>& loop_of, int loop,
                                             const std::vector<VertexHandle>& sources,
                                             double slack, double extra)
{
    using Item = std::pair<double, int>;
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> heap;
    std::vector<double> dist(mesh.n_vertices(), std::numeric_limits<double>::infinity());
    for (auto v : sources)
    {
        dist[v.idx()] = 0.0;
        heap.push({0.0, v.idx()});
    }
    std::vector<VertexHandle> near;
    double limit = std::numeric_limits<double>::infinity();
    while (!heap.empty())
    {
        const auto [d, v] = heap.top();
        heap.pop();
        if (d > dist[v])
            continue;
        if (d > limit)
            break;
        if (on_tree[v])
        {
            if (near.empty())
                limit = d * (1.0 + slack) + extra;
            near.push_back(VertexHandle(v));
            continue;
        }
        for (auto h : mesh.voh_range(VertexHandle(v)))
        {
            const int w = h.to().idx();
            const double nd = d + mesh.calc_edge_length(h);
            if ((loop_of[w] < 0 || loop_of[w] == loop) && nd < dist[w])
            {
                dist[w] = nd;
                heap.push({nd, w});
            }
        }
    }
    if (near.empty())
        throw InvalidInputError("plan_cuts: outlet " + std::to_string(loop) +
                                " cannot reach the cut tree; is the mesh one connected surface?");
    return near;
}

// CutJoin::Approach: \p path cut back at its first vertex v within \p reach of the cut tree
// whose remaining length along the path exceeds its distance to the tree by more than
// \p excess (the path would run on beside the tree), and joined to the tree from v over the
// shortest bridge (tree.via); unchanged if there is no such vertex.
//
// The tree distance is read only as far as a vertex could pass: at vertex i, up to
// min(reach, left - excess), and not at all where the straight distance to the nearest tree
// vertex (which the edge-path distance cannot undercut) already exceeds that. When there is
// such a read, \p tree grows a scratch copy of its field only on the routes that can reach the
// reading vertices within their zone's read (TreeDistance::near_zones()); when there is none
// the path is kept as is.
GraphPath cut_back(const CutGraph& graph, const GraphPath& path, TreeDistance& tree,
                   const std::vector<int>& loop_of, double reach, double excess)
{
    const Mesh& mesh = graph.mesh();
    const std::size_t n = path.halfedges.size();
    std::vector<double> left(n, 0.0);  // path length after the head of halfedge i
    for (std::size_t i = n - 1; i-- > 0;)
        left[i] = left[i + 1] + mesh.calc_edge_length(path.halfedges[i + 1]);
    // A margin far above rounding (1e-9 of the lengths involved) keeps the screen on the safe
    // side: it may read further than needed, never less.
    const double margin = 1e-9 * (reach + excess + (n > 0 ? left[0] : 0.0));
    // The tree points within reach of the path's bounding box, in cells of the largest read
    // (a vertex then looks into its own cell and the 26 around it).
    const double cell = reach + margin;
    Eigen::AlignedBox3d box;
    for (std::size_t i = 0; i + 1 < n; ++i)
        if (left[i] - excess + margin >= 0.0)
            box.extend(to_eigen(mesh.point(mesh.to_vertex_handle(path.halfedges[i]))));
    if (box.isEmpty())
        return path;
    box.min().array() -= cell;
    box.max().array() += cell;
    const bool grid = cell > 0.0 && (box.sizes() / cell).maxCoeff() < 1e5;
    const auto cell_of = [&](const Eigen::Vector3d& p, int dx, int dy, int dz) -> std::int64_t {
        if (!grid)
            return 0;
        const Eigen::Vector3d c = (p - box.min()) / cell;
        return (static_cast<std::int64_t>(c.x()) + dx) * 1000003LL * 1000003LL +
               (static_cast<std::int64_t>(c.y()) + dy) * 1000003LL +
               (static_cast<std::int64_t>(c.z()) + dz);
    };
    std::unordered_map<std::int64_t, std::vector<Eigen::Vector3d>> near;
    for (const auto& q : tree.points())
        if (box.contains(q))
            near[cell_of(q, 0, 0, 0)].push_back(q);
    // Whether a tree point lies within \p read of \p p (the edge-path distance cannot be less).
    const auto within = [&](const Eigen::Vector3d& p, double read) {
        for (int dx = -1; dx <= 1; ++dx)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dz = -1; dz <= 1; ++dz)
                {
                    const auto found = near.find(cell_of(p, dx, dy, dz));
                    if (found != near.end())
                        for (const auto& q : found->second)
                            if ((p - q).squaredNorm() <= read * read)
                                return true;
                    if (!grid)
                        return false;  // one cell holds them all
                }
        return false;
    };
    // The reading vertices: those with a tree point within their read, in path order (their
    // reads fall along the path, as left does).
    std::vector<std::pair<Eigen::Vector3d, double>> reading;
    for (std::size_t i = 0; i + 1 < n; ++i)
    {
        const double read = std::min(reach, left[i] - excess) + margin;
        if (read < 0.0)
            break;
        const Eigen::Vector3d p = to_eigen(mesh.point(mesh.to_vertex_handle(path.halfedges[i])));
        if (within(p, read))
            reading.emplace_back(p, read);
    }
    if (reading.empty())
        return path;
    // Every read lies in one of a few zones (consecutive reading vertices: their box and the
    // first one's read): only the tree distance on the routes that can reach a zone within its
    // read is grown (TreeDistance::near_zones()).
    const std::vector<ReadZone> zones = zones_along(
        reading.size(),
        [&](std::size_t j, Eigen::AlignedBox3d& zone_box) { zone_box.extend(reading[j].first); },
        [&](std::size_t k) { return reading[k].second; });
    const detail::EdgeDistance& field = tree.near_zones(graph, loop_of, zones, margin);
    for (std::size_t i = 0; i + 1 < n; ++i)
    {
        const VertexHandle v = mesh.to_vertex_handle(path.halfedges[i]);
        const double d = field.dist[v.idx()];
        if (!(d <= reach) || !(left[i] > d + excess))
            continue;
        std::vector<HalfedgeHandle> halfedges(path.halfedges.begin(),
                                              path.halfedges.begin() + static_cast<long>(i) + 1);
        std::unordered_map<int, std::size_t> kept;  // prefix vertex -> halfedges up to it
        for (std::size_t k = 0; k < halfedges.size(); ++k)
            kept[mesh.to_vertex_handle(halfedges[k]).idx()] = k + 1;
        std::size_t prefix = halfedges.size();
        for (int u = v.idx(), w = field.via[u]; w >= 0; u = w, w = field.via[u])
        {
            // A bridge through an earlier vertex of the path: cut back there instead, so the
            // cut stays simple.
            const auto it = kept.find(w);
            if (it != kept.end() && it->second <= prefix)
            {
                prefix = it->second;
                halfedges.resize(prefix);
            }
            else
                halfedges.push_back(mesh.find_halfedge(VertexHandle(u), VertexHandle(w)));
        }
        return graph.path_of(std::move(halfedges));
    }
    return path;
}

CutPath as_cut(const Mesh& mesh, const GraphPath& p)
{
    CutPath c;
    c.halfedges = p.halfedges;
    c.start = mesh.from_vertex_handle(p.halfedges.front());
    return c;
}

// CutRoute::Aligned: whether the traced path replaces the cheapest one. With a winding meter,
// when it winds clearly less and is not much worse aligned; otherwise (or without a meter)
// when it follows the stream field clearly better. \p winding_meter returns the meter (built
// at its first call) or null.
bool keep_traced(const Mesh& mesh, const GraphPath& cheapest, const GraphPath& traced,
                 const Eigen::MatrixX3d& stream_field,
                 const std::function<const WindingMeter*()>& winding_meter,
                 const CutPlanOptions& options)
{
    const CutPath a = as_cut(mesh, cheapest), b = as_cut(mesh, traced);
    const double aligned_a = path_alignment(mesh, a, stream_field).mean;
    const double aligned_b = path_alignment(mesh, b, stream_field).mean;
    // Either test alone can keep it; the windings (the costly part) are measured only when
    // the alignments leave the answer open.
    if (aligned_b > aligned_a + options.aligned_min_gain)
        return true;
    if (!(aligned_b >= aligned_a - options.winding_max_alignment_loss))
        return false;
    const WindingMeter* meter = winding_meter();
    return meter && std::abs(meter->measure(b).winding_deg) <
                        std::abs(meter->measure(a).winding_deg) - options.winding_min_gain_deg;
}

// The bounded search of steer_path() carries a cut's frame over unmeasured vertices up to one
// ring radius (WindingMeter::step()). With the meter's own restart at every such vertex the
// search can turn where a band fails the spread test by noise alone, unseen by this meter and
// seen by another whose bands differ by rounding (seamwinding.py; docs/design.md, "Natural
// cuts"). A radius spans such noisy bands (one to four vertices) and stops short of junctions
// and sacs.
constexpr double kSearchBridge = 1.0;

// CutRoute::Aligned: a cut that winds more than options.winding_target_deg around its vessel
// end to end, or that is no natural cut (it winds more than options.winding_limit_deg, or with
// options.natural_cuts its angle spans more than that: WindingMeter), is searched again.
//
// 1. Its signed winding priced into the arcs (PathQuery::steer_rate =
//    WindingMeter::angular_rate(), a Lagrangian relaxation of "winds at most the target"): the
//    multiplier opposes the way \p current winds; it doubles from 1/16 of the path's cost per
//    half turn (up to 16) until the steered cut winds less than the target or the other way,
//    then three bisections between the last two. A multiplier reaches only the routes on the
//    convex hull of (winding, cost). A steered path replaces \p current if it winds less by
//    more than options.winding_min_gain_deg and its alignment with the stream field is at most
//    options.winding_max_alignment_loss lower.
// 2. With options.natural_cuts, if no steered path reached the target or a natural cut:
//    winding_bounded_path() with the meter's steps (WindingMeter::step(), carried over gaps of
//    kSearchBridge ring radii) and the target as its bound (then, if that gives no natural
//    cut, half the limit, bridged and then not): the cheapest route whose angle stays within
//    +-bound at every vertex (span <= 2 x bound), inside the hull too (on the vmtk aorta every
//    route on the hull winds about +-80 degrees). There a candidate must also keep a natural
//    cut natural, and a cut that is not natural takes a natural candidate whatever its
//    alignment (the bound is what natural means; the alignment's floor was fitted on cuts
//    that wind less).
// \p traced: \p current was taken along a streamline (it cannot drift from an aligned curve by
// more than its band); it is searched again only if it is no natural cut.
// \p finish: what the caller does to a cheapest path (the cut back of CutJoin::Approach); a
// bounded route keeps its cut back only if it stays within the bound.
// Empty = keep \p current.
template <class Finish>
std::optional<GraphPath> steer_path(CutGraph& graph, PathQuery& query,
                                    const Eigen::MatrixX3d& winding_rate,
                                    const WindingMeter& meter, const GraphPath& current,
                                    bool traced, const Eigen::MatrixX3d& stream_field,
                                    const CutPlanOptions& options, Finish finish)
{
    const Mesh& mesh = graph.mesh();
    if (winding_rate.rows() == 0 || options.winding_target_deg <= 0.0)
        return std::nullopt;
    const bool strict = options.natural_cuts;
    const auto natural = [&](const PathWinding& w) {
        return std::abs(w.winding_deg) <= options.winding_limit_deg &&
               (!strict || w.span_deg <= options.winding_limit_deg);
    };
    const PathWinding now = meter.measure(as_cut(mesh, current));
    const double wound = std::abs(now.winding_deg);
    const bool was_natural = natural(now);
    if (was_natural && (traced || !(wound > options.winding_target_deg)))
        return std::nullopt;
    const double floor_alignment =
        path_alignment(mesh, as_cut(mesh, current), stream_field).mean -
        options.winding_max_alignment_loss;
    std::optional<GraphPath> best;
    bool best_natural = was_natural;
    double best_wound = wound - options.winding_min_gain_deg;
    // Whether \p p replaces the best so far (and becomes it).
    const auto offer = [&](GraphPath& p) {
        const CutPath cut = as_cut(mesh, p);
        const PathWinding w = meter.measure(cut);
        const bool is_natural = natural(w);
        const bool aligned = path_alignment(mesh, cut, stream_field).mean >= floor_alignment;
        const bool better =
            strict ? (!best_natural && is_natural) ||
                         (std::abs(w.winding_deg) < best_wound &&
                          (is_natural || !best_natural) && aligned)
                   : std::abs(w.winding_deg) < best_wound && aligned;
        if (better)
        {
            best_wound = std::abs(w.winding_deg);
            best_natural = is_natural;
            best = std::move(p);
        }
        return w.winding_deg;
    };
    if (wound > options.winding_target_deg)
    {
        query.steer_rate = [&meter](int v) { return meter.angular_rate(VertexHandle(v)); };
        const double sign = now.winding_deg > 0.0 ? 1.0 : -1.0;
        const double unit = current.cost / M_PI;  // t = 1: a half turn costs the path's cost
        // The signed winding of the steered path at multiplier t (0 = on target).
        const auto steer = [&](double t) {
            query.steer_weight = sign * t * unit;
            GraphPath p = finish(graph.shortest_path(query, winding_rate));
            const double w = offer(p);
            return std::abs(w) <= options.winding_target_deg ? 0.0 : sign * w;
        };
        double low = 0.0, high = 0.0;
        for (double t = 1.0 / 16; t <= 16.0; t *= 2.0)
        {
            const double left = steer(t);
            if (left <= 0.0)
            {
                high = t;
                break;
            }
            low = t;
        }
        if (high > 0.0 && low == 0.0)
            low = high / 2.0;
        if (high > 0.0 && best_wound > options.winding_target_deg)
            for (int i = 0; i < 3 && best_wound > options.winding_target_deg; ++i)
            {
                const double t = std::sqrt(low * high);
                (steer(t) > 0.0 ? low : high) = t;
            }
        query.steer_rate = nullptr;
        query.steer_weight = 0.0;
    }
    // The target as the bound first; if no route keeps it (or none is taken), half the natural
    // limit, which still bounds the span by the limit.
    // Last, half the limit with the meter's own steps (no bridge): the bound then holds exactly
    // as the meter reads it.
    const std::pair<double, double> tries[] = {{options.winding_target_deg, kSearchBridge},
                                               {0.5 * options.winding_limit_deg, kSearchBridge},
                                               {0.5 * options.winding_limit_deg, 0.0}};
    for (const auto& [limit, bridge] : tries)
    {
        if (!(strict && (best_wound > options.winding_target_deg || !best_natural)) ||
            !(limit > 0.0 && limit < 180.0))
            break;
        WindingBoundOptions bound;
        bound.limit_deg = limit;
        const double carry = bridge;
        std::optional<GraphPath> bounded = winding_bounded_path(
            graph, query,
            [&meter, carry](VertexHandle last, VertexHandle w, bool gap) {
                return meter.step(last, w, gap, carry);
            },
            bound);
        if (bounded)
        {
            // A later cut that would run beside the tree is cut back and bridged to it
            // (CutJoin::Approach); the bridge may turn, so a bounded route keeps its cut back
            // only if it stays within the bound (else it may run beside the tree).
            GraphPath p = finish(*bounded);
            if (std::abs(meter.measure(as_cut(mesh, p)).winding_deg) > bound.limit_deg)
                p = std::move(*bounded);
            offer(p);
        }
        if (best_natural)
            break;
    }
    return best;
}

}  // namespace

CutPlan plan_cuts(const Mesh& mesh, const std::vector<BoundaryLoop>& loops,
                  const HalfedgeWeights& weights, const Eigen::MatrixX3d& winding_rate,
                  const CutPlanOptions& options, const Eigen::MatrixX3d& stream_field,
                  const Eigen::VectorXd& longitudinal)
{
    options.validate();
    CutGraph graph(mesh, weights);
    return plan_cuts(graph, loops, winding_rate, options, stream_field, longitudinal);
}

CutPlan plan_cuts(CutGraph& graph, const std::vector<BoundaryLoop>& loops,
                  const Eigen::MatrixX3d& winding_rate, const CutPlanOptions& options,
                  const Eigen::MatrixX3d& stream_field, const Eigen::VectorXd& longitudinal)
{
    options.validate();
    const Mesh& mesh = graph.mesh();
    const bool streamline =
        options.route == CutRoute::Streamline || options.route == CutRoute::Aligned;
    const bool compare = options.route == CutRoute::Aligned;
    if (streamline && static_cast<std::size_t>(stream_field.rows()) != mesh.n_vertices())
        throw InvalidInputError("plan_cuts: the streamline route needs a stream field with one "
                                "row per vertex (" + std::to_string(mesh.n_vertices()) +
                                "), got " + std::to_string(stream_field.rows()));
    if (loops.size() < 2)
        throw InvalidInputError("plan_cuts: " + std::to_string(loops.size()) +
                                " boundary loop(s); a vessel tree needs an inlet and an outlet");
    const std::size_t nv = mesh.n_vertices();
    if (compare && longitudinal.size() != 0 && static_cast<std::size_t>(longitudinal.size()) != nv)
        throw InvalidInputError("plan_cuts: " + std::to_string(longitudinal.size()) +
                                " longitudinal values for " + std::to_string(nv) +
                                " vertices; pass harmonic_longitudinal() of the same mesh, or none");
    const double mean_edge = streamline ? mean_edge_length(mesh) : 0.0;
    // Built at the first cut whose alignments leave the choice to the windings (keep_traced).
    std::optional<WindingMeter> meter;
    const auto winding_meter = [&]() -> const WindingMeter* {
        if (!compare || longitudinal.size() == 0)
            return nullptr;
        // The harmonic stream field is the descent of `longitudinal`: minus it is the unit
        // gradient the meter would otherwise compute at every vertex its rings reach.
        if (!meter)
        {
            if (options.stream_field == StreamField::Harmonic)
                meter.emplace(graph, longitudinal, mean_edge, -stream_field);
            else
                meter.emplace(graph, longitudinal, mean_edge);
        }
        return &*meter;
    };

    // path_of[v]: first cut through v (-1 if none); loop_of[v]: boundary loop of v (-1 if none).
    std::vector<int> path_of(nv, -1), loop_of(nv, -1);
    for (std::size_t l = 0; l < loops.size(); ++l)
        for (auto v : loops[l].vertices)
            loop_of[v.idx()] = static_cast<int>(l);
    // Where each loop's cut may start (outlets) or end (the inlet).
    const ImaginaryNodeEndpoints whole_loop;
    const EndpointPolicy& endpoints = options.endpoints ? *options.endpoints : whole_loop;
    const auto ends_on = [&](std::size_t l) {
        std::vector<VertexHandle> ends = endpoints.allowed(mesh, loops[l], l);
        if (ends.empty())
            throw InvalidInputError("plan_cuts: the endpoint policy '" + endpoints.name() +
                                    "' allows no vertex of loop " + std::to_string(l) +
                                    "; it must return at least one of the loop's vertices");
        for (auto v : ends)
            if (!v.is_valid() || static_cast<std::size_t>(v.idx()) >= nv ||
                loop_of[v.idx()] != static_cast<int>(l))
                throw InvalidInputError("plan_cuts: the endpoint policy '" + endpoints.name() +
                                        "' returned vertex " + std::to_string(v.idx()) +
                                        ", which is not on loop " + std::to_string(l) +
                                        "; it must return vertices of the loop it is given");
        return ends;
    };

    // One graph and one query for all outlets; the flags change only on loops and new cuts.
    // Query l: targets are the inlet (l = 1) or the interior vertices of earlier cuts (l > 1);
    // blocked are the vertices of every loop but l that are not targets.
    PathQuery query;
    // The |V| x 3 winding field is passed to each search by reference, not copied in.
    query.tie_tolerance = options.tie_tolerance;
    query.is_target.assign(nv, 0);
    query.is_blocked.assign(nv, 0);
    const auto set_blocked = [&](std::size_t l, char value) {
        for (auto v : loops[l].vertices)
            query.is_blocked[v.idx()] = value;
    };
    for (std::size_t l = 0; l < loops.size(); ++l)
        set_blocked(l, 1);
    const std::vector<VertexHandle> inlet_targets = ends_on(0);
    for (auto v : inlet_targets)
    {
        query.is_target[v.idx()] = 1;
        query.is_blocked[v.idx()] = 0;
    }

    // Streamline route: join[v] = edge rings from v to the nearest interior cut vertex, within
    // options.join_rings (-1 beyond); a later cut's streamline stops where join >= 0.
    std::vector<int> join(streamline ? nv : 0, -1);
    std::vector<char> stop_at(streamline ? nv : 0, 0);
    std::vector<int> joined;  // vertices given a join value since the last trace
    BandScratch band_scratch(streamline ? nv : 0);
    const bool closest = options.join == CutJoin::Closest && options.route != CutRoute::Streamline;
    const bool approach = options.join == CutJoin::Approach;
    const double slack = streamline ? options.join_rings * mean_edge : 0.0;
    // The distance to the cut tree is read by cut_back() (CutJoin::Approach) only where a path
    // vertex could pass, often nowhere, and by band_path() at a later cut's trace up to the
    // slack beyond its nearest approach (the trace stops within join_rings of the tree when it
    // arrives); each grows it only near what it reads (TreeDistance::near_zones()). Until
    // 2026-11-27 band_path() read a field grown from the whole tree out to the largest
    // reach, which cost a third of the default VC on carotid-44k.
    TreeDistance tree;
    if (streamline || approach)
        tree.reset(nv);

    CutPlan plan;
    for (std::size_t l = 1; l < loops.size(); ++l)
    {
        if (l == 2)
        {
            // Interior cut vertices only: a cut ending on a loop would open that loop twice.
            for (auto v : inlet_targets)
                query.is_target[v.idx()] = 0;
            set_blocked(0, 1);
            for (auto h : plan.paths.front().halfedges)
                for (auto v : {mesh.from_vertex_handle(h), mesh.to_vertex_handle(h)})
                    query.is_target[v.idx()] = loop_of[v.idx()] < 0;
        }
        std::vector<VertexHandle> cheapest_targets;
        if (l >= 2 && closest)
        {
            // End on a cut vertex close to the outlet (CutJoin::Closest); the path there is the
            // cheapest.
            const std::vector<VertexHandle> near = near_tree_vertices(
                mesh, query.is_target, loop_of, static_cast<int>(l), loops[l].vertices,
                options.join_slack, loops[l].arc_length);
            for (std::size_t v = 0; v < nv; ++v)
                if (query.is_target[v])
                    cheapest_targets.push_back(VertexHandle(static_cast<int>(v)));
            // The tree vertices not allowed as ends are blocked, or the path could cross the
            // tree there (then the cut mesh is no disk).
            for (auto v : cheapest_targets)
            {
                query.is_target[v.idx()] = 0;
                query.is_blocked[v.idx()] = 1;
            }
            for (auto v : near)
            {
                query.is_target[v.idx()] = 1;
                query.is_blocked[v.idx()] = 0;
            }
        }
        if (l >= 2)
            set_blocked(l - 1, 1);
        set_blocked(l, 0);
        query.sources = ends_on(l);

        // A later cut's cheapest path is cut back where it runs beside the tree.
        const auto finish = [&](GraphPath p) {
            if (l < 2 || !approach)
                return p;
            const double radius = loops[l].arc_length / (2.0 * M_PI);
            return cut_back(graph, p, tree, loop_of, options.join_reach * radius,
                            options.join_excess * radius);
        };
        GraphPath found = finish(graph.shortest_path(query, winding_rate));
        if (!cheapest_targets.empty())  // restore: the whole tree, for the traced path and the next outlet
        {
            query.is_target.assign(nv, 0);
            for (auto v : cheapest_targets)
            {
                query.is_target[v.idx()] = 1;
                query.is_blocked[v.idx()] = 0;
            }
        }
        bool traced = false;
        if (streamline)
        {
            if (l == 1)
                stop_at = query.is_target;
            else if (l == 2)
                for (std::size_t v = 0; v < nv; ++v)
                    stop_at[v] = join[v] >= 0;
            else
                for (int v : joined)
                    stop_at[v] = 1;
            joined.clear();
            std::optional<GraphPath> along =
                band_path(graph, query, band_scratch, winding_rate, stream_field,
                          mesh.from_vertex_handle(found.halfedges.front()), stop_at,
                          options.band_rings, l == 1 ? nullptr : &tree, loop_of, slack);
            if (along && compare && !keep_traced(mesh, found, *along, stream_field,
                                                  winding_meter, options))
                along.reset();
            if (along)
            {
                found = std::move(*along);
                traced = true;
            }
        }
        if (compare && !closest)
            if (const WindingMeter* reader = winding_meter())
            {
                std::optional<GraphPath> held =
                    steer_path(graph, query, winding_rate, *reader, found, traced, stream_field,
                               options, finish);
                if (held)
                {
                    found = std::move(*held);
                    traced = false;
                }
            }
        CutPath cut;
        cut.traced = traced;
        cut.outlet = static_cast<int>(l);
        cut.halfedges = std::move(found.halfedges);
        cut.cost = found.cost;
        cut.start = mesh.from_vertex_handle(cut.halfedges.front());
        cut.end = mesh.to_vertex_handle(cut.halfedges.back());
        cut.parent = l == 1 ? -1 : path_of[cut.end.idx()];
        const int index = static_cast<int>(plan.paths.size());
        path_of[cut.start.idx()] = index;
        for (auto h : cut.halfedges)
        {
            const int w = mesh.to_vertex_handle(h).idx();
            if (path_of[w] < 0)
                path_of[w] = index;
            if (l >= 2 && loop_of[w] < 0)
                query.is_target[w] = 1;  // later outlets may end on this cut
        }
        if (l >= 2 && loop_of[cut.start.idx()] < 0)
            query.is_target[cut.start.idx()] = 1;
        // The join rings and the tree distance serve later outlets only.
        if ((streamline || approach) && l + 1 < loops.size())
        {
            std::vector<VertexHandle> on_cut;
            for (auto h : cut.halfedges)
                on_cut.push_back(mesh.to_vertex_handle(h));
            if (streamline)
                grow_rings(
                    graph, on_cut, options.join_rings, [&loop_of](int v) { return loop_of[v] >= 0; },
                    join, &joined);
            tree.defer(mesh, on_cut, loop_of);
        }
        plan.paths.push_back(std::move(cut));
    }
    return plan;
}

}  // namespace vessel
