#pragma once

#include <Eigen/Core>
#include <cholmod.h>

#include <vector>

namespace vessel::detail {

//! Solves A x = b for two right-hand sides with the Cholesky factor L of A (PAP' = LL'), on one
//! or two threads with the same bits.
//!
//! Each triangular solve streams the whole factor from memory and is bound by that, not by its
//! arithmetic. Two threads help only if each streams part of it: the elimination tree is split
//! into two sets of disjoint subtrees of about equal nonzeros, whose columns never touch each
//! other, plus the few columns above them (the "top"). The forward solve runs each set on its own
//! thread and collects its updates of the top's rows in its own buffer, then the top (u and v on
//! one thread each); the backward solve runs the top first, then the two sets. One thread runs
//! the same steps in the same order, so the result does not depend on the thread count. CHOLMOD
//! 3 has no parallel triangular solve; its supernodal solve was slower here (arap.cpp).
//!
//! Columns are relabelled set 0, set 1, top (each in the factor's order, a topological order of
//! the tree, so the relabelled factor is the factor of the same matrix in an equivalent
//! ordering), and each column's entries above the top are stored before those in it.
class SubtreeSolver
{
public:
    //! Copies \p L, an LL' factor from cholmod_factorize() (supernodal, or simplicial with
    //! final_ll), which the caller may free afterwards.
    explicit SubtreeSolver(const cholmod_factor& L);

    //! Scratch for one solve at a time: give each concurrent caller its own.
    struct Workspace
    {
        std::vector<double> x;       // interleaved (u, v) per column
        std::vector<double> buffer;  // each set's updates of the top's rows, interleaved
        std::vector<double> top_rows;  // the top's rows, u then v
    };

    int size() const { return n_; }
    //! Nonzeros of the stored factor.
    long nonzeros() const { return static_cast<long>(rows_.size()); }
    //! Share of the nonzeros in each of the two sets (the rest is the top).
    double set_share(int set) const;

    //! x = A^-1 b for both columns of \p b (size() rows), on \p threads (1 or 2) threads.
    void solve(const Eigen::MatrixX2d& b, Eigen::MatrixX2d& x, int threads,
               Workspace& work) const;

private:
    void forward_set(int set, double* x, double* buffer) const;
    void forward_top(double* x) const;
    void backward_top(double* x) const;
    void backward_set(int set, double* x) const;

    int n_ = 0;
    int set_end_[2] = {0, 0};     // set s holds columns [set_begin(s), set_end_[s])
    int top_begin() const { return set_end_[1]; }
    int set_begin(int s) const { return s == 0 ? 0 : set_end_[0]; }
    std::vector<int> perm_;       // column c of the relabelled factor is row perm_[c] of A
    std::vector<long> start_;     // column c: entries [start_[c], start_[c + 1]), diagonal first
    std::vector<long> top_start_; // column c's entries in top rows: [top_start_[c], start_[c + 1])
    std::vector<int> rows_;
    std::vector<double> values_;
};

}  // namespace vessel::detail
