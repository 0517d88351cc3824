#pragma once
// The checks every search of the cut graph makes of its PathQuery (CutGraph::shortest_path(),
// winding_bounded_path()).

#include "vessel/core/errors.h"
#include "vessel/cut/cut_graph.h"

#include <string>

namespace vessel::detail {

//! \throw InvalidInputError, the message starting with \p caller, if \p query has no sources,
//! a source that is no vertex of \p mesh, or flags not one per vertex (is_blocked may be empty).
inline void check_path_query(const Mesh& mesh, const PathQuery& query, const std::string& caller)
{
    const std::size_t nv = mesh.n_vertices();
    if (query.sources.empty())
        throw InvalidInputError(caller + ": no source vertices");
    if (query.is_target.size() != nv)
        throw InvalidInputError(caller + ": is_target needs one flag per vertex");
    if (!query.is_blocked.empty() && query.is_blocked.size() != nv)
        throw InvalidInputError(caller + ": is_blocked needs one flag per vertex (or none)");
    for (auto v : query.sources)
        if (!mesh.is_valid_handle(v))
            throw InvalidInputError(caller + ": invalid source vertex handle");
}

}  // namespace vessel::detail
