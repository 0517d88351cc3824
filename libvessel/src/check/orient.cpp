#include "detail/orient.h"

#include <algorithm>
#include <cstdint>
#include <utility>

namespace vessel::detail {

namespace {

// The neighbour of a triangle across one of its edges, and whether both run that edge the same
// way (then one of them has to be reversed).
struct Neighbour
{
    int triangle = -1;
    bool same_way = false;
};

// neighbours[3 t + k]: the other triangle across edge k (corner k to k + 1) of triangle t, if
// exactly two triangles share that edge.
std::vector<Neighbour> edge_neighbours(const std::vector<std::array<int, 3>>& T,
                                       std::uint64_t n)
{
    struct Run
    {
        std::uint64_t key;
        int corner;  // 3 t + k
        bool forward;
    };
    std::vector<Run> runs;
    runs.reserve(3 * T.size());
    for (std::size_t t = 0; t < T.size(); ++t)
        for (int k = 0; k < 3; ++k)
        {
            const std::uint64_t a = T[t][k], b = T[t][(k + 1) % 3];
            runs.push_back({std::min(a, b) * n + std::max(a, b), static_cast<int>(3 * t + k), a < b});
        }
    std::sort(runs.begin(), runs.end(), [](const Run& x, const Run& y) { return x.key < y.key; });
    std::vector<Neighbour> out(3 * T.size());
    for (std::size_t i = 0; i < runs.size();)
    {
        std::size_t j = i + 1;
        while (j < runs.size() && runs[j].key == runs[i].key)
            ++j;
        if (j - i == 2)
        {
            const Run& x = runs[i];
            const Run& y = runs[i + 1];
            out[x.corner] = {y.corner / 3, x.forward == y.forward};
            out[y.corner] = {x.corner / 3, x.forward == y.forward};
        }
        i = j;
    }
    return out;
}

}  // namespace

Orientation orient_consistently(std::vector<std::array<int, 3>>& triangles, std::size_t n_vertices)
{
    const std::vector<Neighbour> neighbours = edge_neighbours(triangles, n_vertices);
    const int n = static_cast<int>(triangles.size());
    std::vector<signed char> flip(n, -1);  // -1: not reached yet; 0 keep; 1 reverse
    std::vector<int> piece;
    Orientation out;
    for (int seed = 0; seed < n; ++seed)
    {
        if (flip[seed] >= 0)
            continue;
        flip[seed] = 0;
        piece.assign(1, seed);
        int reversed = 0;
        for (std::size_t q = 0; q < piece.size(); ++q)
        {
            const int t = piece[q];
            for (int k = 0; k < 3; ++k)
            {
                const Neighbour& nb = neighbours[3 * t + k];
                if (nb.triangle < 0)
                    continue;
                const signed char wanted = static_cast<signed char>(flip[t] ^ nb.same_way);
                if (flip[nb.triangle] < 0)
                {
                    flip[nb.triangle] = wanted;
                    reversed += wanted;
                    piece.push_back(nb.triangle);
                }
                else if (flip[nb.triangle] != wanted)
                {
                    out.conflict_a = std::min(t, nb.triangle);
                    out.conflict_b = std::max(t, nb.triangle);
                    out.reversed = 0;
                    return out;
                }
            }
        }
        const bool keep_majority = 2 * reversed > static_cast<int>(piece.size());
        for (const int t : piece)
            flip[t] = static_cast<signed char>(flip[t] ^ keep_majority);
        out.reversed += keep_majority ? static_cast<int>(piece.size()) - reversed : reversed;
    }
    for (int t = 0; t < n; ++t)
        if (flip[t])
            std::swap(triangles[t][1], triangles[t][2]);
    return out;
}

}  // namespace vessel::detail
