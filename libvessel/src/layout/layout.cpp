#include "vessel/layout/layout.h"

#include "detail/layout_frame.h"
#include "vessel/core/errors.h"

#include <algorithm>
#include <cmath>

namespace vessel {

std::vector<BoundarySegment> boundary_segments(const Mesh& mesh, const std::vector<int>& origin,
                                               const std::vector<int>& loop_of_origin)
{
    // A boundary halfedge lies on loop l when both its ends came from loop l: cuts touch each
    // loop at one vertex only, so seam edges never join two vertices of the same loop.
    const auto loop_of = [&](HalfedgeHandle h) {
        const int a = loop_of_origin[origin[mesh.from_vertex_handle(h).idx()]];
        const int b = loop_of_origin[origin[mesh.to_vertex_handle(h).idx()]];
        return a == b ? a : -1;
    };
    HalfedgeHandle start;
    for (auto h : mesh.halfedges())
        if (h.is_boundary() && loop_of(h) == 0 && loop_of(h.prev()) != 0)
        {
            start = h;
            break;
        }
    if (!start.is_valid())
        throw TopologyError("boundary_segments: the inlet loop is not opened by a cut on this "
                            "mesh; cut the mesh first (cut_along_edges)");

    std::vector<BoundarySegment> segments;
    HalfedgeHandle h = start;
    std::size_t steps = 0;
    do
    {
        const int l = loop_of(h);
        if (l >= 0)
        {
            if (segments.empty() || segments.back().loop != l || loop_of(mesh.prev_halfedge_handle(h)) != l)
            {
                BoundarySegment& s = segments.emplace_back();
                s.loop = l;
                s.vertices.push_back(mesh.from_vertex_handle(h));
                s.arc_length.push_back(0.0);
            }
            BoundarySegment& s = segments.back();
            s.arc_length.push_back(s.arc_length.back() + mesh.calc_edge_length(h));
            s.vertices.push_back(mesh.to_vertex_handle(h));
        }
        h = mesh.next_halfedge_handle(h);
        if (++steps > mesh.n_halfedges())
            throw TopologyError("boundary_segments: the boundary walk does not close; the mesh "
                                "connectivity is corrupt");
    } while (h != start);
    return segments;
}

BranchFanLayout::BranchFanLayout(double alpha_deg) : alpha_deg_(alpha_deg)
{
    if (!(alpha_deg >= 0.0 && alpha_deg < 90.0))
        throw InvalidInputError("BranchFanLayout: alpha must be in [0, 90) degrees, got " +
                                std::to_string(alpha_deg));
}

namespace detail {

std::vector<int> segment_of_loop(const LayoutInput& input, const std::string& caller)
{
    std::vector<int> segment(input.loops->size(), -1);
    for (std::size_t i = 0; i < input.segments.size(); ++i)
    {
        int& slot = segment[input.segments[i].loop];
        if (slot >= 0)
            throw TopologyError(caller + ": loop " + std::to_string(input.segments[i].loop) +
                                " is opened in several places; each loop must be cut once");
        slot = static_cast<int>(i);
    }
    for (std::size_t l = 0; l < segment.size(); ++l)
        if (segment[l] < 0)
            throw TopologyError(caller + ": loop " + std::to_string(l) +
                                " is not on the cut mesh's boundary; every loop must be cut");
    return segment;
}

void pin_segment(const BoundarySegment& seg, const Eigen::Vector2d& centre,
                 const Eigen::Vector2d& direction, Pins& pins)
{
    const double length = seg.arc_length.back();
    const Eigen::Vector2d n = left_normal(direction);
    for (std::size_t i = 0; i < seg.vertices.size(); ++i)
        pins.push_back({seg.vertices[i], centre + n * (0.5 * length - seg.arc_length[i])});
}

Strip make_strip(const Eigen::Vector2d& base, const Eigen::Vector2d& direction, double height,
                 double base_width, double top_width)
{
    const Eigen::Vector2d n = left_normal(direction), top = base + height * direction;
    return {base + 0.5 * base_width * n, base - 0.5 * base_width * n, top - 0.5 * top_width * n,
            top + 0.5 * top_width * n};
}

double path_length(const Mesh& mesh, const CutPath& path)
{
    double length = 0.0;
    for (auto h : path.halfedges)
        length += mesh.calc_edge_length(h);
    return length;
}

}  // namespace detail

namespace {

using detail::left_normal;
using detail::rotate;

// The frame of one cut's vessel segment in the plane.
struct Frame
{
    Eigen::Vector2d base;       // where the segment starts (inlet centre or branch point)
    Eigen::Vector2d direction;  // unit, toward the outlet
    double base_distance = 0;   // geodesic distance from the inlet at the base
    double height = 0;          // base to outlet centre
    double base_width = 0;      // strip width at the base
    double top_width = 0;       // strip width at the outlet (its arc length)
};

}  // namespace

LayoutResult BranchFanLayout::place(const LayoutInput& input) const
{
    const auto& paths = input.plan->paths;
    const auto& G = *input.geodesic;
    const std::vector<int> segment_of_loop = detail::segment_of_loop(input, "BranchFanLayout");
    LayoutResult result;
    const BoundarySegment& inlet = input.segments[segment_of_loop[0]];
    const double inlet_length = inlet.arc_length.back();
    // The clockwise walk crosses the inlet from right to left: it is the far end of a strip
    // pointing down.
    detail::pin_segment(inlet, Eigen::Vector2d::Zero(), -Eigen::Vector2d::UnitY(), result.inlet);

    const double alpha = alpha_deg_ * M_PI / 180.0;
    std::vector<Frame> frames(paths.size());
    for (std::size_t k = 0; k < paths.size(); ++k)
    {
        const CutPath& path = paths[k];
        const BoundarySegment& seg = input.segments[segment_of_loop[path.outlet]];
        Frame& f = frames[k];
        f.top_width = seg.arc_length.back();
        const double seam_length = detail::path_length(*input.mesh, path);
        if (path.parent < 0)
        {
            f.base = Eigen::Vector2d::Zero();
            f.direction = Eigen::Vector2d::UnitY();
            f.base_distance = G[path.end.idx()];
            f.base_width = inlet_length;
        }
        else
        {
            const Frame& p = frames[path.parent];
            const double junction = G[path.end.idx()];
            const double t = std::clamp((junction - p.base_distance) / p.height, 0.0, 1.0);
            const double width = (1.0 - t) * p.base_width + t * p.top_width;
            // Branches met before their parent's outlet on the clockwise boundary walk hang off
            // the parent's left side.
            const int parent_loop = paths[path.parent].outlet;
            const double side =
                segment_of_loop[path.outlet] < segment_of_loop[parent_loop] ? 1.0 : -1.0;
            f.base = p.base + t * p.height * p.direction +
                     side * 0.5 * (width + f.top_width) * left_normal(p.direction);
            f.direction = rotate(p.direction, side * alpha);
            f.base_distance = junction;
            f.base_width = f.top_width;
        }
        // The geodesic rise is the height; a cut that climbs little (a side branch leaving
        // sideways) still gets a strip at least half as long as its seam.
        f.height = std::max(G[path.start.idx()] - f.base_distance, 0.5 * seam_length);
        detail::pin_segment(seg, f.base + f.height * f.direction, f.direction, result.outlets);
        result.strips.push_back(
            detail::make_strip(f.base, f.direction, f.height, f.base_width, f.top_width));
    }
    return result;
}

std::unique_ptr<Layout> make_layout(const std::string& name, double alpha_deg)
{
    if (name == "fan")
        return std::make_unique<BranchFanLayout>(alpha_deg);
    if (name == "sector")
        return std::make_unique<SectorLayout>();
    throw InvalidInputError("make_layout: unknown layout '" + name + "'; valid names: fan, sector");
}

}  // namespace vessel
