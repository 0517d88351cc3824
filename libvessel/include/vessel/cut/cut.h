#pragma once

#include "vessel/core/mesh.h"

#include <vector>

namespace vessel {

//! What cut_along_edges() did.
struct CutSummary
{
    int seam_edges = 0;         //!< interior edges opened
    int duplicated_vertices = 0;  //!< vertices added (one per extra fan of a split vertex)
};

//! \brief Cut the mesh open in place along \p seam by splitting its edges and duplicating the
//! vertices where the surface falls apart into several fans; work is O(seam length), nothing is
//! deleted, existing handles stay valid. (A mesh whose arrays are exactly full, e.g. a fresh
//! copy, is grown once by OpenMesh, which is O(V); call `mesh.reserve()` first to avoid it, as
//! flatten() does.)
//!
//! Every vertex property (named or not) is copied to the duplicates. The `int` vertex property
//! `prop::origin` maps every vertex to the input vertex it came from; it is created (identity) if
//! missing. Edge and halfedge properties of an opened edge are copied to its new twin.
//! \param mesh Triangle mesh, modified in place.
//! \param seam Interior (non-boundary) edges, without duplicates.
//! \throw InvalidInputError if an edge is invalid, repeated or already on the boundary.
CutSummary cut_along_edges(Mesh& mesh, const std::vector<EdgeHandle>& seam);

}  // namespace vessel
