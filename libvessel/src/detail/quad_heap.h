#pragma once

// The 4-ary min-heap with decrease-key of the cut graph's Dijkstra (cut_graph.cpp) and of the
// edge distance (detail/edge_distance.h: the cut planner's distance to the cut tree).

#include <algorithm>
#include <utility>
#include <vector>

namespace vessel::detail {

// A heap of (distance, vertex) items, at most one per vertex, stored in \p heap; slot[v] is v's
// place in it (-1 when not in it), so a shorter distance moves the vertex up instead of adding
// an entry. \p less orders two items; it decides which of two equal distances comes first.
using HeapItem = std::pair<double, int>;

// Places vertex \p v with distance \p d, or moves it up to \p d (no more than its distance).
template <class Less>
void heap_lower(std::vector<HeapItem>& heap, std::vector<int>& slot, int v, double d, Less less)
{
    int i = slot[v];
    if (i < 0)
    {
        i = static_cast<int>(heap.size());
        heap.emplace_back();
    }
    const HeapItem item{d, v};
    while (i > 0)
    {
        const int up = (i - 1) / 4;
        if (!less(item, heap[up]))
            break;
        heap[i] = heap[up];
        slot[heap[i].second] = i;
        i = up;
    }
    heap[i] = item;
    slot[v] = i;
}

// Removes and returns the least item.
template <class Less>
HeapItem heap_pop(std::vector<HeapItem>& heap, std::vector<int>& slot, Less less)
{
    const HeapItem top = heap.front();
    slot[top.second] = -1;
    const HeapItem last = heap.back();
    heap.pop_back();
    const int n = static_cast<int>(heap.size());
    if (n == 0)
        return top;
    int i = 0;
    for (;;)
    {
        const int first = 4 * i + 1;
        if (first >= n)
            break;
        int best = first;
        const int end = std::min(first + 4, n);
        for (int c = first + 1; c < end; ++c)
            if (less(heap[c], heap[best]))
                best = c;
        if (!less(heap[best], last))
            break;
        heap[i] = heap[best];
        slot[heap[i].second] = i;
        i = best;
    }
    heap[i] = last;
    slot[last.second] = i;
    return top;
}

}  // namespace vessel::detail
