#include "detail/orient.h"

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
                                       const EdgeGroups& edges)
{
    const auto forward = [&](int c) {
        const auto& t = T[static_cast<std::size_t>(c / 3)];
        return t[c % 3] < t[(c % 3 + 1) % 3];
    };
    std::vector<Neighbour> out(3 * T.size());
    for (std::size_t e = 0; e < edges.size(); ++e)
        if (edges.count(e) == 2)
        {
            const int x = edges.begin(e)[0], y = edges.begin(e)[1];
            const bool same_way = forward(x) == forward(y);
            out[static_cast<std::size_t>(x)] = {y / 3, same_way};
            out[static_cast<std::size_t>(y)] = {x / 3, same_way};
        }
    return out;
}

}  // namespace

Orientation orient_consistently(std::vector<std::array<int, 3>>& triangles, const EdgeGroups& edges)
{
    const std::vector<Neighbour> neighbours = edge_neighbours(triangles, edges);
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
