#pragma once

#include <Eigen/Core>
#include <cholmod.h>

#include <vector>

namespace vessel::detail {

//! Solves A x = b for two right-hand sides with the Cholesky factor L of A (PAP' = LL'), on one
//! or two threads with the same bits.
//!
//! Each triangular solve streams the whole factor from memory. Two threads help only if each
//! streams part of it: the elimination tree is split into two sets of disjoint subtrees of about
//! equal nonzeros, whose columns never touch each other, plus the few columns above them (the
//! "top"). The forward solve runs each set on its own thread and collects its updates of the
//! top's rows in its own buffer, then the top; the backward solve runs the top first, then the
//! two sets. One thread runs the same steps in the same order, so the result does not depend on
//! the thread count. CHOLMOD 3 has no parallel triangular solve; its supernodal solve was slower
//! here (arap.cpp).
//!
//! The factor is kept in supernodes (columns with one row list, stored as a dense column-major
//! block, as CHOLMOD's supernodal factorization makes them; a simplicial factor gives one column
//! per supernode). Each supernode reads its rows of the solution once, works on them as dense
//! vectors and writes them back once: per stored entry one value is read, no row index, and the
//! inner loops run over contiguous memory (carotid-300k's ARAP factor: 96% of its entries in
//! supernodes of 9 or more columns).
//!
//! Supernodes are relabelled set 0, set 1, top (each in the factor's order, a topological order
//! of the tree, so the relabelled factor is the factor of the same matrix in an equivalent
//! ordering); a supernode's rows below its own columns list those in its set before those in the
//! top.
class SubtreeSolver
{
public:
    //! Copies \p L, an LL' factor from cholmod_factorize() (supernodal, or simplicial with
    //! final_ll), which the caller may free afterwards.
    explicit SubtreeSolver(const cholmod_factor& L);

    //! Scratch for one solve at a time: give each concurrent caller its own.
    struct Workspace
    {
        std::vector<double> x;          // interleaved (u, v) per column
        std::vector<double> buffer;     // each set's updates of the top's rows, interleaved
        std::vector<double> scratch[2]; // one supernode's rows below its columns and its
                                        // columns' sums, per thread
    };

    int size() const { return n_; }
    //! Entries of the stored supernodes (with the zeros a supernodal factor pads them with).
    long stored_entries() const { return static_cast<long>(values_.size()); }
    //! Share of the stored entries in each of the two sets (the rest is the top).
    double set_share(int set) const;

    //! x = A^-1 b for both columns of \p b (size() rows), on \p threads (1 or 2) threads.
    void solve(const Eigen::MatrixX2d& b, Eigen::MatrixX2d& x, int threads,
               Workspace& work) const;

    //! Column c of the factor is row permutation()[c] of A.
    const std::vector<int>& permutation() const { return perm_; }
    //! solve() without its permutations, for callers that number their unknowns in the
    //! factor's order: \p x holds (b_u, b_v) of column c at x[2c], x[2c + 1] and receives the
    //! solution there.
    void solve_in_order(double* x, int threads, Workspace& work) const;

private:
    struct Node
    {
        int first_column;  // its columns: first_column .. first_column + width - 1
        int width;
        int height;        // rows, its own columns first: rows_[row_start ..]
        int set_rows_end;  // rows [width, set_rows_end) lie outside the top, the rest in it
        long row_start;
        long value_start;  // from values_[value_start], as the .cpp file describes
    };
    // Forward solve of a node for the first `Lanes` right-hand sides of x (interleaved in pairs):
    // its columns in x, its updates of rows below go to x, except those of the top's rows,
    // which go to `top_buffer` when not null (row r at r - top_begin_).
    template <int Lanes>
    void forward_node(const Node& node, double* x, double* top_buffer, double* scratch) const;
    template <int Lanes>
    void backward_node(const Node& node, double* x, double* scratch) const;

    int n_ = 0;
    int node_end_[2] = {0, 0};  // set s holds nodes [node_begin(s), node_end_[s])
    int node_begin(int s) const { return s == 0 ? 0 : node_end_[0]; }
    int top_begin_ = 0;         // the first column of the top
    int max_below_ = 0;         // the most rows below a node's own columns
    int max_width_ = 0;         // the most columns of a node
    std::vector<Node> nodes_;
    std::vector<int> perm_;     // column c of the relabelled factor is row perm_[c] of A
    std::vector<int> rows_;
    std::vector<double> values_;
};

}  // namespace vessel::detail
