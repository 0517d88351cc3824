#include "detail/streamline_tracer.h"

#include "vessel/core/errors.h"
#include "vessel/cut/streamline.h"

#include <limits>
#include <string>

namespace vessel::detail {

StreamlineTracer::StreamlineTracer(const CutPlanContext& context)
{
    const Mesh& mesh = context.mesh();
    const std::size_t nv = mesh.n_vertices();
    if (static_cast<std::size_t>(context.stream_field->rows()) != nv)
        throw InvalidInputError(
            "plan_cuts: the streamline route needs a stream field with one "
            "row per vertex (" +
            std::to_string(nv) + "), got " + std::to_string(context.stream_field->rows()));
    mean_edge_ = mean_edge_length(mesh);
    join_.assign(nv, -1);
    stop_at_.assign(nv, 0);
    ring_.assign(nv, -1);
    band_.is_blocked.assign(nv, 1);
    tree_.reset(nv);
}

std::optional<GraphPath> StreamlineTracer::trace(const CutStep& step, VertexHandle start,
                                                 const Eigen::MatrixX3d* field)
{
    const CutPlanContext& context = step.context();
    CutGraph& graph = *context.graph;
    const Mesh& mesh = graph.mesh();
    const PathQuery& query = step.query();
    const std::vector<int>& loop_of = *context.loop_of;
    const std::size_t l = step.outlet();
    if (l == 1)
        stop_at_ = query.is_target;
    else if (l == 2)
        for (std::size_t v = 0; v < stop_at_.size(); ++v)
            stop_at_[v] = join_[v] >= 0;
    else
        for (int v : joined_)
            stop_at_[v] = 1;
    joined_.clear();
    TreeDistance* tree = l == 1 ? nullptr : &tree_;
    const double slack = context.options->join_rings * mean_edge_;

    const Streamline line =
        trace_streamline(mesh, field ? *field : *context.stream_field, start, stop_at_);
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
        const EdgeDistance* reached = nullptr;
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
    in_band_.clear();
    grow_rings(
        graph, seeds, context.options->band_rings, [](int) { return false; }, ring_, &in_band_);

    // The band's query: the outlet's targets, every vertex outside the band blocked, and the
    // loop's other vertices: the cut opens its loop at `start` only, with no step along the rim
    // (boundary edges).
    band_.sources = {start};
    band_.tie_tolerance = query.tie_tolerance;
    band_.is_target = query.is_target;
    for (int v : in_band_)
        band_.is_blocked[v] = query.is_blocked.empty() ? 0 : query.is_blocked[v];
    for (auto v : query.sources)
        if (v != start)
            band_.is_blocked[v.idx()] = 1;
    std::optional<GraphPath> path;
    try
    {
        path = graph.shortest_path(band_, *context.winding_rate);
    }
    catch (const InvalidInputError&)
    {
        // no target inside the band
    }
    for (int v : in_band_)
    {
        band_.is_blocked[v] = 1;
        ring_[v] = -1;
    }
    return path;
}

void StreamlineTracer::added(const CutStep& step, const CutPath& cut)
{
    const CutPlanContext& context = step.context();
    if (step.outlet() + 1 >= context.loops->size())
        return;  // the join rings and the tree distance serve later outlets only
    const Mesh& mesh = context.mesh();
    const std::vector<int>& loop_of = *context.loop_of;
    std::vector<VertexHandle> on_cut;
    for (auto h : cut.halfedges)
        on_cut.push_back(mesh.to_vertex_handle(h));
    grow_rings(
        *context.graph, on_cut, context.options->join_rings,
        [&loop_of](int v) { return loop_of[v] >= 0; }, join_, &joined_);
    tree_.defer(mesh, on_cut, loop_of);
}

}  // namespace vessel::detail
