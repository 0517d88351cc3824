#pragma once
// A triangle's term of a quadratic proxy, kron(G, W) over its three corners' (u, v) (G the 3 x 3
// Gram matrix of its gradient operator times its area, W a 2 x 2 weight, both positive
// semidefinite), fitted to a sparsity pattern that does not couple some pairs of its corners:
// SLIM's global step keeps the pattern it analysed while edge flips change the scaffold's
// triangles (injective.cpp), and a triangle that a flip made couples a pair the pattern may not
// hold.

#include <array>

namespace vessel::detail {

//! The Gram matrix G' of the split term kron(G', W) for \p gram (G's lower triangle, in the order
//! (0,0) (1,0) (1,1) (2,0) (2,1) (2,2)) where \p uncoupled[k] says that the pair of corners
//! other than k is not coupled (k = 2: corners 0 and 1). With one or two uncoupled pairs,
//! G' = G + S G S, S = diag(s), s = -1 at the corner that the uncoupled pairs share (either of
//! one pair's) and +1 elsewhere: G' is 2 G with the couplings of that corner cancelled.
//! S G S is congruent to G, so G' - G is positive semidefinite: the split term bounds the
//! triangle's own from above, and the proxy stays convex. With all three pairs uncoupled no such
//! s exists, and G' = 3 diag(G) (Cauchy-Schwarz: (a + b + c)^2 <= 3 (a^2 + b^2 + c^2)). Where
//! nothing is uncoupled G' = G.
inline std::array<double, 6> split_gram(const std::array<double, 6>& gram,
                                        const std::array<bool, 3>& uncoupled)
{
    const int count = uncoupled[0] + uncoupled[1] + uncoupled[2];
    if (count == 0)
        return gram;
    // The corner in most uncoupled pairs: corner c is in the pairs other than c's own.
    int flipped = 0, most = -1;
    for (int c = 0; c < 3; ++c)
        if (const int in = count - uncoupled[c]; in > most)
        {
            flipped = c;
            most = in;
        }
    std::array<double, 6> split{};
    int g = 0;
    for (int k = 0; k < 3; ++k)
        for (int l = 0; l <= k; ++l, ++g)
            if (count == 3)
                split[g] = l == k ? 3.0 * gram[g] : 0.0;
            else
                split[g] = (k == flipped) == (l == flipped) ? 2.0 * gram[g] : 0.0;
    return split;
}

}  // namespace vessel::detail
