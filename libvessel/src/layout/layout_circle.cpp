#include "vessel/layout/layout_circle.h"

#include "vessel/core/errors.h"
#include "vessel/map/injective.h"
#include "vessel/map/map_look.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace vessel {

void LayoutCircleOptions::validate() const
{
    if (!(min_gap_fraction > 0.0 && min_gap_fraction <= 1.0))
        throw InvalidInputError("LayoutCircleOptions: min_gap_fraction must be in (0, 1], got " +
                                std::to_string(min_gap_fraction));
    if (!(bearing_scale > 0.0 && bearing_scale <= 2.0))
        throw InvalidInputError("LayoutCircleOptions: bearing_scale must be in (0, 2], got " +
                                std::to_string(bearing_scale));
    if (!(pull >= 0.0 && pull <= 1.0))
        throw InvalidInputError("LayoutCircleOptions: pull must be in [0, 1], got " +
                                std::to_string(pull));
}

namespace {

// Least-squares nondecreasing fit of y (weights w), pool-adjacent-violators.
std::vector<double> isotonic(const std::vector<double>& y, const std::vector<double>& w)
{
    struct Block
    {
        double mean, weight;
        int size;
    };
    std::vector<Block> blocks;
    for (std::size_t i = 0; i < y.size(); ++i)
    {
        blocks.push_back({y[i], w[i], 1});
        while (blocks.size() > 1 && blocks[blocks.size() - 2].mean > blocks.back().mean)
        {
            const Block b = blocks.back();
            blocks.pop_back();
            Block& a = blocks.back();
            a.mean = (a.mean * a.weight + b.mean * b.weight) / (a.weight + b.weight);
            a.weight += b.weight;
            a.size += b.size;
        }
    }
    std::vector<double> fit;
    for (const Block& b : blocks)
        fit.insert(fit.end(), b.size, b.mean);
    return fit;
}

}  // namespace

Eigen::MatrixX2d layout_circle_start(const LayoutInput& input, const LayoutResult& placed,
                                     const LayoutCircleOptions& options)
{
    options.validate();
    const Mesh& mesh = *input.mesh;
    const auto loops = boundary_loops(mesh);
    if (loops.size() != 1 || input.segments.empty() || input.segments.front().loop != 0)
        throw TopologyError("layout_circle_start: the cut mesh must be a disk whose boundary "
                            "segments start with the inlet; cut the tree first");
    const BoundaryLoop& loop = loops[0];
    const int n = static_cast<int>(loop.vertices.size());
    // The walk from the inlet's first vertex, with its arc length.
    const auto first = std::find(loop.vertices.begin(), loop.vertices.end(),
                                 input.segments.front().vertices.front());
    if (first == loop.vertices.end())
        throw TopologyError("layout_circle_start: the inlet is not on the cut mesh's boundary");
    const int start = static_cast<int>(first - loop.vertices.begin());
    std::vector<VertexHandle> walk(n);
    std::vector<double> s(n + 1, 0.0);
    for (int i = 0; i < n; ++i)
    {
        walk[i] = loop.vertices[(start + i) % n];
        s[i + 1] = s[i] + mesh.calc_edge_length(loop.halfedges[(start + i) % n]);
    }
    const double total = s[n];
    std::vector<int> at(mesh.n_vertices(), -1);  // position in the walk
    for (int i = 0; i < n; ++i)
        at[walk[i].idx()] = i;
    // Each segment as a run [begin, end] of walk positions, in walk order.
    struct Run
    {
        int begin, end;
        double width, target;  // degrees of bearing
    };
    std::vector<Run> runs;
    for (const BoundarySegment& seg : input.segments)
    {
        const int b = at[seg.vertices.front().idx()], e = at[seg.vertices.back().idx()];
        if (b < 0 || e < b || e - b + 1 != static_cast<int>(seg.vertices.size()))
            throw TopologyError("layout_circle_start: loop " + std::to_string(seg.loop) +
                                " is not a run of the boundary walk; pass boundary_segments() "
                                "of this cut mesh");
        runs.push_back({b, e, 360.0 * (s[e] - s[b]) / total, 0.0});
    }
    // Layout bearings (0 = up, clockwise), unwrapped so that the walk, which starts at the
    // inlet's right end (bearing 180 - w0 / 2), meets them increasing.
    const std::vector<double> bearing = layout_bearings(mesh, input.segments, placed);
    const double w0 = runs[0].width;
    runs[0].target = 180.0;
    for (std::size_t k = 1; k < runs.size(); ++k)
    {
        const double b =
            options.bearing_scale * bearing[static_cast<std::size_t>(input.segments[k].loop)];
        // Bearings past the inlet's ends (pointing below it) go to the ends' side.
        const double layout_target = 360.0 + std::clamp(b, -180.0 + 0.5 * w0, 180.0 - 0.5 * w0);
        const double tutte = 180.0 - 0.5 * w0 +
                             360.0 * 0.5 * (s[runs[k].begin] + s[runs[k].end]) / total;
        runs[k].target = tutte + options.pull * (layout_target - tutte);
    }
    // Minimal spacing of consecutive centres: half widths + the gap's minimal angle.
    const auto gap_deg = [&](std::size_t k) {  // the cut sides after run k
        const int from = runs[k].end;
        const double to = k + 1 < runs.size() ? s[runs[k + 1].begin] : total;
        return 360.0 * (to - s[from]) / total;
    };
    const std::size_t m = runs.size();
    std::vector<double> offset(m, 0.0), y(m - 1), weight(m - 1);
    for (std::size_t k = 1; k < m; ++k)
        offset[k] = offset[k - 1] + 0.5 * (runs[k - 1].width + runs[k].width) +
                    options.min_gap_fraction * gap_deg(k - 1);
    for (std::size_t k = 1; k < m; ++k)
    {
        y[k - 1] = runs[k].target - offset[k];
        weight[k - 1] = std::max(runs[k].width, 1e-9);
    }
    std::vector<double> t = isotonic(y, weight);
    const double lo = 180.0;
    const double hi = 540.0 - 0.5 * w0 - 0.5 * runs[m - 1].width -
                      options.min_gap_fraction * gap_deg(m - 1) - offset[m - 1];
    for (double& v : t)
        v = std::clamp(v, lo, std::max(lo, hi));
    // Bearing of every walk position: loops linear in arc length around their centres, the
    // cut sides between them linear in arc length.
    std::vector<double> beta(n + 1, 0.0);
    std::vector<double> centre(m);
    centre[0] = 180.0;
    for (std::size_t k = 1; k < m; ++k)
        centre[k] = t[k - 1] + offset[k];
    const auto fill = [&](int b, int e, double from, double to) {
        for (int i = b; i <= e; ++i)
            beta[i] = s[e] > s[b] ? from + (to - from) * (s[i] - s[b]) / (s[e] - s[b]) : from;
    };
    for (std::size_t k = 0; k < m; ++k)
    {
        const double b0 = centre[k] - 0.5 * runs[k].width, b1 = centre[k] + 0.5 * runs[k].width;
        fill(runs[k].begin, runs[k].end, b0, b1);
        const int next = k + 1 < m ? runs[k + 1].begin : n;
        const double next_b = k + 1 < m ? centre[k + 1] - 0.5 * runs[k + 1].width
                                        : 180.0 - 0.5 * w0 + 360.0;
        fill(runs[k].end, next, b1, next_b);
    }
    const double radius = total / (2.0 * M_PI);
    Pins boundary;
    for (int i = 0; i < n; ++i)
    {
        const double phi = (90.0 - beta[i]) * M_PI / 180.0;
        boundary.push_back({walk[i], {radius * std::cos(phi), radius * std::sin(phi)}});
    }
    return tutte_embedding(mesh, boundary);
}

}  // namespace vessel
