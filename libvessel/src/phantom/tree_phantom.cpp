#include "vessel/phantom/phantom.h"

#include "detail/implicit_vessel.h"
#include "vessel/core/errors.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace vessel {

using detail::EndPlane;
using detail::VesselField;
using detail::vessel_surface;

void TreePhantomOptions::validate() const
{
    auto fail = [](const std::string& what) {
        throw InvalidInputError("TreePhantomOptions: " + what);
    };
    if (outlets < 1 || outlets > 30)
        fail("outlets must be in [1, 30] (got " + std::to_string(outlets) + ")");
    if (!(root_radius > 0.0))
        fail("root_radius must be > 0");
    if (!(edge_length > 0.0))
        fail("edge_length must be > 0");
    if (edge_length > 0.5 * root_radius)
        fail("edge_length must be <= root_radius / 2 (" + std::to_string(0.5 * root_radius) +
             ")");
}

namespace {

// Draws from std::mt19937, whose output sequence the standard fixes, through hand-written
// distributions (the std:: distributions differ between standard libraries).
class Random
{
public:
    explicit Random(std::uint32_t seed) : engine_(seed) {}
    double uniform(double lo, double hi)
    {
        return lo + (hi - lo) * static_cast<double>(engine_() >> 8) * (1.0 / 16777216.0);
    }
    //! Uniform integer in [0, n).
    int below(int n)
    {
        return static_cast<int>((static_cast<std::uint64_t>(engine_()) * std::uint64_t(n)) >> 32);
    }

private:
    std::mt19937 engine_;
};

// Smallest distance between segments [p0, p1] and [q0, q1] (Ericson, Real-Time Collision
// Detection, 5.1.9).
double segment_distance(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                        const Eigen::Vector3d& q0, const Eigen::Vector3d& q1)
{
    const Eigen::Vector3d d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
    const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
    double s = 0.0, t = 0.0;
    if (a <= 1e-300 && e <= 1e-300)
        return r.norm();
    if (a <= 1e-300)
        t = std::clamp(f / e, 0.0, 1.0);
    else
    {
        const double c = d1.dot(r);
        if (e <= 1e-300)
            s = std::clamp(-c / a, 0.0, 1.0);
        else
        {
            const double b = d1.dot(d2), denom = a * e - b * b;
            s = denom > 1e-14 * a * e ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
            t = (b * s + f) / e;
            if (t < 0.0)
            {
                t = 0.0;
                s = std::clamp(-c / a, 0.0, 1.0);
            }
            else if (t > 1.0)
            {
                t = 1.0;
                s = std::clamp((b - c) / a, 0.0, 1.0);
            }
        }
    }
    return ((p0 + s * d1) - (q0 + t * d2)).norm();
}

struct TreeNode
{
    int parent = -1;
    int outlets = 0;
    double wedge_lo = 0.0, wedge_hi = 0.0;  // angular sector of the subtree, radians from +y
    double rho = 0.0;                       // distance from the first bifurcation, in the plane
    double radius = 0.0;                    // radius of the vessel ending at this node
    Eigen::Vector3d position = Eigen::Vector3d::Zero();
    std::vector<int> children;
};

// One attempt at laying out the tree: a radial layout in which every subtree keeps to its own
// angular sector, sized by its outlet count, and every node lies farther from the first
// bifurcation than its parent, so that subtrees cannot cross; a little out-of-plane jitter keeps
// it from being flat. Returns false if a clearance, branching-angle or bend check fails.
bool layout_tree(const TreePhantomOptions& o, Random& random, double scale, double h,
                 double blend, std::vector<TreeNode>& nodes)
{
    const int N = o.outlets;
    const double r_min = 2.0 * o.edge_length;
    auto radius_of = [&](int n) { return std::max(o.root_radius * std::cbrt(double(n) / N), r_min); };
    const double half_wedge = 75.0 * M_PI / 180.0;

    nodes.clear();
    TreeNode inlet;
    inlet.position = Eigen::Vector3d(0, -6.0 * o.root_radius * scale, 0);
    nodes.push_back(inlet);
    TreeNode first;
    first.parent = 0;
    first.outlets = N;
    first.wedge_lo = -half_wedge;
    first.wedge_hi = half_wedge;
    first.radius = o.root_radius;
    nodes.push_back(first);
    nodes[0].children.push_back(1);

    for (std::size_t k = 1; k < nodes.size(); ++k)  // breadth-first; nodes grows as we go
    {
        const int n = nodes[k].outlets;
        if (n == 1)
            continue;
        const int lo = std::max(1, n / 4), hi = std::min(n - 1, n - n / 4);
        const int n1 = lo + random.below(hi - lo + 1);
        const double width = nodes[k].wedge_hi - nodes[k].wedge_lo;
        const double split = nodes[k].wedge_lo + width * n1 / n;
        for (int side = 0; side < 2; ++side)
        {
            TreeNode child;
            child.parent = static_cast<int>(k);
            child.outlets = side == 0 ? n1 : n - n1;
            child.wedge_lo = side == 0 ? nodes[k].wedge_lo : split;
            child.wedge_hi = side == 0 ? split : nodes[k].wedge_hi;
            child.radius = radius_of(child.outlets);
            const double child_width = child.wedge_hi - child.wedge_lo;
            const double phi = 0.5 * (child.wedge_lo + child.wedge_hi) +
                               random.uniform(-0.15, 0.15) * child_width;
            double length = random.uniform(3.5, 6.0) * nodes[k].radius * scale;
            length = std::max(length, 2.5 * nodes[k].radius + 2.5 * child.radius + 4.0 * h);
            // Far enough out for the vessel to fit inside its own sector.
            const double needed = (1.3 * child.radius + 1.5 * h + 0.5 * blend) /
                                  std::sin(std::min(0.5 * child_width, 1.2));
            child.rho = std::max(nodes[k].rho + length, needed);
            const double z = nodes[k].position.z() +
                             random.uniform(-0.15, 0.15) * (child.rho - nodes[k].rho);
            child.position = Eigen::Vector3d(child.rho * std::sin(phi), child.rho * std::cos(phi), z);
            nodes[k].children.push_back(static_cast<int>(nodes.size()));
            nodes.push_back(child);
        }
    }

    // Segment k runs from its parent to node k; outlets and inlet include their capped overshoot.
    struct Segment
    {
        Eigen::Vector3d a, b;
        double r;
        int from, to;
    };
    std::vector<Segment> segments;
    for (std::size_t k = 1; k < nodes.size(); ++k)
    {
        Eigen::Vector3d a = nodes[nodes[k].parent].position, b = nodes[k].position;
        const double r = nodes[k].radius;
        const Eigen::Vector3d dir = (b - a).normalized();
        if (nodes[k].children.empty())
            b += (2.0 * r + 3.0 * h) * dir;
        if (nodes[k].parent == 0)
            a -= (2.0 * r + 3.0 * h) * dir;
        segments.push_back({a, b, r, nodes[k].parent, static_cast<int>(k)});
    }
    for (std::size_t i = 0; i < segments.size(); ++i)
        for (std::size_t j = i + 1; j < segments.size(); ++j)
        {
            const auto &s = segments[i], &t = segments[j];
            const bool adjacent =
                s.from == t.from || s.from == t.to || s.to == t.from || s.to == t.to;
            if (adjacent)
            {
                // Siblings must diverge; a child must not fold back onto its parent.
                const Eigen::Vector3d ds = (s.b - s.a).normalized(), dt = (t.b - t.a).normalized();
                const double cos_angle = ds.dot(dt);
                if (s.from == t.from && cos_angle > std::cos(25.0 * M_PI / 180.0))
                    return false;
                if ((s.to == t.from || t.to == s.from) && cos_angle < std::cos(80.0 * M_PI / 180.0))
                    return false;
                continue;
            }
            const double clearance = 1.5 * (s.r + t.r) + 3.0 * h + blend;
            if (segment_distance(s.a, s.b, t.a, t.b) < clearance)
                return false;
        }
    return true;
}

}  // namespace

Mesh tree_phantom(const TreePhantomOptions& options)
{
    options.validate();
    const double h = options.edge_length;
    const double r_min = std::max(options.root_radius * std::cbrt(1.0 / options.outlets),
                                  2.0 * options.edge_length);
    const double blend = 0.4 * r_min;
    Random random(options.seed);
    std::vector<TreeNode> nodes;
    bool found = false;
    for (int attempt = 0; attempt < 200 && !found; ++attempt)
        found = layout_tree(options, random, std::pow(1.05, attempt / 10), h, blend, nodes);
    if (!found)
        throw TopologyError("tree_phantom: could not lay out " + std::to_string(options.outlets) +
                            " outlets without overlapping vessels; try another seed");

    VesselField field(blend, 3.0 * h + blend);
    std::vector<EndPlane> ends;
    for (std::size_t k = 1; k < nodes.size(); ++k)
    {
        const TreeNode& node = nodes[k];
        Eigen::Vector3d a = nodes[node.parent].position, b = node.position;
        const Eigen::Vector3d dir = (b - a).normalized();
        const double r = node.radius, overshoot = r + 3.0 * h;
        if (node.parent == 0)
        {
            ends.push_back({a, -dir, r, overshoot + r});
            a -= overshoot * dir;
        }
        if (node.children.empty())
        {
            ends.push_back({b, dir, r, overshoot + r});
            b += overshoot * dir;
        }
        field.add_tube(a, b, [r](double) { return r; });
    }
    return vessel_surface(field, ends, h, "tree_phantom");
}

}  // namespace vessel
