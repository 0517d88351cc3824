#pragma once

#include <vector>

namespace vessel::detail {

//! Two sets of whole subtrees of a forest, by their roots (SubtreeSolver, SubtreeFactorization).
struct ForestSplit
{
    std::vector<int> roots[2];  //!< subtree roots of each set
};

//! Splits the forest given by \p parent (parent[j] > j, or -1) into two sets of whole subtrees of
//! about equal weight (\p subtree_weight: of each node's subtree): the heaviest subtree of the
//! frontier is expanded into the top (its root) and its children, and the frontier is dealt to
//! the two sets heaviest first, each to the lighter set, until they balance or the top grows
//! too heavy (then the best split seen is kept).
ForestSplit split_forest(const std::vector<int>& parent, const std::vector<double>& subtree_weight);

//! split_forest() as the owner of each node: 0 or 1, the set whose subtree holds it, else 2 (the
//! top, above both sets).
std::vector<int> split_owners(const std::vector<int>& parent,
                              const std::vector<double>& subtree_weight);

}  // namespace vessel::detail
