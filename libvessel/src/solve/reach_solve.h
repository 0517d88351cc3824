#pragma once

#include <cholmod.h>
#include <Eigen/Core>
#include <Eigen/Sparse>

#include <vector>

namespace vessel::detail {

//! The forward solve Y = L^-1 P U of a few sparse columns U with a supernodal LL' factor
//! (P A P^T = L L^T), on the rows it reaches only.
//!
//! Row i of P U enters Y through the supernode that holds its column of L and moves up the
//! supernodal elimination tree from there: Y is zero outside the union of those supernodes'
//! paths to their roots (Gilbert 1994, "Predicting structure in sparse matrix computations").
//! A column that touches a few dozen unknowns, as a look pull's does, reaches a small part of
//! the factor, where a dense solve of that column would stream all of it.
struct ReachSolve
{
    //! The permuted unknowns reached (the columns of the reached supernodes), in elimination
    //! order.
    std::vector<int> rows;
    //! rows.size() x U.cols(): L^-1 P U at those unknowns (every other row of it is zero).
    Eigen::MatrixXd Y;
};

//! Y = L^-1 P U for \p L a supernodal LL' factor with int indices and real values (the
//! numeric factorization made), \p U with as many rows as L has columns.
ReachSolve reach_forward_solve(const cholmod_factor& L, const Eigen::SparseMatrix<double>& U);

}  // namespace vessel::detail
