#include <doctest/doctest.h>

#include "detail/vertex_order.h"
#include "support/meshes.h"
#include "vessel/phantom/phantom.h"

#include <algorithm>
#include <numeric>
#include <random>
#include <set>

using namespace vessel;

namespace {

// \p mesh with its vertices in a random order (the faces' corners mapped), as a mesh split
// 1 -> 4 or joined from parts scatters its neighbours through the index range.
Mesh shuffled(const Mesh& mesh, std::uint32_t seed)
{
    std::vector<int> old_of(mesh.n_vertices());
    std::iota(old_of.begin(), old_of.end(), 0);
    std::shuffle(old_of.begin(), old_of.end(), std::mt19937(seed));
    return detail::renumbered_mesh(mesh, old_of);
}

}  // namespace

TEST_CASE("vertex_order: the space-filling order renumbers the same surface, its edges short")
{
    const Mesh mesh = shuffled(carotid_phantom(), 7);
    const std::vector<int> old_of = detail::space_filling_order(mesh);
    REQUIRE(old_of.size() == mesh.n_vertices());
    std::vector<int> sorted = old_of;
    std::sort(sorted.begin(), sorted.end());
    std::vector<int> identity(mesh.n_vertices());
    std::iota(identity.begin(), identity.end(), 0);
    CHECK(sorted == identity);  // a permutation

    std::vector<int> new_of(old_of.size());
    for (std::size_t k = 0; k < old_of.size(); ++k)
        new_of[static_cast<std::size_t>(old_of[k])] = static_cast<int>(k);
    const double scattered = detail::mean_edge_index_gap(mesh);
    const double along = detail::mean_edge_index_gap(mesh, new_of);
    MESSAGE("mean edge index gap: shuffled " << scattered << ", space-filling " << along);
    CHECK(along * 10.0 < scattered);

    // The renumbered mesh is the same surface: every vertex where it was, every face (with its
    // orientation) there, the boundary the same length.
    const Mesh copy = detail::renumbered_mesh(mesh, old_of);
    REQUIRE(copy.n_vertices() == mesh.n_vertices());
    REQUIRE(copy.n_faces() == mesh.n_faces());
    CHECK(copy.n_edges() == mesh.n_edges());
    for (VertexHandle v : mesh.vertices())
        CHECK(copy.point(VertexHandle(new_of[static_cast<std::size_t>(v.idx())])) ==
              mesh.point(v));
    std::set<std::array<int, 3>> faces;  // each face's corners from its smallest, in order
    const auto canonical = [](std::array<int, 3> c) {
        std::rotate(c.begin(), std::min_element(c.begin(), c.end()), c.end());
        return c;
    };
    for (const auto f : mesh.faces())
    {
        std::array<int, 3> c{};
        int i = 0;
        for (const auto v : f.vertices())
            c[static_cast<std::size_t>(i++)] = new_of[static_cast<std::size_t>(v.idx())];
        faces.insert(canonical(c));
    }
    for (const auto f : copy.faces())
    {
        std::array<int, 3> c{};
        int i = 0;
        for (const auto v : f.vertices())
            c[static_cast<std::size_t>(i++)] = v.idx();
        CHECK(faces.count(canonical(c)) == 1);
    }
    std::size_t boundary = 0, copy_boundary = 0;
    for (const auto h : mesh.halfedges())
        boundary += h.is_boundary() ? 1 : 0;
    for (const auto h : copy.halfedges())
        copy_boundary += h.is_boundary() ? 1 : 0;
    CHECK(copy_boundary == boundary);
}
