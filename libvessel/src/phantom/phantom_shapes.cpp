#include "vessel/phantom/phantom.h"

#include "vessel/core/errors.h"

#include <array>
#include <cmath>
#include <map>
#include <utility>
#include <vector>

namespace vessel {

namespace {

// Adds the two triangles of quad (a, b, c, d), counter-clockwise seen from outside.
void add_quad(Mesh& mesh, VertexHandle a, VertexHandle b, VertexHandle c, VertexHandle d)
{
    mesh.add_face(a, b, c);
    mesh.add_face(a, c, d);
}

}  // namespace

Mesh open_cylinder(double radius, double length, int n_around, int n_along)
{
    if (radius <= 0 || length <= 0 || n_around < 3 || n_along < 1)
        throw InvalidInputError("open_cylinder: need radius > 0, length > 0, n_around >= 3, "
                                "n_along >= 1");
    Mesh mesh;
    std::vector<VertexHandle> v((n_along + 1) * n_around);
    for (int j = 0; j <= n_along; ++j)
        for (int i = 0; i < n_around; ++i)
        {
            const double t = 2.0 * M_PI * i / n_around;
            v[j * n_around + i] = mesh.add_vertex(
                {radius * std::cos(t), radius * std::sin(t), length * j / n_along});
        }
    for (int j = 0; j < n_along; ++j)
        for (int i = 0; i < n_around; ++i)
        {
            const int i1 = (i + 1) % n_around;
            add_quad(mesh, v[j * n_around + i], v[j * n_around + i1], v[(j + 1) * n_around + i1],
                     v[(j + 1) * n_around + i]);
        }
    return mesh;
}

Mesh torus(double R, double r, int n_major, int n_minor)
{
    if (R <= r || r <= 0 || n_major < 3 || n_minor < 3)
        throw InvalidInputError("torus: need R > r > 0 and at least 3 segments each way");
    Mesh mesh;
    std::vector<VertexHandle> v(n_major * n_minor);
    for (int i = 0; i < n_major; ++i)
        for (int j = 0; j < n_minor; ++j)
        {
            const double u = 2.0 * M_PI * i / n_major, w = 2.0 * M_PI * j / n_minor;
            v[i * n_minor + j] = mesh.add_vertex({(R + r * std::cos(w)) * std::cos(u),
                                                  (R + r * std::cos(w)) * std::sin(u),
                                                  r * std::sin(w)});
        }
    for (int i = 0; i < n_major; ++i)
        for (int j = 0; j < n_minor; ++j)
        {
            const int i1 = (i + 1) % n_major, j1 = (j + 1) % n_minor;
            add_quad(mesh, v[i * n_minor + j], v[i1 * n_minor + j], v[i1 * n_minor + j1],
                     v[i * n_minor + j1]);
        }
    return mesh;
}

Mesh icosphere(double radius, int subdivisions)
{
    if (radius <= 0 || subdivisions < 0)
        throw InvalidInputError("icosphere: need radius > 0 and subdivisions >= 0");
    const double p = (1.0 + std::sqrt(5.0)) / 2.0;
    std::vector<Eigen::Vector3d> points = {{-1, p, 0}, {1, p, 0},  {-1, -p, 0}, {1, -p, 0},
                                           {0, -1, p}, {0, 1, p},  {0, -1, -p}, {0, 1, -p},
                                           {p, 0, -1}, {p, 0, 1},  {-p, 0, -1}, {-p, 0, 1}};
    std::vector<std::array<int, 3>> faces = {
        {0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
        {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
        {3, 8, 9},  {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
    for (int s = 0; s < subdivisions; ++s)
    {
        std::map<std::pair<int, int>, int> midpoint;
        auto mid = [&](int a, int b) {
            auto key = std::minmax(a, b);
            auto it = midpoint.find(key);
            if (it != midpoint.end())
                return it->second;
            points.push_back(0.5 * (points[a] + points[b]));
            return midpoint[key] = static_cast<int>(points.size()) - 1;
        };
        std::vector<std::array<int, 3>> next;
        for (auto [a, b, c] : faces)
        {
            const int ab = mid(a, b), bc = mid(b, c), ca = mid(c, a);
            next.push_back({a, ab, ca});
            next.push_back({b, bc, ab});
            next.push_back({c, ca, bc});
            next.push_back({ab, bc, ca});
        }
        faces = std::move(next);
    }
    Mesh mesh;
    std::vector<VertexHandle> v;
    for (const auto& q : points)
        v.push_back(mesh.add_vertex(to_openmesh(radius * q.normalized())));
    for (auto [a, b, c] : faces)
        mesh.add_face(v[a], v[b], v[c]);
    return mesh;
}

Mesh plane_grid(double size, int n)
{
    if (size <= 0 || n < 1)
        throw InvalidInputError("plane_grid: need size > 0 and n >= 1");
    Mesh mesh;
    std::vector<VertexHandle> v((n + 1) * (n + 1));
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i)
            v[j * (n + 1) + i] = mesh.add_vertex({size * i / n, size * j / n, 0.0});
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i)
            add_quad(mesh, v[j * (n + 1) + i], v[j * (n + 1) + i + 1],
                     v[(j + 1) * (n + 1) + i + 1], v[(j + 1) * (n + 1) + i]);
    return mesh;
}

}  // namespace vessel
