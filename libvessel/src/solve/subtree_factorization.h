#pragma once

#include <cholmod.h>

#include <atomic>
#include <vector>

namespace vessel::detail {

//! The numeric part of CHOLMOD's supernodal LL' factorization, on one or two threads with the
//! same bits.
//!
//! CHOLMOD 3's supernodal factorization runs on one core (its BLAS is kept serial, see
//! serial_openmp.h), and the flattening's iterative stages (SLIM, the area polish) refactor a
//! matrix of a fixed pattern tens of times with the second core idle. This factorization takes
//! CHOLMOD's symbolic analysis as it is (supernodes, row lists, the value layout, so that
//! cholmod_solve() and the SubtreeSolver read the result as CHOLMOD's own) and computes the
//! values left-looking, as CHOLMOD does: per supernode, A's entries, then the updates of its
//! descendants (dsyrk/dgemm), then dpotrf and dtrsm; blocks of a few thousand multiply-adds by
//! plain loops instead, as a BLAS call costs more than their arithmetic (OpenBLAS locks a
//! process-wide buffer at every level-3 call, a lock that two factorizing threads contend
//! for). The supernodal tree is split into two sets of whole subtrees of about equal work and
//! the few supernodes above them (the "top", as in SubtreeSolver): the two sets share no
//! column, so each runs on its own thread; the top runs after both. One thread runs the same
//! steps in the same order, so the result does not depend on the thread count (it differs
//! from cholmod_factorize()'s in the last bits: the updates of a top supernode are summed in
//! another order, and the small blocks' sums too).
//!
//! A's entries are scattered straight into the factor's blocks through a map made once per
//! symbolic analysis (CHOLMOD permutes A into a transposed copy at every factorization).
class SubtreeFactorization
{
public:
    //! \p L: a supernodal symbolic factor of \p A's pattern (cholmod_analyze() with
    //! CHOLMOD_SUPERNODAL, int indices); \p A: symmetric, its upper triangle read (stype 1),
    //! compressed columns. Only the pattern is read.
    SubtreeFactorization(const cholmod_sparse& A, const cholmod_factor& L);

    //! Factorizes \p A (the pattern given at construction, new values) into \p L, allocating its
    //! values the first time. \return false if A is not positive definite (L->minor is then the
    //! failing column, as cholmod_factorize() sets it).
    //! Not for two threads at once on one object (it keeps its scratch between calls).
    bool factorize(const cholmod_sparse& A, cholmod_factor& L, cholmod_common& common,
                   int threads);

    //! Share of the estimated flops in each of the two sets (the rest is the top).
    double set_share(int set) const;

private:
    struct Entry
    {
        int value;  // index into A's values
        int dest;   // index into the factor's values (CHOLMOD's int factor: below 2^31)
    };
    // One thread's scratch and its lists of the supernodes waiting to update a supernode.
    struct Context
    {
        std::vector<int> head;       // by supernode: the first supernode waiting to update it, or -1
        std::vector<int> map;        // by row: its place in the rows of the supernode being made
        std::vector<double> update;  // one descendant's update block (map, update: sets only)
    };
    // Makes the supernodes of `part` (0, 1: a set; 2: the top) in \p context's lists with
    // \p scratch's row map and update block; stops at a supernode that is not positive definite
    // (its failing column lowers \p failed).
    void run(int part, Context& context, Context& scratch, const cholmod_factor& L, double* Lx,
             std::vector<int>& next, std::vector<int>& position, std::vector<Context>& all,
             const double* Ax, std::atomic<int>& failed) const;

    int n_ = 0;
    int nsuper_ = 0;
    long xsize_ = 0;
    long max_update_ = 0;  // the largest update block (rows x columns) of one descendant
    std::vector<int> super_of_;   // supernode of each column
    std::vector<int> order_[3];   // supernodes of set 0, set 1 and the top, in factor order
    std::vector<long> entry_start_;  // entries_[entry_start_[s] ..] fill supernode s
    std::vector<Entry> entries_;
    double share_[2] = {0.0, 0.0};
    long a_nonzeros_ = 0;
    // factorize()'s scratch, kept for the next call: a context per part, the supernode lists.
    std::vector<Context> contexts_;
    std::vector<int> next_, position_;
};

//! One numeric factorization of \p A into the symbolic factor \p L (as analysed from A's pattern
//! by cholmod_analyze()): a SubtreeFactorization on \p threads threads when L is supernodal,
//! else cholmod_factorize(). \return false if CHOLMOD fails or A is not positive definite.
bool factorize_once(const cholmod_sparse& A, cholmod_factor& L, cholmod_common& common,
                    int threads);

}  // namespace vessel::detail
