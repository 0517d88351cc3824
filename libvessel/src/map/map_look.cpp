#include "vessel/map/map_look.h"

#include "vessel/core/errors.h"
#include "vessel/quality/metrics.h"
#include "detail/uv_rows.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace vessel {

namespace {

// The frame of an inlet chord: origin at its midpoint, +u from its left to its right end,
// +v to the side the map lies on.
struct InletFrame
{
    Eigen::Vector2d origin, right, up;

    Eigen::Vector2d local(const Eigen::Vector2d& p) const
    {
        const Eigen::Vector2d d = p - origin;
        return {d.dot(right), d.dot(up)};
    }
    // 0 = up, +90 = right, +-180 = down.
    double bearing_deg(const Eigen::Vector2d& p) const
    {
        const Eigen::Vector2d q = local(p);
        return std::atan2(q.x(), q.y()) * 180.0 / M_PI;
    }
};

InletFrame inlet_frame(const Eigen::Vector2d& right, const Eigen::Vector2d& left)
{
    const Eigen::Vector2d chord = right - left;
    if (!(chord.norm() > 0.0))
        throw InvalidInputError("map_look: the inlet's two ends coincide; the map (or layout) is "
                                "degenerate at the inlet");
    InletFrame frame;
    frame.origin = 0.5 * (right + left);
    frame.right = chord.normalized();
    frame.up = Eigen::Vector2d(-frame.right.y(), frame.right.x());
    return frame;
}

double wrapped_deg(double a)
{
    while (a > 180.0)
        a -= 360.0;
    while (a <= -180.0)
        a += 360.0;
    return a;
}

int sign(double x) { return (x > 0.0) - (x < 0.0); }

// One side (the map or the layout) read from its own inlet chord: the frame and every loop's
// centre (mean of its vertices' positions; count 0 = the loop has no segment).
struct LoopView
{
    InletFrame frame;
    std::vector<Eigen::Vector2d> centre;
    std::vector<int> count;
};

LoopView loop_view(const Eigen::MatrixX2d& at, const std::vector<BoundarySegment>& segments)
{
    const BoundarySegment* inlet = nullptr;
    int loops = 0;
    for (const BoundarySegment& s : segments)
    {
        if (s.loop == 0 && !s.vertices.empty())
            inlet = &s;
        loops = std::max(loops, s.loop + 1);
    }
    if (!inlet)
        throw InvalidInputError("map_look: no inlet segment (loop 0); pass boundary_segments() "
                                "of the cut mesh");
    LoopView view;
    view.centre.assign(loops, Eigen::Vector2d::Zero());
    view.count.assign(loops, 0);
    for (const BoundarySegment& s : segments)
        for (VertexHandle v : s.vertices)
        {
            view.centre[s.loop] += at.row(v.idx()).transpose();
            ++view.count[s.loop];
        }
    for (std::size_t l = 0; l < view.centre.size(); ++l)
        if (view.count[l] > 0)
            view.centre[l] /= view.count[l];
    // The inlet's first vertex is its right end, its last its left end.
    view.frame = inlet_frame(at.row(inlet->vertices.front().idx()).transpose(),
                             at.row(inlet->vertices.back().idx()).transpose());
    return view;
}

// The layout's pins as a |V| x 2 matrix; every loop vertex of \p segments must have one.
Eigen::MatrixX2d pinned_layout(int n, const std::vector<BoundarySegment>& segments,
                               const LayoutResult& layout)
{
    Eigen::MatrixX2d placed = Eigen::MatrixX2d::Zero(n, 2);
    std::vector<char> has_pin(n, 0);
    for (const Pins* pins : {&layout.inlet, &layout.outlets})
        for (const Pin& pin : *pins)
            if (pin.vertex.is_valid() && pin.vertex.idx() < n)
            {
                placed.row(pin.vertex.idx()) = pin.uv.transpose();
                has_pin[pin.vertex.idx()] = 1;
            }
    for (const BoundarySegment& s : segments)
        for (VertexHandle v : s.vertices)
            if (!has_pin[v.idx()])
                throw InvalidInputError("map_look: vertex " + std::to_string(v.idx()) + " of loop " +
                                        std::to_string(s.loop) +
                                        " has no layout pin; pass the layout of this cut mesh");
    return placed;
}

}  // namespace

std::vector<double> layout_bearings(const Mesh& mesh,
                                    const std::vector<BoundarySegment>& segments,
                                    const LayoutResult& layout)
{
    const LoopView view =
        loop_view(pinned_layout(static_cast<int>(mesh.n_vertices()), segments, layout), segments);
    std::vector<double> bearing(view.centre.size(), 0.0);
    for (std::size_t l = 1; l < view.centre.size(); ++l)
        if (view.count[l] > 0)
            bearing[l] = view.frame.bearing_deg(view.centre[l]);
    return bearing;
}

MapLook map_look(const Mesh& mesh, const Eigen::MatrixX2d& uv,
                 const std::vector<BoundarySegment>& segments, const LayoutResult& layout)
{
    detail::require_uv_rows(mesh, uv, "map_look");
    const LoopView map = loop_view(uv, segments);
    const LoopView planned =
        loop_view(pinned_layout(static_cast<int>(mesh.n_vertices()), segments, layout), segments);
    const InletFrame& map_frame = map.frame;
    const int loops = static_cast<int>(map.centre.size());

    MapLook look;
    double area = 0.0, below = 0.0;
    for (auto f : mesh.faces())
    {
        Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
        for (auto v : f.vertices())
            centroid += uv.row(v.idx()).transpose() / 3.0;
        const double a = std::abs(signed_uv_area(mesh, uv, f));
        area += a;
        if (map_frame.local(centroid).y() < 0.0)
            below += a;
    }
    look.area_below_inlet = area > 0.0 ? below / area : 0.0;
    std::vector<int> rank(loops, -1);
    int walked = 0;
    for (const BoundarySegment& s : segments)
        if (s.loop > 0 && rank[s.loop] < 0)
            rank[s.loop] = walked++;
    for (int l = 1; l < loops; ++l)
    {
        if (map.count[l] == 0)
            continue;
        OutletLook o;
        o.loop = l;
        o.walk_rank = rank[l];
        o.map_bearing_deg = map_frame.bearing_deg(map.centre[l]);
        o.layout_bearing_deg = planned.frame.bearing_deg(planned.centre[l]);
        o.below_inlet = map_frame.local(map.centre[l]).y() < 0.0;
        look.outlets_below_inlet += o.below_inlet;
        const double error = std::abs(wrapped_deg(o.map_bearing_deg - o.layout_bearing_deg));
        look.mean_bearing_error_deg += error;
        look.max_bearing_error_deg = std::max(look.max_bearing_error_deg, error);
        look.outlet_looks.push_back(o);
    }
    look.outlets = static_cast<int>(look.outlet_looks.size());
    if (look.outlets > 0)
        look.mean_bearing_error_deg /= look.outlets;
    long concordant = 0, discordant = 0;
    for (int i = 0; i < look.outlets; ++i)
        for (int j = i + 1; j < look.outlets; ++j)
        {
            const OutletLook &a = look.outlet_looks[i], &b = look.outlet_looks[j];
            const int s = sign(a.layout_bearing_deg - b.layout_bearing_deg) *
                          sign(a.map_bearing_deg - b.map_bearing_deg);
            concordant += s > 0;
            discordant += s < 0;
            if (sign(a.layout_bearing_deg - b.layout_bearing_deg) != 0 && s <= 0)
                ++look.fan_inversions;
            if (sign(a.walk_rank - b.walk_rank) * sign(a.map_bearing_deg - b.map_bearing_deg) <= 0)
                ++look.walk_inversions;
        }
    if (concordant + discordant > 0)
        look.fan_kendall_tau = double(concordant - discordant) / double(concordant + discordant);
    return look;
}

}  // namespace vessel
