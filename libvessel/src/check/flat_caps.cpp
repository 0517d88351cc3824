#include "detail/flat_caps.h"

#include "detail/edge_groups.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <utility>

namespace vessel::detail {

namespace {

// Each triangle's neighbour across its edge k (corners k and k + 1), -1 on the boundary.
std::vector<std::array<int, 3>> neighbours(const std::vector<std::array<int, 3>>& triangles,
                                           std::size_t n_vertices)
{
    const EdgeGroups edges = edge_groups(triangles, n_vertices);
    std::vector<std::array<int, 3>> across(triangles.size(), {-1, -1, -1});
    for (std::size_t e = 0; e < edges.size(); ++e)
        if (edges.count(e) == 2)
        {
            const int a = edges.begin(e)[0], b = edges.begin(e)[1];
            across[a / 3][a % 3] = b / 3;
            across[b / 3][b % 3] = a / 3;
        }
    return across;
}

double angle_deg(const Eigen::Vector3d& a, const Eigen::Vector3d& b)
{
    return std::atan2(a.cross(b).norm(), a.dot(b)) * 180.0 / M_PI;
}

}  // namespace

std::vector<FlatCap> find_flat_caps(const std::vector<Eigen::Vector3d>& points,
                                    const std::vector<std::array<int, 3>>& triangles,
                                    double coplanar_deg, double min_rim_deg, double mean_rim_deg,
                                    int min_rim_edges)
{
    const std::size_t n = triangles.size();
    std::vector<Eigen::Vector3d> normal(n);
    std::vector<double> area(n);
    for (std::size_t t = 0; t < n; ++t)
    {
        const auto& [a, b, c] = triangles[t];
        const Eigen::Vector3d cross = (points[b] - points[a]).cross(points[c] - points[a]);
        area[t] = 0.5 * cross.norm();
        normal[t] = area[t] > 0.0 ? Eigen::Vector3d(cross.normalized()) : Eigen::Vector3d::Zero();
    }
    const std::vector<std::array<int, 3>> across = neighbours(triangles, points.size());

    std::vector<FlatCap> caps;
    std::vector<int> patch_of(n, -1);
    std::vector<int> members, vertices;
    for (std::size_t seed = 0; seed < n; ++seed)
    {
        if (patch_of[seed] >= 0 || area[seed] <= 0.0)
            continue;
        // The planar patch of the seed: faces whose normals are within coplanar_deg of the
        // seed's, reached across edges.
        members.assign(1, static_cast<int>(seed));
        patch_of[seed] = static_cast<int>(seed);
        for (std::size_t i = 0; i < members.size(); ++i)
            for (const int u : across[members[i]])
                if (u >= 0 && patch_of[u] < 0 && area[u] > 0.0 &&
                    angle_deg(normal[seed], normal[u]) <= coplanar_deg)
                {
                    patch_of[u] = static_cast<int>(seed);
                    members.push_back(u);
                }
        // A disk inside the surface whose rim is a crease.
        bool open_end = false;
        int rim_edges = 0, inner_edges = 0;
        double rim_sum = 0.0, rim_min = 180.0;
        vertices.clear();
        for (const int t : members)
            for (int k = 0; k < 3; ++k)
            {
                vertices.push_back(triangles[t][k]);
                const int u = across[t][k];
                if (u < 0)
                    open_end = true;
                else if (patch_of[u] != static_cast<int>(seed))
                {
                    const double rim = angle_deg(normal[t], normal[u]);
                    ++rim_edges;
                    rim_sum += rim;
                    rim_min = std::min(rim_min, rim);
                }
                else
                    ++inner_edges;
            }
        if (open_end || rim_edges < min_rim_edges)
            continue;
        std::sort(vertices.begin(), vertices.end());
        const long v = std::unique(vertices.begin(), vertices.end()) - vertices.begin();
        const long e = rim_edges + inner_edges / 2;
        const long f = static_cast<long>(members.size());
        // One rim loop: a disk's rim has as many vertices as edges, so V - E + F = 1 with the
        // rim's vertices each on one loop. Two loops (an annulus) give 0.
        if (v - e + f != 1 || rim_min < min_rim_deg || rim_sum / rim_edges < mean_rim_deg)
            continue;
        FlatCap cap;
        cap.triangles = members;
        std::sort(cap.triangles.begin(), cap.triangles.end());
        for (const int t : members)
            cap.area += area[t];
        cap.mean_rim_angle_deg = rim_sum / rim_edges;
        caps.push_back(std::move(cap));
    }
    return caps;
}

}  // namespace vessel::detail
