#include "detail/edge_groups.h"

#include <algorithm>

namespace vessel::detail {

EdgeGroups edge_groups(const std::vector<std::array<int, 3>>& T, std::size_t n_vertices)
{
    const auto lower = [&](int c) {
        const auto& t = T[static_cast<std::size_t>(c / 3)];
        return std::min(t[c % 3], t[(c % 3 + 1) % 3]);
    };
    const auto upper = [&](int c) {
        const auto& t = T[static_cast<std::size_t>(c / 3)];
        return std::max(t[c % 3], t[(c % 3 + 1) % 3]);
    };
    const int n_corners = static_cast<int>(3 * T.size());
    // Counting sort by the smaller vertex; each vertex's corners stay in corner order.
    std::vector<int> offset(n_vertices + 1, 0);
    for (int c = 0; c < n_corners; ++c)
        ++offset[static_cast<std::size_t>(lower(c)) + 1];
    for (std::size_t v = 0; v < n_vertices; ++v)
        offset[v + 1] += offset[v];
    EdgeGroups out;
    out.corners.resize(static_cast<std::size_t>(n_corners));
    {
        std::vector<int> next(offset.begin(), offset.end() - 1);
        for (int c = 0; c < n_corners; ++c)
            out.corners[static_cast<std::size_t>(next[static_cast<std::size_t>(lower(c))]++)] = c;
    }
    // Each vertex's corners by the larger vertex (stable: equal edges keep corner order), then
    // one group per run of equal larger vertices.
    out.start.reserve(static_cast<std::size_t>(n_corners) / 2 + 1);
    out.edge.reserve(static_cast<std::size_t>(n_corners) / 2);
    for (std::size_t v = 0; v < n_vertices; ++v)
    {
        int* const first = out.corners.data() + offset[v];
        int* const last = out.corners.data() + offset[v + 1];
        if (last - first > 32)  // a vertex of high valence
            std::stable_sort(first, last, [&](int a, int b) { return upper(a) < upper(b); });
        else
            for (int* i = first + 1; i < last; ++i)  // insertion sort: stable, no buffer
            {
                const int c = *i, key = upper(c);
                int* j = i;
                for (; j != first && upper(j[-1]) > key; --j)
                    *j = j[-1];
                *j = c;
            }
        for (int* run = first; run != last;)
        {
            const int hi = upper(*run);
            out.start.push_back(static_cast<int>(run - out.corners.data()));
            out.edge.push_back({static_cast<int>(v), hi});
            while (run != last && upper(*run) == hi)
                ++run;
        }
    }
    out.start.push_back(n_corners);
    return out;
}

}  // namespace vessel::detail
