#pragma once
// The sparsity pattern of a symmetric matrix over the (u, v) of n vertices (unknowns 2i and
// 2i + 1), upper triangle, built straight from which vertices couple: no triplets to sort. The
// SLIM global step's normal matrix and the area polish's Newton Hessian have it, and
// PairedCholmod orders it by its vertex graph.

#include <Eigen/Sparse>

#include <algorithm>
#include <array>
#include <cstddef>
#include <vector>

namespace vessel::detail {

//! Column 2J + k (k = 0 for u, 1 for v) holds rows 2I and 2I + 1 of each vertex I < J that
//! couples with J, in increasing order, then 2J, and for k = 1 also 2J + 1. An entry's value
//! index therefore follows from the rank of I among J's lower neighbours alone (index()).
class PairedPattern
{
public:
    //! \p start (n + 1 offsets) and \p below: vertex J's lower neighbours I < J in
    //! below[start[J], start[J + 1]), in any order, repeats allowed.
    PairedPattern(int n, std::vector<int> start, std::vector<int> below)
        : start_(std::move(start)), below_(std::move(below)), distinct_(n), outer_(2 * n + 1, 0)
    {
        inner_.reserve(4 * below_.size() + 3 * static_cast<std::size_t>(n));
        for (int J = 0; J < n; ++J)
        {
            const auto first = below_.begin() + start_[J];
            const auto end = below_.begin() + start_[J + 1];
            std::sort(first, end);
            const auto last = std::unique(first, end);
            distinct_[J] = static_cast<int>(last - first);
            for (int k = 0; k < 2; ++k)
            {
                for (auto I = first; I != last; ++I)
                {
                    inner_.push_back(2 * *I);
                    inner_.push_back(2 * *I + 1);
                }
                inner_.push_back(2 * J);
                if (k == 1)
                    inner_.push_back(2 * J + 1);
                outer_[2 * J + 1 + k] = static_cast<int>(inner_.size());
            }
        }
    }

    //! The pattern of \p faces triangles whose vertices couple: corners(f, s) writes triangle
    //! f's vertices (those that take part, 0-3 of them) into s in increasing order and returns
    //! how many.
    template <class Corners>
    static PairedPattern of_triangles(int n, std::size_t faces, const Corners& corners)
    {
        std::vector<int> start(n + 1, 0);
        std::array<int, 3> s{};
        for (std::size_t f = 0; f < faces; ++f)
            for (int k = 1, count = corners(f, s); k < count; ++k)
                start[s[k] + 1] += k;
        for (int J = 0; J < n; ++J)
            start[J + 1] += start[J];
        std::vector<int> below(start[n]);
        std::vector<int> fill(start.begin(), start.end() - 1);
        for (std::size_t f = 0; f < faces; ++f)
            for (int k = 1, count = corners(f, s); k < count; ++k)
                for (int l = 0; l < k; ++l)
                    below[fill[s[k]]++] = s[l];
        return PairedPattern(n, std::move(start), std::move(below));
    }

    //! The value index of entry (r, c), r <= c, of a coupled pair (or r / 2 == c / 2).
    int index(int r, int c) const { return index_at(rank(r / 2, c / 2), r, c); }

    //! Vertex I's place among vertex J's coupled vertices I' <= J, I <= J: the four entries of
    //! the pair (I, J) share it (index_at()), so a block's entries need one search per pair.
    int rank(int I, int J) const
    {
        if (I == J)
            return distinct_[J];
        const auto first = below_.begin() + start_[J];
        return static_cast<int>(std::lower_bound(first, first + distinct_[J], I) - first);
    }

    //! n, the vertices the pattern is over.
    int vertices() const { return static_cast<int>(distinct_.size()); }

    //! rank(I, J) where vertices I < J couple (both in [0, n)), else -1.
    int coupled_rank(int I, int J) const
    {
        const int r = rank(I, J);
        return r < distinct_[J] && below_[start_[J] + r] == I ? r : -1;
    }

    //! index(r, c) given rank(r / 2, c / 2).
    int index_at(int rank, int r, int c) const { return outer_[c] + 2 * rank + r % 2; }

    //! \p A resized to 2n x 2n with this pattern, compressed, every value 0.
    void into(Eigen::SparseMatrix<double>& A) const
    {
        const Eigen::Index size = static_cast<Eigen::Index>(outer_.size()) - 1;
        A.resize(size, size);
        A.resizeNonZeros(static_cast<Eigen::Index>(inner_.size()));
        std::copy(outer_.begin(), outer_.end(), A.outerIndexPtr());
        std::copy(inner_.begin(), inner_.end(), A.innerIndexPtr());
        std::fill(A.valuePtr(), A.valuePtr() + inner_.size(), 0.0);
    }

private:
    std::vector<int> start_, below_, distinct_, outer_, inner_;
};

}  // namespace vessel::detail
