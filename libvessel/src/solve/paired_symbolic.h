#pragma once

#include "solve/cholmod_common.h"

#include <cholmod.h>
#include <Eigen/Sparse>

#include <vector>

namespace vessel::detail {

//! The vertex graph G of a symmetric matrix A whose unknowns come in pairs (unknowns 2i and
//! 2i + 1 of vertex i), from A's upper triangle (compressed): vertex I <= J for each stored
//! entry (i, j) with I = i / 2, J = j / 2.
struct VertexGraph
{
    std::vector<int> column_start;  //!< n + 1 offsets into `rows`
    std::vector<int> rows;          //!< column J's vertices I <= J, each once, in A's order
    //! Whether each pair's block is stored whole: four entries with every neighbour and three
    //! on the diagonal (where paired_symbolic() gives A's own factor).
    bool whole_blocks = false;
    //! CHOLMOD's view of G's upper pattern (stype 1): valid while this graph lives unchanged.
    cholmod_sparse view() { return upper_pattern(column_start, rows); }
};

//! \p A's vertex graph (\p A: even size, upper triangle, compressed).
VertexGraph vertex_graph(const Eigen::SparseMatrix<double>& A);

//! The supernodal symbolic factor that CHOLMOD's analysis gives a symmetric matrix A whose
//! unknowns come in pairs (unknowns 2i and 2i + 1 of vertex i, each pair's four entries
//! stored together), made from its vertex graph G instead of A itself.
//!
//! With A's pattern G's with each entry a 2 x 2 block, eliminating the pairs in G's order
//! fills exactly G's factor with each entry a block (Ashcraft 1995, "Compressed graphs and the
//! minimum degree algorithm", SIAM J. Sci. Comput. 16(6)): A's elimination tree, column counts,
//! weighted postorder and fundamental supernodes follow from G's. CHOLMOD's rule for relaxed
//! supernodes (cholmod_common::nrelax, zrelax) is then applied to A's counts, and each
//! supernode's rows found on G. The result is field for field the factor of
//! `cholmod_analyze_p(A, paired order)` with CHOLMOD_GIVEN and cholmod_common::supernodal
//! CHOLMOD_SUPERNODAL (tests/solve/paired_symbolic_test.cpp), so the numeric factorization
//! has the same bits; A itself is never permuted or transposed (CHOLMOD's analysis does so
//! four times), only G, a quarter of its entries.
//!
//! \param graph G's pattern: stype 1 (the upper triangle, each column's rows in any order,
//! the diagonal optional), int indices.
//! \param vertex_order G's elimination order (each vertex once).
//! \param c CHOLMOD's settings: `postorder` and the relaxation limits are read.
//! \return the symbolic factor (free it with cholmod_free_factor); null if CHOLMOD fails or
//! \p graph is not a symmetric pattern.
cholmod_factor* paired_symbolic(const cholmod_sparse& graph, const std::vector<int>& vertex_order,
                                cholmod_common& c);

}  // namespace vessel::detail
