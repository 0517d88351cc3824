#pragma once

#include "vessel/core/mesh.h"

#include <vector>

namespace vessel {

//! \brief A fill-reducing elimination order of a mesh's vertices, for the sparse Cholesky
//! factorizations of matrices with the sparsity of its cotan Laplacian: the heat method's two,
//! the harmonic coordinate's, LSCM's (two unknowns per vertex) and ARAP's.
//!
//! Ordering (AMD) is a large share of such a factorization's cost (docs/design.md,
//! "Dependencies": CHOLMOD). One ordering serves
//! every factorization on the same mesh: a system that drops pinned or fixed vertices takes the
//! order of the rest (unknown_order()). The pipeline orders the uncut mesh once (heat method,
//! harmonic coordinate) and the cut mesh once (LSCM, ARAP); the uncut mesh's ordering carried
//! over the cut would cost more in fill than a new ordering costs to make.
struct VertexOrdering
{
    std::vector<int> vertices;  //!< every vertex index once, the first eliminated first
};

//! \brief AMD (SuiteSparse) on the vertex graph of \p mesh (vertices adjacent by an edge).
//! \throw SolverError if AMD fails (out of memory).
VertexOrdering laplacian_ordering(const Mesh& mesh);

//! \brief The factorization order of a system's unknowns from \p ordering: unknown
//! `unknown_of[v]` of each vertex v that has one (>= 0), in the vertices' order.
//! \param n_unknowns how many unknowns there are (0 .. n_unknowns - 1, each of one vertex).
//! \throw InvalidInputError if \p ordering and \p unknown_of disagree in size or an unknown is
//! missing or repeated.
std::vector<int> unknown_order(const VertexOrdering& ordering, const std::vector<int>& unknown_of,
                               int n_unknowns);

}  // namespace vessel
