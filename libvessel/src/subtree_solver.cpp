#include "detail/subtree_solver.h"

#include "detail/face_jacobian.h"
#include "vessel/errors.h"

#include <algorithm>
#include <numeric>
#include <string>

namespace vessel::detail {

namespace {

// The split stops once the lighter set has this share of the heavier one's nonzeros ...
constexpr double kBalance = 0.97;
// ... or when the top would pass this share of all nonzeros, or after this many expansions (then
// the best split seen is kept; carotid-300k balances after 1 465).
constexpr double kMaxTopShare = 0.3;
constexpr int kMaxExpansions = 1 << 14;

struct Split
{
    std::vector<int> roots[2];  // subtree roots of each set
};

// Splits the forest given by `parent` (parent[j] > j, or -1) into two sets of whole subtrees of
// about equal weight: expand the heaviest subtree of the frontier into the top (its root) and its
// children, and deal the frontier to the two sets heaviest first, each to the lighter set.
Split split_forest(const std::vector<int>& parent, const std::vector<double>& subtree_weight)
{
    const int n = static_cast<int>(parent.size());
    std::vector<int> child_start(n + 1, 0), children(n);
    for (int j = 0; j < n; ++j)
        if (parent[j] >= 0)
            ++child_start[parent[j] + 1];
    std::partial_sum(child_start.begin(), child_start.end(), child_start.begin());
    {
        std::vector<int> next(child_start.begin(), child_start.end() - 1);
        for (int j = 0; j < n; ++j)
            if (parent[j] >= 0)
                children[next[parent[j]]++] = j;
    }
    double total = 0.0;
    for (int j = 0; j < n; ++j)
        if (parent[j] < 0)
            total += subtree_weight[j];
    // The frontier sorted lightest first (ties by index), so the heaviest is at the back.
    const auto lighter_first = [&](int a, int b) {
        return subtree_weight[a] < subtree_weight[b] ||
               (subtree_weight[a] == subtree_weight[b] && a > b);
    };
    std::vector<int> frontier;
    const auto add = [&](int j) {
        frontier.insert(std::lower_bound(frontier.begin(), frontier.end(), j, lighter_first), j);
    };
    for (int j = 0; j < n; ++j)
        if (parent[j] < 0)
            add(j);
    Split best;
    double best_lighter = -1.0, top = 0.0;
    for (int expansions = 0; !frontier.empty() && expansions <= kMaxExpansions; ++expansions)
    {
        Split split;
        double weight[2] = {0.0, 0.0};
        for (auto root = frontier.rbegin(); root != frontier.rend(); ++root)
        {
            const int s = weight[0] <= weight[1] ? 0 : 1;
            weight[s] += subtree_weight[*root];
            split.roots[s].push_back(*root);
        }
        const double lighter = std::min(weight[0], weight[1]);
        if (lighter > best_lighter)
        {
            best_lighter = lighter;
            best = std::move(split);
        }
        if (lighter >= kBalance * std::max(weight[0], weight[1]))
            break;
        const int expanded = frontier.back();
        top += subtree_weight[expanded];
        for (int c = child_start[expanded]; c < child_start[expanded + 1]; ++c)
            top -= subtree_weight[children[c]];
        if (top > kMaxTopShare * total)
            break;
        frontier.pop_back();
        for (int c = child_start[expanded]; c < child_start[expanded + 1]; ++c)
            add(children[c]);
    }
    return best;
}

// body(k) for k = 0 and 1, each on its own thread when \p threads is 2, else in that order.
template <class Body>
void for_both(int threads, const Body& body)
{
    parallel_chunks(2, threads, [&](std::size_t begin, std::size_t end, int) {
        for (std::size_t k = begin; k < end; ++k)
            body(static_cast<int>(k));
    });
}

}  // namespace

SubtreeSolver::SubtreeSolver(const cholmod_factor& L)
{
    if (!L.is_ll || L.xtype != CHOLMOD_REAL || L.itype != CHOLMOD_INT ||
        L.dtype != CHOLMOD_DOUBLE || L.minor != L.n)
        throw SolverError("SubtreeSolver: needs a complete real LL' factor with int indices "
                          "(CHOLMOD's supernodal factorization, or simplicial with final_ll)");
    n_ = static_cast<int>(L.n);
    const double* x = static_cast<const double*>(L.x);
    const int* perm = static_cast<const int*>(L.Perm);

    // Each column's rows and values from its diagonal down, contiguous in either layout.
    struct Column
    {
        const int* rows;
        const double* values;
        int count;
    };
    std::vector<Column> columns(n_);
    if (L.is_super)
    {
        // Supernode s: columns super[s] .. super[s + 1] - 1 share the row list s[pi[s] ..],
        // values column-major with a leading dimension of that list's length.
        const int* super = static_cast<const int*>(L.super);
        const int* pi = static_cast<const int*>(L.pi);
        const int* px = static_cast<const int*>(L.px);
        const int* rows = static_cast<const int*>(L.s);
        for (std::size_t node = 0; node < L.nsuper; ++node)
        {
            const int height = pi[node + 1] - pi[node];
            for (int j = super[node]; j < super[node + 1]; ++j)
            {
                const int offset = j - super[node];
                columns[j] = {rows + pi[node] + offset,
                              x + px[node] + static_cast<long>(offset) * height + offset,
                              height - offset};
            }
        }
    }
    else
    {
        const int* p = static_cast<const int*>(L.p);
        const int* nz = static_cast<const int*>(L.nz);
        for (int j = 0; j < n_; ++j)
            columns[j] = {static_cast<const int*>(L.i) + p[j], x + p[j], nz[j]};
    }

    // Elimination tree of the stored pattern (with a supernodal factor's explicit zeros): a
    // column's parent is its first row below the diagonal, and every row of the column is an
    // ancestor.
    std::vector<int> parent(n_, -1);
    std::vector<double> subtree_weight(n_);
    for (int j = 0; j < n_; ++j)
    {
        const Column& column = columns[j];
        if (column.count < 1 || column.rows[0] != j)
            throw SolverError("SubtreeSolver: column " + std::to_string(j) +
                              " of the factor does not start with its diagonal");
        for (int k = 1; k < column.count; ++k)
            if (parent[j] < 0 || column.rows[k] < parent[j])
                parent[j] = column.rows[k];
        subtree_weight[j] += column.count;
        if (parent[j] >= 0)
            subtree_weight[parent[j]] += subtree_weight[j];
    }
    const Split split = split_forest(parent, subtree_weight);

    // Owner of each column: the set whose subtree holds it, else the top (2). Parents come
    // after their children, so one pass from the last column settles every subtree.
    std::vector<int> owner(n_, 2);
    for (int s = 0; s < 2; ++s)
        for (const int root : split.roots[s])
            owner[root] = s;
    for (int j = n_ - 1; j >= 0; --j)
        if (owner[j] == 2 && parent[j] >= 0 && owner[parent[j]] < 2)
            owner[j] = owner[parent[j]];
    std::vector<int> label(n_), column_of(n_);
    int next = 0;
    for (int s = 0; s < 3; ++s)
    {
        for (int j = 0; j < n_; ++j)
            if (owner[j] == s)
            {
                label[j] = next;
                column_of[next++] = j;
            }
        if (s < 2)
            set_end_[s] = next;
    }

    perm_.resize(n_);
    start_.resize(n_ + 1);
    top_start_.resize(n_);
    long total = 0;
    for (const Column& column : columns)
        total += 1 + std::count_if(column.values + 1, column.values + column.count,
                                   [](double value) { return value != 0.0; });
    rows_.reserve(total);
    values_.reserve(total);
    for (int c = 0; c < n_; ++c)
    {
        const int j = column_of[c];
        const Column& column = columns[j];
        perm_[c] = perm ? perm[j] : j;
        start_[c] = static_cast<long>(rows_.size());
        rows_.push_back(c);
        values_.push_back(column.values[0]);
        // Rows above the top, then the top's; exact zeros (a supernode's padding) are left out,
        // as subtracting them would change nothing.
        for (int pass = 0; pass < 2; ++pass)
        {
            if (pass == 1)
                top_start_[c] = static_cast<long>(rows_.size());
            for (int k = 1; k < column.count; ++k)
                if (column.values[k] != 0.0 && (label[column.rows[k]] >= top_begin()) == (pass == 1))
                {
                    rows_.push_back(label[column.rows[k]]);
                    values_.push_back(column.values[k]);
                }
        }
    }
    start_[n_] = static_cast<long>(rows_.size());
}

double SubtreeSolver::set_share(int set) const
{
    if (rows_.empty())
        return 0.0;
    return static_cast<double>(start_[set_end_[set]] - start_[set_begin(set)]) /
           static_cast<double>(rows_.size());
}

void SubtreeSolver::forward_set(int set, double* x, double* buffer) const
{
    const int top = top_begin();
    for (int c = set_begin(set); c < set_end_[set]; ++c)
    {
        const double d = values_[start_[c]];
        const double y0 = x[2 * c] / d, y1 = x[2 * c + 1] / d;
        x[2 * c] = y0;
        x[2 * c + 1] = y1;
        for (long k = start_[c] + 1; k < top_start_[c]; ++k)
        {
            const int r = rows_[k];
            x[2 * r] -= values_[k] * y0;
            x[2 * r + 1] -= values_[k] * y1;
        }
        for (long k = top_start_[c]; k < start_[c + 1]; ++k)
        {
            const int r = rows_[k] - top;
            buffer[2 * r] -= values_[k] * y0;
            buffer[2 * r + 1] -= values_[k] * y1;
        }
    }
}

// The top's columns for one right-hand side, on a contiguous copy x of its rows.
void SubtreeSolver::forward_top(double* x) const
{
    const int top = top_begin();
    for (int c = top; c < n_; ++c)
    {
        const double y = x[c - top] / values_[start_[c]];
        x[c - top] = y;
        for (long k = start_[c] + 1; k < start_[c + 1]; ++k)
            x[rows_[k] - top] -= values_[k] * y;
    }
}

void SubtreeSolver::backward_top(double* x) const
{
    const int top = top_begin();
    for (int c = n_ - 1; c >= top; --c)
    {
        double sum = x[c - top];
        for (long k = start_[c] + 1; k < start_[c + 1]; ++k)
            sum -= values_[k] * x[rows_[k] - top];
        x[c - top] = sum / values_[start_[c]];
    }
}

void SubtreeSolver::backward_set(int set, double* x) const
{
    for (int c = set_end_[set] - 1; c >= set_begin(set); --c)
    {
        double sum0 = x[2 * c], sum1 = x[2 * c + 1];
        for (long k = start_[c] + 1; k < start_[c + 1]; ++k)
        {
            const int r = rows_[k];
            sum0 -= values_[k] * x[2 * r];
            sum1 -= values_[k] * x[2 * r + 1];
        }
        const double d = values_[start_[c]];
        x[2 * c] = sum0 / d;
        x[2 * c + 1] = sum1 / d;
    }
}

void SubtreeSolver::solve(const Eigen::MatrixX2d& b, Eigen::MatrixX2d& x, int threads,
                          Workspace& work) const
{
    const int top = top_begin(), n_top = n_ - top;
    work.x.resize(2 * static_cast<std::size_t>(n_));
    work.buffer.assign(4 * static_cast<std::size_t>(n_top), 0.0);
    double* xs = work.x.data();
    for (int c = 0; c < n_; ++c)
    {
        xs[2 * c] = b(perm_[c], 0);
        xs[2 * c + 1] = b(perm_[c], 1);
    }
    // L y = P b: the two sets, then the top (its rows collect both sets' updates, in set order).
    for_both(threads, [&](int set) {
        forward_set(set, xs, work.buffer.data() + 2 * static_cast<std::size_t>(set) * n_top);
    });
    // Each right-hand side's top rows, contiguous: the two threads write apart.
    std::vector<double>& top_rows = work.top_rows;
    top_rows.resize(2 * static_cast<std::size_t>(n_top));
    for (int r = 0; r < n_top; ++r)
        for (int k = 0; k < 2; ++k)
            top_rows[k * n_top + r] = xs[2 * (top + r) + k] + work.buffer[2 * r + k] +
                                      work.buffer[2 * (n_top + r) + k];
    // The top's forward and backward solves (u and v on one thread each); then L' z = y on
    // the two sets.
    for_both(threads, [&](int k) {
        forward_top(top_rows.data() + k * n_top);
        backward_top(top_rows.data() + k * n_top);
    });
    for (int r = 0; r < n_top; ++r)
        for (int k = 0; k < 2; ++k)
            xs[2 * (top + r) + k] = top_rows[k * n_top + r];
    for_both(threads, [&](int set) { backward_set(set, xs); });
    x.resize(n_, 2);
    for (int c = 0; c < n_; ++c)
    {
        x(perm_[c], 0) = xs[2 * c];
        x(perm_[c], 1) = xs[2 * c + 1];
    }
}

}  // namespace vessel::detail
