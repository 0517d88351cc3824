#include "vessel/solve/ordering.h"

#include "vessel/core/errors.h"
#include "solve/cholmod_common.h"

#include <string>

namespace vessel {

VertexOrdering laplacian_ordering(const Mesh& mesh)
{
    const int n = static_cast<int>(mesh.n_vertices());
    // Upper triangle of the vertex graph's pattern, column by column.
    std::vector<int> column_start(n + 1, 0), rows;
    rows.reserve(mesh.n_edges());
    for (auto v : mesh.vertices())
    {
        for (auto w : v.vertices())
            if (w.idx() < v.idx())
                rows.push_back(w.idx());
        column_start[v.idx() + 1] = static_cast<int>(rows.size());
    }
    cholmod_sparse graph = detail::upper_pattern(column_start, rows);
    VertexOrdering ordering;
    ordering.vertices.resize(n);
    detail::CholmodCommon common;
    if (n > 0 && !cholmod_amd(&graph, nullptr, 0, ordering.vertices.data(), &common.c))
        throw SolverError("laplacian_ordering: AMD failed on the vertex graph (" +
                          std::to_string(n) + " vertices; CHOLMOD status " +
                          std::to_string(common.c.status) + "); the machine may be out of memory");
    return ordering;
}

std::vector<int> unknown_order(const VertexOrdering& ordering, const std::vector<int>& unknown_of,
                               int n_unknowns)
{
    if (ordering.vertices.size() != unknown_of.size())
        throw InvalidInputError("unknown_order: the ordering has " +
                                std::to_string(ordering.vertices.size()) +
                                " vertices but the mesh " + std::to_string(unknown_of.size()) +
                                "; pass an ordering of this mesh (a new one after cutting it)");
    std::vector<int> order;
    order.reserve(n_unknowns);
    std::vector<char> seen(n_unknowns, 0);
    for (const int v : ordering.vertices)
    {
        if (v < 0 || v >= static_cast<int>(unknown_of.size()))
            throw InvalidInputError("unknown_order: vertex " + std::to_string(v) +
                                    " of the ordering is not a vertex of the mesh");
        const int k = unknown_of[v];
        if (k < 0)
            continue;
        if (k >= n_unknowns || seen[k])
            throw InvalidInputError("unknown_order: unknown " + std::to_string(k) +
                                    " is out of range or comes twice; each vertex must appear "
                                    "once in the ordering");
        seen[k] = 1;
        order.push_back(k);
    }
    if (static_cast<int>(order.size()) != n_unknowns)
        throw InvalidInputError("unknown_order: the ordering reaches " +
                                std::to_string(order.size()) + " of " +
                                std::to_string(n_unknowns) + " unknowns; pass an ordering of "
                                "every vertex of this mesh");
    return order;
}

}  // namespace vessel
