#include "solve/paired_symbolic.h"

#include <algorithm>
#include <cstddef>
#include <memory>

namespace vessel::detail {

namespace {

constexpr int kNone = -1;

struct FactorDeleter
{
    cholmod_common* c;
    void operator()(cholmod_factor* L) const { cholmod_free_factor(&L, c); }
};
using FactorPtr = std::unique_ptr<cholmod_factor, FactorDeleter>;

// G's elimination tree and column counts in the order `perm` (which becomes the final order:
// postordered by the column counts where c.postorder is set, as cholmod_analyze_p2() does).
bool eliminate(const cholmod_sparse& graph, std::vector<int>& perm, std::vector<int>& parent,
               std::vector<int>& count, cholmod_common& c)
{
    const int n = static_cast<int>(graph.ncol);
    std::vector<int> post(n), first(n), level(n);
    cholmod_sparse G = graph;  // CHOLMOD's signature takes a non-const matrix; it is only read
    if (!cholmod_analyze_ordering(&G, CHOLMOD_GIVEN, perm.data(), nullptr, 0, parent.data(),
                                  post.data(), count.data(), first.data(), level.data(), &c))
        return false;
    if (!c.postorder)
        return true;
    if (cholmod_postorder(parent.data(), n, count.data(), post.data(), &c) != n)
        return false;
    std::vector<int> new_of(n), work(n);
    for (int k = 0; k < n; ++k)
        new_of[post[k]] = k;
    for (int k = 0; k < n; ++k)
        work[k] = perm[post[k]];
    perm.swap(work);
    for (int k = 0; k < n; ++k)
        work[k] = count[post[k]];
    count.swap(work);
    for (int k = 0; k < n; ++k)
        work[k] = parent[post[k]] == kNone ? kNone : new_of[parent[post[k]]];
    parent.swap(work);
    return true;
}

// The supernodes that partition the vertices into ranges [first[s], first[s + 1]) as a tree:
// each vertex's supernode, and each supernode's parent (the supernode of its last vertex's
// parent in the elimination tree, or kNone).
void supernode_tree(const std::vector<int>& first, const std::vector<int>& parent,
                    std::vector<int>& supernode_of, std::vector<int>& super_parent)
{
    const int count = static_cast<int>(first.size()) - 1;
    supernode_of.resize(parent.size());
    super_parent.resize(static_cast<std::size_t>(count));
    for (int s = 0; s < count; ++s)
        std::fill(supernode_of.begin() + first[s], supernode_of.begin() + first[s + 1], s);
    for (int s = 0; s < count; ++s)
    {
        const int last = parent[first[s + 1] - 1];
        super_parent[s] = last == kNone ? kNone : supernode_of[last];
    }
}

// A's relaxed supernodes as vertex ranges.
struct Supernodes
{
    std::vector<int> first;  // each supernode's first vertex, and n at the end
    std::vector<int> rows;   // each supernode's rows of G (its own vertices and those below)
};

// CHOLMOD's fundamental supernodes of A, merged by its relaxed amalgamation rule on A's
// column counts (cholmod_super_symbolic2()). A's fundamental supernodes are G's, each vertex
// two columns: column 2j's parent is 2j + 1, whose count is one less and whose only child it
// is; 2j + 1 and 2j + 2 chain exactly where j and j + 1 do.
Supernodes relaxed_supernodes(const std::vector<int>& parent, const std::vector<int>& count,
                              const cholmod_common& c)
{
    const int n = static_cast<int>(parent.size());
    std::vector<int> children(n, 0);
    for (int j = 0; j < n; ++j)
        if (parent[j] != kNone)
            ++children[parent[j]];
    std::vector<int> first;  // of each fundamental supernode
    if (n > 0)
        first.push_back(0);
    for (int j = 1; j < n; ++j)
        if (parent[j - 1] != j || count[j - 1] != count[j] + 1 || children[j] > 1)
            first.push_back(j);
    const int fundamental = static_cast<int>(first.size());
    first.push_back(n);
    std::vector<int> supernode_of, super_parent, merged(fundamental, kNone);
    supernode_tree(first, parent, supernode_of, super_parent);
    // A's counts: columns, zeros and the entries of each supernode's leading column.
    std::vector<long> columns(fundamental), zeros(fundamental, 0), leading(fundamental);
    for (int s = 0; s < fundamental; ++s)
    {
        columns[s] = 2L * (first[s + 1] - first[s]);
        leading[s] = 2L * count[first[s]];
    }
    for (int s = fundamental - 2; s >= 0; --s)
    {
        if (super_parent[s] == kNone)
            continue;
        int current = super_parent[s];  // s's parent now, with path compression
        while (merged[current] != kNone)
            current = merged[current];
        for (int t = super_parent[s], next; merged[t] != kNone; t = next)
        {
            next = merged[t];
            merged[t] = current;
        }
        if (current != s + 1)
            continue;
        const long nscol0 = columns[s], nscol1 = columns[s + 1], ns = nscol0 + nscol1;
        long total_zeros = zeros[s + 1];
        bool merge = false;
        if (ns <= static_cast<long>(c.nrelax[0]))
            merge = true;
        else
        {
            const long new_zeros = nscol0 * (leading[s + 1] + nscol0 - leading[s]);
            if (new_zeros == 0)
                merge = true;
            else
            {
                // The fraction of zeros of the merged supernode, in CHOLMOD's arithmetic.
                const double xns = static_cast<double>(ns);
                const double size =
                    xns * (xns + 1) / 2 + xns * (static_cast<double>(leading[s + 1]) - nscol1);
                const double z =
                    (static_cast<double>(total_zeros) + static_cast<double>(new_zeros)) / size;
                total_zeros += new_zeros;
                merge = (ns <= static_cast<long>(c.nrelax[1]) && z < c.zrelax[0]) ||
                        (ns <= static_cast<long>(c.nrelax[2]) && z < c.zrelax[1]) ||
                        z < c.zrelax[2];
            }
        }
        if (merge)
        {
            zeros[s] = total_zeros;
            merged[s + 1] = s;
            leading[s] = nscol0 + leading[s + 1];
            columns[s] += columns[s + 1];
        }
    }
    Supernodes relaxed;
    for (int s = 0; s < fundamental; ++s)
        if (merged[s] == kNone)
        {
            relaxed.first.push_back(first[s]);
            relaxed.rows.push_back(static_cast<int>(leading[s] / 2));
        }
    relaxed.first.push_back(n);
    return relaxed;
}

}  // namespace

VertexGraph vertex_graph(const Eigen::SparseMatrix<double>& A)
{
    const int n = static_cast<int>(A.cols()) / 2;
    VertexGraph graph;
    graph.column_start.assign(static_cast<std::size_t>(n) + 1, 0);
    graph.rows.reserve(static_cast<std::size_t>(A.nonZeros()) / 3);
    std::vector<int> seen(static_cast<std::size_t>(n), kNone);
    int diagonal = 0;  // vertices with a diagonal block
    for (int J = 0; J < n; ++J)
    {
        for (int j = 2 * J; j < 2 * J + 2; ++j)
            for (Eigen::SparseMatrix<double>::InnerIterator entry(A, j); entry; ++entry)
                if (const int I = static_cast<int>(entry.row()) / 2; I <= J && seen[I] != J)
                {
                    seen[I] = J;
                    graph.rows.push_back(I);
                    diagonal += I == J ? 1 : 0;
                }
        graph.column_start[J + 1] = static_cast<int>(graph.rows.size());
    }
    const std::size_t off_diagonal = graph.rows.size() - static_cast<std::size_t>(diagonal);
    graph.whole_blocks = diagonal == n && static_cast<std::size_t>(A.nonZeros()) ==
                                              4 * off_diagonal + 3 * static_cast<std::size_t>(n);
    return graph;
}

cholmod_factor* paired_symbolic(const cholmod_sparse& graph, const std::vector<int>& vertex_order,
                                cholmod_common& c)
{
    const int n = static_cast<int>(graph.ncol);
    std::vector<int> perm = vertex_order, parent(n), count(n);
    if (!eliminate(graph, perm, parent, count, c))
        return nullptr;
    const Supernodes supernodes = relaxed_supernodes(parent, count, c);
    const std::vector<int>& first = supernodes.first;
    const int nsuper = static_cast<int>(first.size()) - 1;
    std::vector<int> supernode_of, super_parent;
    supernode_tree(first, parent, supernode_of, super_parent);

    // G in the final order: for each vertex k the vertices i < k next to it.
    std::vector<int> new_of(n);
    for (int k = 0; k < n; ++k)
        new_of[perm[k]] = k;
    const auto* gp = static_cast<const int*>(graph.p);
    const auto* gi = static_cast<const int*>(graph.i);
    std::vector<int> below_start(n + 1, 0);
    for (int J = 0; J < n; ++J)
        for (int p = gp[J]; p < gp[J + 1]; ++p)
            if (const int I = gi[p]; I != J)
                ++below_start[std::max(new_of[I], new_of[J]) + 1];
    for (int k = 0; k < n; ++k)
        below_start[k + 1] += below_start[k];
    std::vector<int> below(below_start[n]), fill(below_start.begin(), below_start.end() - 1);
    for (int J = 0; J < n; ++J)
        for (int p = gp[J]; p < gp[J + 1]; ++p)
            if (const int I = gi[p]; I != J)
            {
                const int a = new_of[I], b = new_of[J];
                below[fill[std::max(a, b)]++] = std::min(a, b);
            }

    // Each supernode's rows on G: its own vertices, then every later vertex k whose row
    // subtree passes through it (k is appended in increasing order, so each list is sorted).
    std::vector<int> rows_start(nsuper + 1, 0);
    for (int s = 0; s < nsuper; ++s)
        rows_start[s + 1] = rows_start[s] + supernodes.rows[s];
    std::vector<int> rows(rows_start[nsuper]), filled(rows_start.begin(), rows_start.end() - 1);
    std::vector<int> mark(nsuper, kNone);
    for (int s = 0; s < nsuper; ++s)
        for (int k = first[s]; k < first[s + 1]; ++k)
            rows[filled[s]++] = k;
    for (int s = 0; s < nsuper; ++s)
        for (int k = first[s]; k < first[s + 1]; ++k)
        {
            mark[s] = k;
            for (int p = below_start[k]; p < below_start[k + 1]; ++p)
                for (int t = supernode_of[below[p]]; t != kNone && mark[t] != k;
                     t = super_parent[t])
                {
                    mark[t] = k;
                    if (filled[t] == rows_start[t + 1])  // more rows than the column counts say
                        return nullptr;
                    rows[filled[t]++] = k;
                }
        }

    for (int s = 0; s < nsuper; ++s)
        if (filled[s] != rows_start[s + 1])  // fewer rows than the column counts say
            return nullptr;

    // A's factor: every vertex row two rows, every supernode twice its columns.
    FactorPtr L(cholmod_allocate_factor(2 * static_cast<std::size_t>(n), &c), FactorDeleter{&c});
    if (!L)
        return nullptr;
    auto* l_perm = static_cast<int*>(L->Perm);
    auto* l_count = static_cast<int*>(L->ColCount);
    for (int k = 0; k < n; ++k)
    {
        l_perm[2 * k] = 2 * perm[k];
        l_perm[2 * k + 1] = 2 * perm[k] + 1;
        l_count[2 * k] = 2 * count[k];
        l_count[2 * k + 1] = 2 * count[k] - 1;
    }
    std::size_t ssize = 0, xsize = 0;
    for (int s = 0; s < nsuper; ++s)
    {
        const std::size_t nsrow = 2 * static_cast<std::size_t>(supernodes.rows[s]);
        ssize += nsrow;
        xsize += 2 * static_cast<std::size_t>(first[s + 1] - first[s]) * nsrow;
    }
    L->ordering = CHOLMOD_GIVEN;
    L->nsuper = static_cast<std::size_t>(nsuper);
    L->ssize = std::max<std::size_t>(1, ssize);
    L->xsize = std::max<std::size_t>(1, xsize);
    if (!cholmod_change_factor(CHOLMOD_PATTERN, true, true, true, true, L.get(), &c))
        return nullptr;
    auto* super = static_cast<int*>(L->super);
    auto* pi = static_cast<int*>(L->pi);
    auto* px = static_cast<int*>(L->px);
    auto* ls = static_cast<int*>(L->s);
    ls[0] = 0;
    int p = 0, x = 0;
    std::size_t max_c = 1, max_e = 1;  // CHOLMOD's workspace sizes (update block, solve)
    for (int s = 0; s < nsuper; ++s)
    {
        super[s] = 2 * first[s];
        pi[s] = p;
        px[s] = x;
        for (int q = rows_start[s]; q < rows_start[s + 1]; ++q)
        {
            ls[p++] = 2 * rows[q];
            ls[p++] = 2 * rows[q] + 1;
        }
        const int nscol = 2 * (first[s + 1] - first[s]);
        const int nsrow = 2 * supernodes.rows[s];
        x += nscol * nsrow;
        // The rows below the diagonal block, in runs by the supernode that holds them.
        max_e = std::max<std::size_t>(max_e, static_cast<std::size_t>(nsrow - nscol));
        const int begin = pi[s] + nscol, end = p;
        for (int q = begin, run = begin; q <= end; ++q)
            if (q == end || supernode_of[ls[q] / 2] != supernode_of[ls[run] / 2])
            {
                if (q > run)
                    max_c = std::max<std::size_t>(max_c, static_cast<std::size_t>(q - run) *
                                                             static_cast<std::size_t>(end - run));
                run = q;
            }
    }
    super[nsuper] = 2 * n;
    pi[nsuper] = p;
    px[nsuper] = x;
    L->maxcsize = max_c;
    L->maxesize = max_e;
    return L.release();
}

}  // namespace vessel::detail
