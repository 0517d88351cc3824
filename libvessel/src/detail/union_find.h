#pragma once

// Disjoint sets over 0..n-1 (validation.cpp: components and vertex fans; split.cpp: merge tree).

#include <cstddef>
#include <numeric>
#include <vector>

namespace vessel::detail {

class UnionFind
{
public:
    explicit UnionFind(std::size_t n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), 0); }
    int find(int x)
    {
        while (parent_[x] != x)
            x = parent_[x] = parent_[parent_[x]];
        return x;
    }
    //! Joins the sets of \p a and \p b; returns the surviving root (\p a's).
    int unite(int a, int b)
    {
        a = find(a);
        b = find(b);
        if (a != b)
            parent_[b] = a;
        return a;
    }

private:
    std::vector<int> parent_;
};

}  // namespace vessel::detail
