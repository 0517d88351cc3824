#include "vessel/cut/cut_join.h"

#include "detail/tree_distance.h"

#include <Eigen/Geometry>

#include <cmath>
#include <cstdint>
#include <unordered_map>

namespace vessel {

namespace {

using detail::ReadZone;
using detail::TreeDistance;
using detail::zones_along;

// CutJoin::Approach: \p path cut back at its first vertex v within \p reach of the cut tree
// whose remaining length along the path exceeds its distance to the tree by more than
// \p excess (the path would run on beside the tree), and joined to the tree from v over the
// shortest bridge (tree.via); unchanged if there is no such vertex. With \p keeps, the first
// such vertex whose joined path \p keeps accepts (a held route's bound: the bridge may turn
// round the vessel where the route does not), unchanged if none is.
//
// The tree distance is read only as far as a vertex could pass: at vertex i, up to
// min(reach, left - excess), and not at all where the straight distance to the nearest tree
// vertex (which the edge-path distance cannot undercut) already exceeds that. When there is
// such a read, \p tree grows a scratch copy of its field only on the routes that can reach the
// reading vertices within their zone's read (TreeDistance::near_zones()); when there is none
// the path is kept as is.
GraphPath cut_back(const CutGraph& graph, const GraphPath& path, TreeDistance& tree,
                   const std::vector<int>& loop_of, double reach, double excess,
                   const PathTest* keeps = nullptr)
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
        GraphPath joined = graph.path_of(std::move(halfedges));
        if (!keeps || (*keeps)(joined))
            return joined;
    }
    return path;
}

class ApproachJoiner : public CutJoiner
{
public:
    explicit ApproachJoiner(const CutPlanContext& context)
    {
        tree_.reset(context.mesh().n_vertices());
    }

    GraphPath finish(const CutStep& step, GraphPath path) override
    {
        return cut_back_from(step, path, step.context().options->join_excess);
    }

    GraphPath finish_held(const CutStep& step, GraphPath path, const PathTest& keeps) override
    {
        return cut_back_from(step, path, step.context().options->join_held_excess, &keeps);
    }

    void added(const CutStep& step, const CutPath& cut) override
    {
        const CutPlanContext& context = step.context();
        if (step.outlet() + 1 >= context.loops->size())
            return;  // the tree distance serves later outlets only
        const Mesh& mesh = context.mesh();
        std::vector<VertexHandle> on_cut;
        for (auto h : cut.halfedges)
            on_cut.push_back(mesh.to_vertex_handle(h));
        tree_.defer(mesh, on_cut, *context.loop_of);
    }

private:
    // cut_back() of \p path within CutPlanOptions::join_reach and \p excess outlet radii.
    GraphPath cut_back_from(const CutStep& step, const GraphPath& path, double excess,
                            const PathTest* keeps = nullptr)
    {
        const CutPlanContext& context = step.context();
        const double radius = (*context.loops)[step.outlet()].radius();
        return cut_back(*context.graph, path, tree_, *context.loop_of,
                        context.options->join_reach * radius, excess * radius, keeps);
    }

    TreeDistance tree_;
};

}  // namespace

std::unique_ptr<CutJoiner> ApproachJoin::start(const CutPlanContext& context) const
{
    return std::make_unique<ApproachJoiner>(context);
}

}  // namespace vessel
