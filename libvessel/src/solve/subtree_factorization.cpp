#include "solve/subtree_factorization.h"

#include "solve/tree_split.h"
#include "vessel/core/errors.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <new>
#include <string>
#include <thread>

// The BLAS and LAPACK that CHOLMOD calls (the system's libblas.so.3 / liblapack.so.3).
extern "C" {
void dsyrk_(const char* uplo, const char* trans, const int* n, const int* k, const double* alpha,
            const double* a, const int* lda, const double* beta, double* c, const int* ldc);
void dgemm_(const char* transa, const char* transb, const int* m, const int* n, const int* k,
            const double* alpha, const double* a, const int* lda, const double* b, const int* ldb,
            const double* beta, double* c, const int* ldc);
void dpotrf_(const char* uplo, const int* n, double* a, const int* lda, int* info);
void dtrsm_(const char* side, const char* uplo, const char* transa, const char* diag, const int* m,
            const int* n, const double* alpha, const double* a, const int* lda, double* b,
            const int* ldb);
}

namespace vessel::detail {

namespace {

// Blocks of at most this many multiply-adds are made by the loops below instead of BLAS. Most
// supernodes of a surface mesh's factor are a few columns wide, and on such a block a BLAS call
// costs more than its arithmetic: OpenBLAS's level-3 routines take a process-wide lock around
// their buffer at every call, which two threads factorizing at once (the two sets here, or two
// solvers on their own threads) contend for; larger blocks amortize it, and BLAS's kernels are
// faster there.
constexpr long kSmallBlock = 8192;

// C(i, j) = sum_k S(i, k) S(j, k) for j < inside and j <= i < below, C column-major with
// leading dimension `below`: dsyrk's lower triangle and dgemm's rows below it, in one pass.
void small_update(int inside, int below, int width, const double* S, int ld, double* C)
{
    for (int j = 0; j < inside; ++j)
    {
        double* c = C + static_cast<long>(j) * below;
        std::fill(c + j, c + below, 0.0);
        for (int k = 0; k < width; ++k)
        {
            const double* column = S + static_cast<long>(k) * ld;
            const double sj = column[j];
            for (int i = j; i < below; ++i)
                c[i] += column[i] * sj;
        }
    }
}

// dpotrf("L") of the width x width block A (leading dimension ld): 0, or as LAPACK's info the
// 1-based column whose pivot is not positive.
int small_cholesky(int width, double* A, int ld)
{
    const auto at = [A, ld](int i, int k) -> double& { return A[i + static_cast<long>(k) * ld]; };
    for (int j = 0; j < width; ++j)
    {
        double pivot = at(j, j);
        for (int k = 0; k < j; ++k)
            pivot -= at(j, k) * at(j, k);
        if (!(pivot > 0.0))
            return j + 1;
        pivot = std::sqrt(pivot);
        at(j, j) = pivot;
        for (int i = j + 1; i < width; ++i)
        {
            double value = at(i, j);
            for (int k = 0; k < j; ++k)
                value -= at(i, k) * at(j, k);
            at(i, j) = value / pivot;
        }
    }
    return 0;
}

// B := B L^-T (dtrsm "R", "L", "T", "N"): B of `rest` rows and L of width x width, both with
// leading dimension ld.
void small_solve(int rest, int width, const double* L, int ld, double* B)
{
    for (int j = 0; j < width; ++j)
    {
        double* bj = B + static_cast<long>(j) * ld;
        for (int k = 0; k < j; ++k)
        {
            const double l = L[j + static_cast<long>(k) * ld];
            const double* bk = B + static_cast<long>(k) * ld;
            for (int r = 0; r < rest; ++r)
                bj[r] -= bk[r] * l;
        }
        const double pivot = L[j + static_cast<long>(j) * ld];
        for (int r = 0; r < rest; ++r)
            bj[r] /= pivot;
    }
}

}  // namespace

SubtreeFactorization::SubtreeFactorization(const cholmod_sparse& A, const cholmod_factor& L)
{
    if (!L.is_super || L.itype != CHOLMOD_INT || A.itype != CHOLMOD_INT || !A.packed ||
        A.stype == 0 || A.nrow != L.n || A.ncol != L.n)
        throw SolverError("SubtreeFactorization: needs a supernodal symbolic factor with int "
                          "indices of a square symmetric matrix stored as one packed triangle");
    n_ = static_cast<int>(L.n);
    nsuper_ = static_cast<int>(L.nsuper);
    xsize_ = static_cast<long>(L.xsize);
    const int* super = static_cast<const int*>(L.super);
    const int* pi = static_cast<const int*>(L.pi);
    const int* px = static_cast<const int*>(L.px);
    const int* rows = static_cast<const int*>(L.s);
    const int* perm = static_cast<const int*>(L.Perm);

    super_of_.resize(n_);
    for (int s = 0; s < nsuper_; ++s)
        for (int c = super[s]; c < super[s + 1]; ++c)
            super_of_[c] = s;
    std::vector<int> column_of(n_);  // column of the factor that row i of A becomes
    for (int c = 0; c < n_; ++c)
        column_of[perm ? perm[c] : c] = c;

    // A's stored triangle, entry by entry, to (row, column) of the factor's lower triangle,
    // bucketed by supernode.
    const int* Ap = static_cast<const int*>(A.p);
    const int* Ai = static_cast<const int*>(A.i);
    const bool upper = A.stype > 0;
    a_nonzeros_ = Ap[n_];
    const auto read = [&](auto&& visit) {
        for (int j = 0; j < n_; ++j)
            for (int p = Ap[j]; p < Ap[j + 1]; ++p)
            {
                const int i = Ai[p];
                if (upper ? i > j : i < j)
                    continue;  // the other triangle, not read (as CHOLMOD with this stype)
                const int a = column_of[i], b = column_of[j];
                visit(p, std::max(a, b), std::min(a, b));
            }
    };
    entry_start_.assign(nsuper_ + 1, 0);
    read([&](int, int, int column) { ++entry_start_[super_of_[column] + 1]; });
    for (int s = 0; s < nsuper_; ++s)
        entry_start_[s + 1] += entry_start_[s];
    entries_.resize(entry_start_[nsuper_]);
    {
        // Bucketed by supernode first (dest holds the row meanwhile, `offset` the column within
        // the supernode), then each supernode's entries are placed through a map of its rows:
        // one lookup per entry instead of a bisection of the supernode's rows.
        std::vector<int> offset(entries_.size());
        std::vector<long> cursor(entry_start_.begin(), entry_start_.end() - 1);
        read([&](int p, int row, int column) {
            const int s = super_of_[column];
            const long e = cursor[s]++;
            entries_[e].value = p;
            entries_[e].dest = row;
            offset[e] = column - super[s];
        });
        std::vector<int> place(n_), owner(n_, -1);  // row -> its index in supernode owner[row]
        for (int s = 0; s < nsuper_; ++s)
        {
            const int height = pi[s + 1] - pi[s];
            for (int k = 0; k < height; ++k)
            {
                place[rows[pi[s] + k]] = k;
                owner[rows[pi[s] + k]] = s;
            }
            for (long e = entry_start_[s]; e < entry_start_[s + 1]; ++e)
            {
                const int row = entries_[e].dest;
                if (owner[row] != s)
                    throw SolverError("SubtreeFactorization: the matrix has an entry outside the "
                                      "factor's pattern; analyze this matrix's pattern");
                entries_[e].dest = px[s] + offset[e] * height + place[row];
            }
        }
    }

    // The supernodal tree (a supernode's parent holds its first row below its own columns),
    // weighted by an estimate of the flops each supernode's columns cost and send.
    std::vector<int> parent(nsuper_, -1);
    std::vector<double> work(nsuper_), subtree_work(nsuper_);
    for (int s = 0; s < nsuper_; ++s)
    {
        const int width = super[s + 1] - super[s], height = pi[s + 1] - pi[s];
        if (height > width)
            parent[s] = super_of_[rows[pi[s] + width]];
        work[s] = static_cast<double>(width) * height * height;
        // The update blocks this supernode sends (run()): from each run of its rows below its
        // columns that falls in one ancestor's columns, that run by the rows from it on.
        for (int p = pi[s] + width; p < pi[s + 1];)
        {
            const int target_end = super[super_of_[rows[p]] + 1];
            int q = p;
            while (q < pi[s + 1] && rows[q] < target_end)
                ++q;
            max_update_ = std::max(max_update_, static_cast<long>(q - p) * (pi[s + 1] - p));
            p = q;
        }
    }
    for (int s = 0; s < nsuper_; ++s)
    {
        subtree_work[s] += work[s];
        if (parent[s] >= 0)
            subtree_work[parent[s]] += subtree_work[s];
    }
    const std::vector<int> owner = split_owners(parent, subtree_work);
    double total = 0.0, in_set[2] = {0.0, 0.0};
    for (int s = 0; s < nsuper_; ++s)
    {
        order_[owner[s]].push_back(s);
        total += work[s];
        if (owner[s] < 2)
            in_set[owner[s]] += work[s];
    }
    for (int set = 0; set < 2; ++set)
        share_[set] = total > 0.0 ? in_set[set] / total : 0.0;
}

double SubtreeFactorization::set_share(int set) const
{
    return share_[set];
}

void SubtreeFactorization::run(int part, Context& context, Context& scratch,
                               const cholmod_factor& L, double* Lx,
                               std::vector<int>& next, std::vector<int>& position,
                               std::vector<Context>& all, const double* Ax,
                               std::atomic<int>& failed) const
{
    const int* super = static_cast<const int*>(L.super);
    const int* pi = static_cast<const int*>(L.pi);
    const int* px = static_cast<const int*>(L.px);
    const int* rows = static_cast<const int*>(L.s);
    const double one = 1.0, zero = 0.0;
    // d waits to update the supernode of its next row below the columns it has updated.
    const auto wait = [&](int d, int row_offset) {
        position[d] = row_offset;
        if (pi[d] + row_offset < pi[d + 1])
        {
            const int target = super_of_[rows[pi[d] + row_offset]];
            next[d] = context.head[target];
            context.head[target] = d;
        }
    };
    for (const int s : order_[part])
    {
        if (failed.load(std::memory_order_relaxed) < n_)
            return;
        const int first = super[s], end = super[s + 1], width = end - first;
        const int height = pi[s + 1] - pi[s];
        double* block = Lx + px[s];
        std::fill(block, block + static_cast<long>(width) * height, 0.0);
        for (long e = entry_start_[s]; e < entry_start_[s + 1]; ++e)
            Lx[entries_[e].dest] += Ax[entries_[e].value];
        for (int k = 0; k < height; ++k)
            scratch.map[rows[pi[s] + k]] = k;

        // The descendants that update s: those listed by this thread, and in the top also
        // those each set's thread left waiting for it.
        const auto update_from = [&](Context& lists) {
            int d = lists.head[s];
            lists.head[s] = -1;
            while (d >= 0)
            {
                const int d_next = next[d];
                const int d_height = pi[d + 1] - pi[d], d_width = super[d + 1] - super[d];
                const int begin = pi[d] + position[d];
                int middle = begin;
                while (middle < pi[d + 1] && rows[middle] < end)
                    ++middle;
                const int inside = middle - begin, below = pi[d + 1] - begin;
                const double* source = Lx + px[d] + (begin - pi[d]);
                double* C = scratch.update.data();
                if (static_cast<long>(below) * inside * d_width <= kSmallBlock)
                    small_update(inside, below, d_width, source, d_height, C);
                else
                {
                    dsyrk_("L", "N", &inside, &d_width, &one, source, &d_height, &zero, C,
                           &below);
                    if (below > inside)
                    {
                        const int rest = below - inside;
                        dgemm_("N", "T", &rest, &inside, &d_width, &one, source + inside,
                               &d_height, source, &d_height, &zero, C + inside, &below);
                    }
                }
                for (int j = 0; j < inside; ++j)
                {
                    double* column = block + static_cast<long>(rows[begin + j] - first) * height;
                    const double* c = C + static_cast<long>(j) * below;
                    for (int i = j; i < below; ++i)
                        column[scratch.map[rows[begin + i]]] -= c[i];
                }
                wait(d, middle - pi[d]);
                d = d_next;
            }
        };
        if (part < 2)
            update_from(context);
        else
            for (Context& lists : all)
                update_from(lists);

        int info = 0;
        const bool small = static_cast<long>(width) * width * height <= kSmallBlock;
        if (small)
            info = small_cholesky(width, block, height);
        else
            dpotrf_("L", &width, block, &height, &info);
        if (info != 0)
        {
            int seen = failed.load();
            while (first + info - 1 < seen && !failed.compare_exchange_weak(seen, first + info - 1))
            {
            }
            return;
        }
        if (height > width)
        {
            const int rest = height - width;
            if (small)
                small_solve(rest, width, block, height, block + width);
            else
                dtrsm_("R", "L", "T", "N", &rest, &width, &one, block, &height, block + width,
                       &height);
            wait(s, width);
        }
    }
}

bool SubtreeFactorization::factorize(const cholmod_sparse& A, cholmod_factor& L,
                                     cholmod_common& common, int threads)
{
    if (A.ncol != static_cast<std::size_t>(n_) || L.n != static_cast<std::size_t>(n_) ||
        static_cast<const int*>(A.p)[n_] != a_nonzeros_ || !A.packed)
        throw SolverError("SubtreeFactorization: the matrix's pattern is not the analysed one");
    if (L.xtype == CHOLMOD_PATTERN)
    {
        // Values for the symbolic factor, in its layout (as cholmod_factorize() allocates them).
        L.is_ll = true;
        if (!cholmod_change_factor(CHOLMOD_REAL, true, true, true, true, &L, &common) ||
            L.x == nullptr)
        {
            if (common.status == CHOLMOD_OUT_OF_MEMORY)
                throw std::bad_alloc();  // said as such to the user (the tools' error_text())
            throw SolverError("SubtreeFactorization: CHOLMOD could not allocate the factor's "
                              "values (status " + std::to_string(common.status) + ")");
        }
    }
    if (!L.is_super || static_cast<long>(L.xsize) != xsize_)
        throw SolverError("SubtreeFactorization: the factor is not the analysed one");
    double* Lx = static_cast<double*>(L.x);
    const double* Ax = static_cast<const double*>(A.x);
    // Every list is empty after a complete factorization, but not after a failed one. The top
    // runs after both sets, with the first set's row map and update block.
    contexts_.resize(3);
    for (int part = 0; part < 3; ++part)
    {
        contexts_[part].head.assign(nsuper_, -1);
        if (part < 2)
        {
            contexts_[part].map.resize(n_);
            contexts_[part].update.resize(max_update_);
        }
    }
    next_.resize(nsuper_);
    position_.resize(nsuper_);
    std::vector<Context>& contexts = contexts_;
    std::vector<int>& next = next_;
    std::vector<int>& position = position_;
    std::atomic<int> failed{n_};
    if (threads > 1 && !order_[0].empty() && !order_[1].empty())
    {
        std::thread other(
            [&] { run(1, contexts[1], contexts[1], L, Lx, next, position, contexts, Ax, failed); });
        run(0, contexts[0], contexts[0], L, Lx, next, position, contexts, Ax, failed);
        other.join();
    }
    else
    {
        run(0, contexts[0], contexts[0], L, Lx, next, position, contexts, Ax, failed);
        run(1, contexts[1], contexts[1], L, Lx, next, position, contexts, Ax, failed);
    }
    run(2, contexts[2], contexts[0], L, Lx, next, position, contexts, Ax, failed);
    L.minor = static_cast<std::size_t>(failed.load());
    return failed.load() == n_;
}

bool factorize_once(const cholmod_sparse& A, cholmod_factor& L, cholmod_common& common,
                    int threads)
{
    if (!L.is_super || L.itype != CHOLMOD_INT || A.itype != CHOLMOD_INT || !A.packed)
        return cholmod_factorize(const_cast<cholmod_sparse*>(&A), &L, &common) &&
               common.status == CHOLMOD_OK && L.minor == L.n;
    return SubtreeFactorization(A, L).factorize(A, L, common, threads);
}

}  // namespace vessel::detail
