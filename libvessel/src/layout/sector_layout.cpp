#include "detail/layout_frame.h"
#include "vessel/core/errors.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace vessel {

SectorLayout::SectorLayout(double spread_deg, double gap) : spread_deg_(spread_deg), gap_(gap)
{
    if (!(spread_deg > 0.0 && spread_deg <= 85.0))
        throw InvalidInputError("SectorLayout: spread must be in (0, 85] degrees, got " +
                                std::to_string(spread_deg));
    if (!(gap >= 0.0 && gap <= 0.45))
        throw InvalidInputError("SectorLayout: gap must be in [0, 0.45], got " +
                                std::to_string(gap));
}

namespace {

// One cut path (a vessel segment) in the layout's tree of cuts.
struct Node
{
    std::vector<int> children;
    double own_width = 0;  // its outlet's arc length
    double weight = 0;     // outlet perimeter of its whole subtree
    double lo = 0, hi = 0;  // its sector, radians
    double theta = 0;      // its direction, radians
    Eigen::Vector2d base = Eigen::Vector2d::Zero();
    double height = 0;
    double base_width = 0;
    double g_lo = 0, g_span = 1;  // geodesic distance at the strip's base, and its rise
};

Eigen::Vector2d unit(double angle) { return {std::cos(angle), std::sin(angle)}; }

// Splits [lo, hi] among `items` (descending angle in the given order) by weight; returns each
// item's interval.
std::vector<std::pair<double, double>> partition(double lo, double hi,
                                                 const std::vector<double>& weights)
{
    const double total = std::accumulate(weights.begin(), weights.end(), 0.0);
    std::vector<std::pair<double, double>> out;
    double top = hi;
    for (double w : weights)
    {
        const double bottom = top - (hi - lo) * w / total;
        out.emplace_back(bottom, top);
        top = bottom;
    }
    return out;
}

}  // namespace

LayoutResult SectorLayout::place(const LayoutInput& input) const
{
    const auto& paths = input.plan->paths;
    const auto& G = *input.geodesic;
    const std::vector<int> segment = detail::segment_of_loop(input, "SectorLayout");
    const auto key = [&](int k) { return segment[paths[k].outlet]; };  // position on the walk
    std::vector<Node> nodes(paths.size());
    int root = -1;
    for (std::size_t k = 0; k < paths.size(); ++k)
    {
        const int parent = paths[k].parent;
        if (parent >= static_cast<int>(k))
            throw TopologyError("SectorLayout: cut " + std::to_string(k) + " ends on a later cut (" +
                                std::to_string(parent) + "); cuts must be planned in order");
        if (parent < 0 && root >= 0)
            throw TopologyError("SectorLayout: cuts " + std::to_string(root) + " and " +
                                std::to_string(k) + " both end on the inlet; expected one");
        if (parent < 0)
            root = static_cast<int>(k);
        else
            nodes[parent].children.push_back(static_cast<int>(k));
        nodes[k].own_width = input.segments[segment[paths[k].outlet]].arc_length.back();
    }
    if (root < 0)
        throw TopologyError("SectorLayout: no cut ends on the inlet; the cut plan is empty");
    for (std::size_t k = paths.size(); k-- > 0;)
    {
        nodes[k].weight += nodes[k].own_width;
        if (paths[k].parent >= 0)
            nodes[paths[k].parent].weight += nodes[k].weight;
    }
    for (auto& n : nodes)  // walk order = left (large angle) to right
        std::sort(n.children.begin(), n.children.end(),
                  [&](int a, int b) { return key(a) < key(b); });

    // Sectors, top-down (a parent precedes its children). The root points straight up, its own
    // outlet's share centred on the vertical; every other cut points at the middle of its own
    // outlet's share of its sector.
    const double spread = spread_deg_ * M_PI / 180.0;
    Node& r = nodes[root];
    r.theta = 0.5 * M_PI;
    r.lo = r.theta - spread;
    r.hi = r.theta + spread;
    for (std::size_t k = root; k < paths.size(); ++k)
    {
        Node& n = nodes[k];
        std::vector<int> left, right;
        for (int c : n.children)
            (key(c) < key(static_cast<int>(k)) ? left : right).push_back(c);
        const auto weights_of = [&](const std::vector<int>& cs) {
            std::vector<double> w;
            for (int c : cs)
                w.push_back(nodes[c].weight);
            return w;
        };
        std::vector<std::pair<double, double>> left_iv, right_iv;
        if (static_cast<int>(k) == root)
        {
            const double own_half = spread * n.own_width / n.weight;
            if (!left.empty())
                left_iv = partition(n.theta + own_half, n.hi, weights_of(left));
            if (!right.empty())
                right_iv = partition(n.lo, n.theta - own_half, weights_of(right));
        }
        else
        {
            std::vector<double> w = weights_of(left);
            w.push_back(n.own_width);
            const std::vector<double> rw = weights_of(right);
            w.insert(w.end(), rw.begin(), rw.end());
            const auto iv = partition(n.lo, n.hi, w);
            left_iv.assign(iv.begin(), iv.begin() + left.size());
            const auto& own = iv[left.size()];
            n.theta = 0.5 * (own.first + own.second);
            right_iv.assign(iv.begin() + left.size() + 1, iv.end());
        }
        const auto assign = [&](const std::vector<int>& cs,
                                const std::vector<std::pair<double, double>>& iv) {
            for (std::size_t i = 0; i < cs.size(); ++i)
            {
                const double margin = gap_ * (iv[i].second - iv[i].first);
                nodes[cs[i]].lo = iv[i].first + margin;
                nodes[cs[i]].hi = iv[i].second - margin;
            }
        };
        assign(left, left_iv);
        assign(right, right_iv);
    }

    LayoutResult result;
    result.strips.resize(paths.size());
    const BoundarySegment& inlet = input.segments[segment[0]];
    detail::pin_segment(inlet, Eigen::Vector2d::Zero(), -Eigen::Vector2d::UnitY(), result.inlet);
    const auto rise_of = [&](int k) { return G[paths[k].start.idx()] - G[paths[k].end.idx()]; };
    r.base_width = inlet.arc_length.back();
    r.height = std::max(rise_of(root), 0.5 * detail::path_length(*input.mesh, paths[root]));
    for (std::size_t k = root; k < paths.size(); ++k)
    {
        Node& n = nodes[k];
        n.g_lo = G[paths[k].end.idx()];
        n.g_span = std::max(rise_of(static_cast<int>(k)), 1e-12);
        const Eigen::Vector2d d = unit(n.theta);
        result.strips[k] = detail::make_strip(n.base, d, n.height, n.base_width, n.own_width);
        detail::pin_segment(input.segments[segment[paths[k].outlet]], n.base + n.height * d, d,
                            result.outlets);

        // Children hang off this strip's sides at their junction's geodesic fraction, the
        // fractions reordered so that on each side they follow the walk (the left side is walked
        // upward, the right side downward): then sibling sectors never cross.
        std::vector<int> left, right;
        for (int c : n.children)
            (key(c) < key(static_cast<int>(k)) ? left : right).push_back(c);
        const auto place_side = [&](const std::vector<int>& cs, bool is_left) {
            std::vector<double> t;
            for (int c : cs)
                t.push_back(std::clamp((G[paths[c].end.idx()] - n.g_lo) / n.g_span, 0.0, 1.0));
            std::sort(t.begin(), t.end());
            if (!is_left)
                std::reverse(t.begin(), t.end());
            const Strip& s = result.strips[k];
            const Eigen::Vector2d& bottom = is_left ? s[0] : s[1];
            const Eigen::Vector2d& top = is_left ? s[3] : s[2];
            for (std::size_t i = 0; i < cs.size(); ++i)
            {
                Node& c = nodes[cs[i]];
                const Eigen::Vector2d apex = (1.0 - t[i]) * bottom + t[i] * top;
                // The strip must fit the cone of the sector seen from the apex: its base starts
                // where the cone is as wide as the loop.
                const double half = std::min(c.theta - c.lo, c.hi - c.theta);
                const double stem =
                    std::max(0.5 * c.own_width / std::tan(half), 0.1 * c.own_width);
                const double reach = std::max(
                    {rise_of(cs[i]), 0.5 * detail::path_length(*input.mesh, paths[cs[i]]),
                     stem + 0.5 * c.own_width});
                c.base = apex + stem * unit(c.theta);
                c.height = reach - stem;
                c.base_width = c.own_width;
            }
        };
        place_side(left, true);
        place_side(right, false);
    }
    return result;
}

}  // namespace vessel
