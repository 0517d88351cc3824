#pragma once

// Consistent orientation of a triangle soup (validation.cpp): issue 6's "inconsistent
// orientation (fixed with a warning)".

#include "detail/edge_groups.h"

#include <array>
#include <cstddef>
#include <vector>

namespace vessel::detail {

//! What orient_consistently() found.
struct Orientation
{
    int reversed = 0;  //!< triangles whose winding was reversed
    //! When the surface is not orientable (e.g. a Moebius strip): two triangles (indices into
    //! the soup) that cannot be wound to agree along their shared edge; otherwise -1, -1.
    int conflict_a = -1, conflict_b = -1;
};

//! \brief Reverses the winding of triangles so that every edge shared by exactly two triangles
//! is run in opposite directions by them (breadth-first over each edge-connected piece).
//! In each piece the winding most triangles already have is kept, so the fewest are reversed.
//! Edges with more than two triangles are ignored (the manifold check refuses them). If the
//! surface is not orientable nothing is changed and the conflict is returned. \p edges: the
//! edge_groups() of \p triangles.
Orientation orient_consistently(std::vector<std::array<int, 3>>& triangles,
                                const EdgeGroups& edges);

}  // namespace vessel::detail
