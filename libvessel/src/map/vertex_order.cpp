// Vertex orders for memory locality (detail/vertex_order.h).
#include "detail/vertex_order.h"

#include "vessel/core/errors.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdlib>
#include <numeric>
#include <string>

namespace vessel::detail {

namespace {

// The 10 low bits of x spread to every third bit (bit i to bit 3i).
std::uint32_t spread_bits(std::uint32_t x)
{
    x &= 0x3ffu;
    x = (x | (x << 16)) & 0x030000ffu;
    x = (x | (x << 8)) & 0x0300f00fu;
    x = (x | (x << 4)) & 0x030c30c3u;
    x = (x | (x << 2)) & 0x09249249u;
    return x;
}

}  // namespace

std::vector<int> space_filling_order(const Mesh& mesh)
{
    const std::size_t n = mesh.n_vertices();
    Mesh::Point lo(1e300, 1e300, 1e300), hi(-1e300, -1e300, -1e300);
    for (VertexHandle v : mesh.vertices())
    {
        lo.minimize(mesh.point(v));
        hi.maximize(mesh.point(v));
    }
    const Mesh::Point size = hi - lo;
    const double extent = std::max({size[0], size[1], size[2]});
    const double scale = extent > 0.0 ? 1023.0 / extent : 0.0;
    std::vector<std::uint32_t> key(n);
    for (VertexHandle v : mesh.vertices())
    {
        const Mesh::Point q = (mesh.point(v) - lo) * scale;
        std::uint32_t code = 0;
        for (int axis = 0; axis < 3; ++axis)
            code |= spread_bits(static_cast<std::uint32_t>(std::clamp(q[axis], 0.0, 1023.0)))
                    << axis;
        key[static_cast<std::size_t>(v.idx())] = code;
    }
    std::vector<int> order(n);
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return key[a] < key[b]; });
    return order;
}

double mean_edge_index_gap(const Mesh& mesh, const std::vector<int>& new_of)
{
    if (mesh.n_edges() == 0)
        return 0.0;
    const auto index = [&](VertexHandle v) {
        return new_of.empty() ? v.idx() : new_of[static_cast<std::size_t>(v.idx())];
    };
    double sum = 0.0;
    for (const auto e : mesh.edges())
        sum += std::abs(index(e.v0()) - index(e.v1()));
    return sum / static_cast<double>(mesh.n_edges());
}

Mesh renumbered_mesh(const Mesh& mesh, const std::vector<int>& old_of)
{
    const std::size_t n = mesh.n_vertices();
    std::vector<int> new_of(n);
    for (std::size_t k = 0; k < n; ++k)
        new_of[static_cast<std::size_t>(old_of[k])] = static_cast<int>(k);
    Mesh copy;
    copy.reserve(n, mesh.n_edges(), mesh.n_faces());
    for (std::size_t k = 0; k < n; ++k)
        copy.add_vertex(mesh.point(VertexHandle(old_of[k])));
    // The faces by their first new vertex (a counting sort), each with its corners in order.
    std::vector<std::array<int, 3>> faces;
    faces.reserve(mesh.n_faces());
    std::vector<int> first(n + 1, 0);
    for (const auto f : mesh.faces())
    {
        std::array<int, 3> corners{};
        int i = 0;
        for (const auto v : f.vertices())
            corners[static_cast<std::size_t>(i++)] = new_of[static_cast<std::size_t>(v.idx())];
        faces.push_back(corners);
        ++first[static_cast<std::size_t>(*std::min_element(corners.begin(), corners.end())) + 1];
    }
    std::partial_sum(first.begin(), first.end(), first.begin());
    std::vector<int> sorted(faces.size());
    for (std::size_t f = 0; f < faces.size(); ++f)
    {
        const int lowest = *std::min_element(faces[f].begin(), faces[f].end());
        sorted[static_cast<std::size_t>(first[static_cast<std::size_t>(lowest)]++)] =
            static_cast<int>(f);
    }
    for (const int f : sorted)
    {
        const std::array<int, 3>& c = faces[static_cast<std::size_t>(f)];
        copy.add_face(VertexHandle(c[0]), VertexHandle(c[1]), VertexHandle(c[2]));
    }
    if (copy.n_faces() != mesh.n_faces())
        throw TopologyError("renumbered_mesh: the copy has " + std::to_string(copy.n_faces()) +
                            " of the mesh's " + std::to_string(mesh.n_faces()) +
                            " faces (a face OpenMesh could not add in the new order)");
    return copy;
}

}  // namespace vessel::detail
