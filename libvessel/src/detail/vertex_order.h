#pragma once
// A mesh's vertices renumbered along a space-filling curve, so that the neighbours a vertex
// sweep reads lie near each other in memory. Yoon, Lindstrom, Pascucci and Manocha 2005,
// "Cache-oblivious mesh layouts", measure how much a mesh's layout matters to such sweeps; a
// space-filling curve is the simplest of the layouts they compare.

#include "vessel/core/mesh.h"

#include <vector>

namespace vessel::detail {

//! The vertex indices of \p mesh in the order of the Z-order (Morton) curve through the
//! bounding box of their positions, 10 bits per axis; vertices in one cell keep their order.
std::vector<int> space_filling_order(const Mesh& mesh);

//! The mean of |new index of a - new index of b| over the edges (a, b) of \p mesh, where
//! `new_of[v]` is v's new index (the identity if \p new_of is empty): how far apart in memory
//! the two ends of an edge lie in that order.
double mean_edge_index_gap(const Mesh& mesh, const std::vector<int>& new_of = {});

//! \brief A copy of \p mesh with its vertex `old_of[k]` as vertex k (positions and faces, the
//! faces in the order of their first new vertex; no custom properties).
//! \throw TopologyError if the copy does not have the faces of \p mesh (it would not be the
//! same surface).
Mesh renumbered_mesh(const Mesh& mesh, const std::vector<int>& old_of);

}  // namespace vessel::detail
