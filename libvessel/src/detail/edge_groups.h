#pragma once

// The edges of a triangle soup, each with the triangle corners that run along it (validation.cpp
// checks manifoldness with them, orient.cpp winds the soup consistently).

#include <array>
#include <cstddef>
#include <vector>

namespace vessel::detail {

//! The corners of a triangle soup grouped by undirected edge. Corner c = 3 t + k stands for edge
//! k of triangle t, from its corner k to corner (k + 1) % 3. Edges are in increasing order of
//! (smaller, larger) vertex index, and the corners of an edge in increasing order. Reversing a
//! triangle's winding keeps each edge's triangles (c / 3), not which of their corners (c % 3)
//! runs along it.
struct EdgeGroups
{
    std::vector<int> corners;              //!< edge e's corners: [start[e], start[e + 1])
    std::vector<int> start;                //!< size() + 1 offsets into corners
    std::vector<std::array<int, 2>> edge;  //!< per edge, its smaller and larger vertex

    std::size_t size() const { return edge.size(); }
    const int* begin(std::size_t e) const { return corners.data() + start[e]; }
    int count(std::size_t e) const { return start[e + 1] - start[e]; }
};

//! \brief Groups the corners of \p triangles (vertex indices below \p n_vertices, three
//! distinct per triangle) by undirected edge, in time linear in the soup's size: a counting sort
//! by the smaller vertex, then each vertex's few edges sorted by the larger one, since every
//! mesh read is validated and large meshes have millions of corners.
EdgeGroups edge_groups(const std::vector<std::array<int, 3>>& triangles, std::size_t n_vertices);

}  // namespace vessel::detail
