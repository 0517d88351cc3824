#include "vessel/layout/pins.h"

#include "vessel/core/errors.h"

namespace vessel {

std::vector<int> pin_index(const Mesh& mesh, const Pins& pins, const std::string& caller)
{
    const int n = static_cast<int>(mesh.n_vertices());
    std::vector<int> index(n, -1);
    for (std::size_t p = 0; p < pins.size(); ++p)
    {
        const VertexHandle v = pins[p].vertex;
        if (!v.is_valid() || v.idx() >= n)
            throw InvalidInputError(caller + ": pin " + std::to_string(p) + " has vertex index " +
                                    std::to_string(v.idx()) + " but the mesh has " +
                                    std::to_string(n) + " vertices; pass handles of this mesh");
        if (!pins[p].uv.allFinite())
            throw InvalidInputError(caller + ": pin " + std::to_string(p) + " (vertex " +
                                    std::to_string(v.idx()) +
                                    ") has a non-finite target; give finite (u, v)");
        if (index[v.idx()] >= 0)
            throw InvalidInputError(caller + ": vertex " + std::to_string(v.idx()) +
                                    " is pinned twice (pins " + std::to_string(index[v.idx()]) +
                                    " and " + std::to_string(p) + "); pin each vertex once");
        index[v.idx()] = static_cast<int>(p);
    }
    return index;
}

}  // namespace vessel
