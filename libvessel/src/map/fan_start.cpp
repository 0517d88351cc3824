#include "vessel/map/fan_start.h"

#include "vessel/core/errors.h"
#include "vessel/map/lscm.h"
#include "vessel/quality/metrics.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace vessel {

void FanStartOptions::validate() const
{
    if (!(spread_deg >= 30.0 && spread_deg <= 89.0))
        throw InvalidInputError("FanStartOptions: spread_deg must be in [30, 89], got " +
                                std::to_string(spread_deg));
    if (!(cut_weight > 0.0 && cut_weight <= 1.0))
        throw InvalidInputError("FanStartOptions: cut_weight must be in (0, 1], got " +
                                std::to_string(cut_weight));
    untangle.validate();
}

namespace {

// The cut mesh's boundary vertices in walk order, starting with the inlet segment's first
// vertex, and the 3D length of each edge (edge i joins walk[i] and walk[i + 1], cyclically).
struct Walk
{
    std::vector<VertexHandle> vertices;
    std::vector<double> length;
};

Walk boundary_walk(const Mesh& mesh, VertexHandle first)
{
    const auto loops = boundary_loops(mesh);
    if (loops.size() != 1)
        throw TopologyError("fan_start: the cut mesh has " + std::to_string(loops.size()) +
                            " boundary loops; a disk (one loop) is required");
    const BoundaryLoop& loop = loops[0];
    const auto at = std::find(loop.vertices.begin(), loop.vertices.end(), first);
    if (at == loop.vertices.end())
        throw TopologyError("fan_start: the inlet is not on the cut mesh's boundary");
    const std::size_t n = loop.vertices.size(), start = at - loop.vertices.begin();
    Walk walk;
    for (std::size_t i = 0; i < n; ++i)
    {
        walk.vertices.push_back(loop.vertices[(start + i) % n]);
        walk.length.push_back(mesh.calc_edge_length(loop.halfedges[(start + i) % n]));
    }
    return walk;
}

// A triangle whose three corners are all on the polygon (e.g. an ear) is inverted where the
// polygon turns the wrong way between them, and no interior motion can fix it: move the
// boundary between its corners across their chord. Corners below `first_free` (the inlet) stay.
void open_reflex_ears(const Mesh& mesh, Pins& pins, std::size_t first_free)
{
    const std::size_t n = pins.size();
    std::vector<int> at(mesh.n_vertices(), -1);
    for (std::size_t i = 0; i < n; ++i)
        at[pins[i].vertex.idx()] = static_cast<int>(i);
    for (auto f : mesh.faces())
    {
        std::array<int, 3> corner;
        int k = 0;
        for (auto v : f.vertices())
            corner[k++] = at[v.idx()];
        if (*std::min_element(corner.begin(), corner.end()) < 0)
            continue;
        const auto p = [&](int c) -> Eigen::Vector2d& { return pins[corner[c]].uv; };
        const auto area = [&] {
            const Eigen::Vector2d e1 = p(1) - p(0), e2 = p(2) - p(0);
            return e1.x() * e2.y() - e1.y() * e2.x();
        };
        if (area() > 0.0)
            continue;
        // The corners' walk positions p0 < p1 < p2 within a short run: lay the run's inner
        // vertices (p0, p2) on an arc across the chord p0-p2, on the side that turns the
        // triangle positive; the run's own ears are then convex too.
        std::array<int, 3> sorted = corner;
        std::sort(sorted.begin(), sorted.end());
        const int p0 = sorted[0], p2 = sorted[2];
        if (p2 - p0 > 8 || p0 + 1 < static_cast<int>(first_free))
            continue;
        const Eigen::Vector2d a = pins[p0].uv, c = pins[p2].uv;
        const Eigen::Vector2d normal(c.y() - a.y(), a.x() - c.x());  // |normal| = |c - a|
        for (double side : {1.0, -1.0})
        {
            for (int j = p0 + 1; j < p2; ++j)
            {
                const double t = static_cast<double>(j - p0) / (p2 - p0);
                pins[j].uv = a + t * (c - a) + side * 0.25 * std::sin(M_PI * t) * normal;
            }
            if (area() > 0.0)
                break;
        }
    }
}

}  // namespace

FanStart fan_start(const LayoutInput& input, const FanStartOptions& options)
{
    options.validate();
    const Mesh& mesh = *input.mesh;
    const auto inlet_at = std::find_if(input.segments.begin(), input.segments.end(),
                                       [](const BoundarySegment& s) { return s.loop == 0; });
    if (inlet_at == input.segments.end() || inlet_at->vertices.size() < 2)
        throw TopologyError("fan_start: the cut mesh's boundary has no inlet segment");
    const BoundarySegment& inlet = *inlet_at;
    const Walk walk = boundary_walk(mesh, inlet.vertices.front());
    const std::size_t n = walk.vertices.size(), n_inlet = inlet.vertices.size();

    // next_on_loop[v]: the vertex after v on its loop segment (edges on loops vs cut sides).
    std::vector<int> next_on_loop(mesh.n_vertices(), -1);
    for (const BoundarySegment& s : input.segments)
        for (std::size_t i = 0; i + 1 < s.vertices.size(); ++i)
            next_on_loop[s.vertices[i].idx()] = s.vertices[i + 1].idx();

    // The inlet, walked right to left, straight at the bottom (its 3D length); the fan's
    // centre below its midpoint, so that the inlet spans 2 x spread seen from the centre.
    const double spread = options.spread_deg * M_PI / 180.0;
    const double half = 0.5 * inlet.arc_length.back();
    const Eigen::Vector2d centre(0.0, -half / std::tan(spread));
    const double rho0 = half / std::sin(spread);  // the inlet's ends from the centre
    Pins pins(n);
    for (std::size_t i = 0; i < n; ++i)
        pins[i].vertex = walk.vertices[i];
    for (std::size_t i = 0; i < n_inlet; ++i)
        pins[i].uv = {half - inlet.arc_length[i], 0.0};

    // The rest, from the inlet's left end round to its right end (clockwise): angle from
    // pi / 2 + spread down to pi / 2 - spread, radius rho0 + geodesic distance, beyond the
    // inlet on every ray from the centre.
    std::vector<double> radius(n + 1);
    for (std::size_t i = n_inlet - 1; i <= n; ++i)
        radius[i] = i == n_inlet - 1 || i == n
                        ? rho0
                        : rho0 + std::max((*input.geodesic)[input.origin[walk.vertices[i].idx()]], 0.0);
    std::vector<double> weight(n, 0.0);
    double total = 0.0;
    for (std::size_t i = n_inlet - 1; i < n; ++i)
    {
        const int to = walk.vertices[(i + 1) % n].idx();
        const bool on_loop = next_on_loop[walk.vertices[i].idx()] == to;
        weight[i] = (on_loop ? 1.0 : options.cut_weight) * std::max(walk.length[i], 1e-12) /
                    (0.5 * (radius[i] + radius[i + 1]));
        total += weight[i];
    }
    double angle = 0.5 * M_PI + spread;
    for (std::size_t i = n_inlet - 1; i + 1 < n; ++i)
    {
        angle -= 2.0 * spread * weight[i] / total;
        pins[i + 1].uv = centre + radius[i + 1] * Eigen::Vector2d(std::cos(angle), std::sin(angle));
    }

    open_reflex_ears(mesh, pins, n_inlet);
    FanStart start;
    start.uv = lscm(mesh, pins);  // all of the boundary pinned: the cotangent-harmonic map
    start.untangle = untangle(mesh, start.uv, pins, options.untangle);
    if (start.untangle.flipped_after > 0)
    {
        // Left over in the polygon's crotch notches: free the boundary but the inlet; the
        // caller checks that it stays simple.
        pins.resize(n_inlet);
        const int before = start.untangle.flipped_before;
        start.untangle = untangle(mesh, start.uv, pins, options.untangle);
        start.untangle.flipped_before = before;
    }
    scale_to_surface_area(mesh, start.uv);
    return start;
}

}  // namespace vessel
