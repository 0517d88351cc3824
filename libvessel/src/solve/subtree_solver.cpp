#include "solve/subtree_solver.h"

#include "detail/face_jacobian.h"
#include "solve/tree_split.h"
#include "vessel/core/errors.h"

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

}  // namespace

ForestSplit split_forest(const std::vector<int>& parent, const std::vector<double>& subtree_weight)
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
    ForestSplit best;
    double best_lighter = -1.0, top = 0.0;
    for (int expansions = 0; !frontier.empty() && expansions <= kMaxExpansions; ++expansions)
    {
        ForestSplit split;
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

std::vector<int> split_owners(const std::vector<int>& parent,
                              const std::vector<double>& subtree_weight)
{
    const ForestSplit split = split_forest(parent, subtree_weight);
    const int n = static_cast<int>(parent.size());
    std::vector<int> owner(n, 2);
    for (int s = 0; s < 2; ++s)
        for (const int root : split.roots[s])
            owner[root] = s;
    // Parents come after their children, so one pass from the last node settles every subtree.
    for (int k = n - 1; k >= 0; --k)
        if (owner[k] == 2 && parent[k] >= 0 && owner[parent[k]] < 2)
            owner[k] = owner[parent[k]];
    return owner;
}

namespace {

// A supernode of width w stores the triangle of its own columns column by column from the
// diagonal down (w - k entries in column k), then the rows below in panels of kPanel columns
// (the last may be narrower), each panel row by row.
constexpr int kPanel = 4;

// Offset of column j's diagonal in the triangle; triangle_offset(w, w) is the triangle's size.
long triangle_offset(int j, int w)
{
    return static_cast<long>(j) * w - static_cast<long>(j) * (j - 1) / 2;
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

    // The factor's supernodes as they are stored: columns first .. first + width - 1 share the
    // rows rows[0 .. height), the first `width` of them their own; values column-major with a
    // leading dimension of `height`, the diagonal of column k at values[k * height + k].
    struct Source
    {
        int first, width, height;
        const int* rows;
        const double* values;
    };
    std::vector<Source> source;
    if (L.is_super)
    {
        const int* super = static_cast<const int*>(L.super);
        const int* pi = static_cast<const int*>(L.pi);
        const int* px = static_cast<const int*>(L.px);
        const int* rows = static_cast<const int*>(L.s);
        source.reserve(L.nsuper);
        for (std::size_t node = 0; node < L.nsuper; ++node)
            source.push_back({super[node], super[node + 1] - super[node], pi[node + 1] - pi[node],
                              rows + pi[node], x + px[node]});
    }
    else
    {
        const int* p = static_cast<const int*>(L.p);
        const int* nz = static_cast<const int*>(L.nz);
        source.reserve(n_);
        for (int j = 0; j < n_; ++j)
            source.push_back({j, 1, nz[j], static_cast<const int*>(L.i) + p[j], x + p[j]});
    }
    const int n_nodes = static_cast<int>(source.size());

    // Tree of the supernodes: a node's parent holds its first row below its own columns, and
    // every such row is an ancestor. Weights: stored entries of each subtree.
    std::vector<int> node_of(n_, -1);
    for (int k = 0; k < n_nodes; ++k)
    {
        const Source& node = source[k];
        for (int c = 0; c < node.width; ++c)
            if (node.height <= c || node.rows[c] != node.first + c)
                throw SolverError("SubtreeSolver: column " + std::to_string(node.first + c) +
                                  " of the factor does not start with its diagonal");
        for (int c = node.first; c < node.first + node.width; ++c)
            node_of[c] = k;
    }
    std::vector<int> parent(n_nodes, -1);
    std::vector<double> subtree_weight(n_nodes, 0.0);
    for (int k = 0; k < n_nodes; ++k)
    {
        const Source& node = source[k];
        if (node.height > node.width)
            parent[k] = node_of[node.rows[node.width]];
        for (int c = 0; c < node.width; ++c)
            subtree_weight[k] += node.height - c;
        if (parent[k] >= 0)
            subtree_weight[parent[k]] += subtree_weight[k];
    }
    // Owner of each node: the set whose subtree holds it, else the top (2).
    const std::vector<int> owner = split_owners(parent, subtree_weight);
    std::vector<int> order;  // nodes in their new order
    order.reserve(n_nodes);
    std::vector<int> label(n_);  // new column of each column
    int next = 0;
    for (int s = 0; s < 3; ++s)
    {
        for (int k = 0; k < n_nodes; ++k)
            if (owner[k] == s)
            {
                order.push_back(k);
                for (int c = 0; c < source[k].width; ++c)
                    label[source[k].first + c] = next++;
            }
        if (s < 2)
            node_end_[s] = static_cast<int>(order.size());
        if (s == 1)
            top_begin_ = next;
    }

    perm_.resize(n_);
    for (int j = 0; j < n_; ++j)
        perm_[label[j]] = perm ? perm[j] : j;
    long total_rows = 0, total_values = 0;
    for (const Source& node : source)
    {
        total_rows += node.height;
        total_values += static_cast<long>(node.width) * (2 * node.height - node.width + 1) / 2;
    }
    rows_.reserve(total_rows);
    values_.reserve(total_values);
    nodes_.reserve(n_nodes);
    for (const int k : order)
    {
        const Source& from = source[k];
        Node node{label[from.first], from.width, from.height, from.height,
                  static_cast<long>(rows_.size()), static_cast<long>(values_.size())};
        // The rows below are ancestors, in increasing order: those in this node's set (below
        // its subtree's root) before those in the top, and relabelling keeps each group's order.
        for (int r = 0; r < from.height; ++r)
        {
            const int row = label[from.rows[r]];
            rows_.push_back(row);
            if (r >= from.width && row >= top_begin_ && node.set_rows_end == from.height)
                node.set_rows_end = r;
        }
        // The triangle of its own columns, each from its diagonal down; then the rows below in
        // panels of kPanel columns, row by row.
        const auto at = [&](int row, int column) {
            return from.values[static_cast<long>(column) * from.height + row];
        };
        for (int c = 0; c < from.width; ++c)
            for (int r = c; r < from.width; ++r)
                values_.push_back(at(r, c));
        for (int c0 = 0; c0 < from.width; c0 += kPanel)
            for (int r = from.width; r < from.height; ++r)
                for (int c = c0; c < std::min(c0 + kPanel, from.width); ++c)
                    values_.push_back(at(r, c));
        max_below_ = std::max(max_below_, from.height - from.width);
        max_width_ = std::max(max_width_, from.width);
        nodes_.push_back(node);
    }
}

double SubtreeSolver::set_share(int set) const
{
    if (values_.empty())
        return 0.0;
    // Where node k's values start; past the last node, the end of the values (a set, and the
    // top, may be empty).
    const auto value_start = [&](int k) {
        return k < static_cast<int>(nodes_.size()) ? nodes_[k].value_start
                                                   : static_cast<long>(values_.size());
    };
    return static_cast<double>(value_start(node_end_[set]) - value_start(node_begin(set))) /
           static_cast<double>(values_.size());
}

template <int Lanes>
void SubtreeSolver::forward_node(const Node& node, double* x, double* top_buffer,
                                 double* scratch) const
{
    const int w = node.width, below = node.height - w;
    const double* V = values_.data() + node.value_start;
    double* y = x + 2 * static_cast<long>(node.first_column);
    // The triangle of its own columns.
    for (int j = 0; j < w; ++j)
    {
        const double* column = V + triangle_offset(j, w);  // rows j, j + 1, ... w - 1
        for (int q = 0; q < Lanes; ++q)
        {
            const double yj = y[2 * j + q] /= column[0];
            for (int i = j + 1; i < w; ++i)
                y[2 * i + q] -= column[i - j] * yj;
        }
    }
    // The rows below, summed over its columns in `scratch` panel by panel (one pass over
    // `scratch` per kPanel columns), then scattered once.
    std::fill(scratch, scratch + 2 * below, 0.0);
    const double* panel = V + triangle_offset(w, w);
    for (int j = 0; j < w; j += kPanel)
    {
        const double* yj = y + 2 * j;
        if (j + kPanel <= w)
        {
            for (int i = 0; i < below; ++i, panel += kPanel)
                for (int q = 0; q < Lanes; ++q)
                    scratch[2 * i + q] += panel[0] * yj[q] + panel[1] * yj[2 + q] +
                                          panel[2] * yj[4 + q] + panel[3] * yj[6 + q];
        }
        else
        {
            const int r = w - j;
            for (int i = 0; i < below; ++i, panel += r)
                for (int c = 0; c < r; ++c)
                    for (int q = 0; q < Lanes; ++q)
                        scratch[2 * i + q] += panel[c] * yj[2 * c + q];
        }
    }
    const int* rows = rows_.data() + node.row_start + w;
    const int split = top_buffer ? node.set_rows_end - w : below;
    for (int i = 0; i < split; ++i)
        for (int q = 0; q < Lanes; ++q)
            x[2 * static_cast<long>(rows[i]) + q] -= scratch[2 * i + q];
    for (int i = split; i < below; ++i)
        for (int q = 0; q < Lanes; ++q)
            top_buffer[2 * static_cast<long>(rows[i] - top_begin_) + q] -= scratch[2 * i + q];
}

template <int Lanes>
void SubtreeSolver::backward_node(const Node& node, double* x, double* scratch) const
{
    const int w = node.width, below = node.height - w;
    const double* V = values_.data() + node.value_start;
    double* y = x + 2 * static_cast<long>(node.first_column);
    const int* rows = rows_.data() + node.row_start + w;
    // The solution's rows below, gathered once, and each column's product with them (a panel
    // per pass, each column with its own sums, so that the additions do not wait on each
    // other), in `sums`.
    double* sums = scratch + 2 * static_cast<long>(below);
    for (int i = 0; i < below; ++i)
        for (int q = 0; q < Lanes; ++q)
            scratch[2 * i + q] = x[2 * static_cast<long>(rows[i]) + q];
    // Panels last first and rows bottom up, so that the whole backward solve reads the factor
    // in one descending sweep, which the hardware prefetches as well as an ascending one (in
    // node order, but each node front to back, it ran at half the forward solve's speed).
    const double* panels = V + triangle_offset(w, w);
    for (int j = (w - 1) / kPanel * kPanel; j >= 0; j -= kPanel)
    {
        const int r = std::min(kPanel, w - j);
        const double* panel = panels + static_cast<long>(j) * below + static_cast<long>(below - 1) * r;
        double s[2 * kPanel] = {};
        if (r == kPanel)
        {
            for (int i = below - 1; i >= 0; --i, panel -= kPanel)
                for (int q = 0; q < Lanes; ++q)
                {
                    const double g = scratch[2 * i + q];
                    s[q] += panel[0] * g;
                    s[2 + q] += panel[1] * g;
                    s[4 + q] += panel[2] * g;
                    s[6 + q] += panel[3] * g;
                }
        }
        else
        {
            for (int i = below - 1; i >= 0; --i, panel -= r)
                for (int c = 0; c < r; ++c)
                    for (int q = 0; q < Lanes; ++q)
                        s[2 * c + q] += panel[c] * scratch[2 * i + q];
        }
        std::copy(s, s + 2 * r, sums + 2 * j);
    }
    // The transposed triangle of its own columns, last column first.
    for (int j = w - 1; j >= 0; --j)
    {
        const double* column = V + triangle_offset(j, w);  // rows j, j + 1, ... w - 1
        for (int q = 0; q < Lanes; ++q)
        {
            double sum = sums[2 * j + q];
            for (int i = j + 1; i < w; ++i)
                sum += column[i - j] * y[2 * i + q];
            y[2 * j + q] = (y[2 * j + q] - sum) / column[0];
        }
    }
}

void SubtreeSolver::solve(const Eigen::MatrixX2d& b, Eigen::MatrixX2d& x, int threads,
                          Workspace& work) const
{
    work.x.resize(2 * static_cast<std::size_t>(n_));
    double* xs = work.x.data();
    for (int c = 0; c < n_; ++c)
    {
        xs[2 * c] = b(perm_[c], 0);
        xs[2 * c + 1] = b(perm_[c], 1);
    }
    solve_in_order(xs, threads, work);
    x.resize(n_, 2);
    for (int c = 0; c < n_; ++c)
    {
        x(perm_[c], 0) = xs[2 * c];
        x(perm_[c], 1) = xs[2 * c + 1];
    }
}

void SubtreeSolver::solve_in_order(double* xs, int threads, Workspace& work) const
{
    const int top = top_begin_, n_top = n_ - top;
    work.buffer.assign(4 * static_cast<std::size_t>(n_top), 0.0);
    for (auto& scratch : work.scratch)
        scratch.resize(2 * static_cast<std::size_t>(max_below_ + max_width_));
    const int n_nodes = static_cast<int>(nodes_.size());
    // L y = P b: the two sets, then the top (its rows collect both sets' updates, in set order).
    for_both(threads, [&](int set) {
        double* buffer = work.buffer.data() + 2 * static_cast<std::size_t>(set) * n_top;
        for (int k = node_begin(set); k < node_end_[set]; ++k)
            forward_node<2>(nodes_[k], xs, buffer, work.scratch[set].data());
    });
    for (int r = 0; r < n_top; ++r)
        for (int k = 0; k < 2; ++k)
            xs[2 * (top + r) + k] += work.buffer[2 * r + k] + work.buffer[2 * (n_top + r) + k];
    // The top's forward and backward solves, u and v on one thread each (lane k of xs); then
    // L' z = y on the two sets.
    for_both(threads, [&](int k) {
        for (int node = node_end_[1]; node < n_nodes; ++node)
            forward_node<1>(nodes_[node], xs + k, nullptr, work.scratch[k].data());
        for (int node = n_nodes - 1; node >= node_end_[1]; --node)
            backward_node<1>(nodes_[node], xs + k, work.scratch[k].data());
    });
    for_both(threads, [&](int set) {
        for (int k = node_end_[set] - 1; k >= node_begin(set); --k)
            backward_node<2>(nodes_[k], xs, work.scratch[set].data());
    });
}

}  // namespace vessel::detail
