#include "solve/reach_solve.h"

#include <algorithm>

namespace vessel::detail {

ReachSolve reach_forward_solve(const cholmod_factor& L, const Eigen::SparseMatrix<double>& U)
{
    const int n = static_cast<int>(L.n);
    const int nsuper = static_cast<int>(L.nsuper);
    const auto* super = static_cast<const int*>(L.super);
    const auto* pi = static_cast<const int*>(L.pi);
    const auto* px = static_cast<const int*>(L.px);
    const auto* s = static_cast<const int*>(L.s);
    const auto* perm = static_cast<const int*>(L.Perm);
    const auto* x = static_cast<const double*>(L.x);

    std::vector<int> supernode_of(n), position(n);  // column -> supernode; unknown -> column
    for (int j = 0; j < nsuper; ++j)
        std::fill(supernode_of.begin() + super[j], supernode_of.begin() + super[j + 1], j);
    for (int k = 0; k < n; ++k)
        position[perm ? perm[k] : k] = k;
    // A supernode's parent holds the first row below its diagonal block.
    const auto parent = [&](int j) {
        const int columns = super[j + 1] - super[j];
        return pi[j + 1] - pi[j] > columns ? supernode_of[s[pi[j] + columns]] : -1;
    };

    // The reach: every supernode on a path from a nonzero of P U to its root.
    std::vector<char> reached(nsuper, 0);
    std::vector<int> order;
    for (int k = 0; k < U.outerSize(); ++k)
        for (Eigen::SparseMatrix<double>::InnerIterator entry(U, k); entry; ++entry)
            for (int j = supernode_of[position[entry.row()]]; j >= 0 && !reached[j]; j = parent(j))
            {
                reached[j] = 1;
                order.push_back(j);
            }
    std::sort(order.begin(), order.end());  // children before parents

    ReachSolve solved;
    std::vector<int> compact(n, -1);  // column -> row of Y
    for (int j : order)
        for (int c = super[j]; c < super[j + 1]; ++c)
        {
            compact[c] = static_cast<int>(solved.rows.size());
            solved.rows.push_back(c);
        }
    Eigen::MatrixXd& Y = solved.Y;
    Y.setZero(static_cast<Eigen::Index>(solved.rows.size()), U.cols());
    for (int k = 0; k < U.outerSize(); ++k)
        for (Eigen::SparseMatrix<double>::InnerIterator entry(U, k); entry; ++entry)
            Y(compact[position[entry.row()]], k) += entry.value();

    // Per supernode (its block nr x nc, column-major, the diagonal block on top): the diagonal
    // block's triangular solve, then the rows below it updated.
    Eigen::MatrixXd below;
    for (int j : order)
    {
        const int nc = super[j + 1] - super[j], nr = pi[j + 1] - pi[j];
        const Eigen::Map<const Eigen::MatrixXd> block(x + px[j], nr, nc);
        auto diagonal = Y.middleRows(compact[super[j]], nc);
        block.topRows(nc).triangularView<Eigen::Lower>().solveInPlace(diagonal);
        if (nr == nc)
            continue;
        below.noalias() = block.bottomRows(nr - nc) * diagonal;
        for (int r = 0; r < nr - nc; ++r)
            Y.row(compact[s[pi[j] + nc + r]]) -= below.row(r);
    }
    return solved;
}

}  // namespace vessel::detail
