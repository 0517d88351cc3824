#include "detail/refine_map.h"

#include "vessel/embedding.h"

#include <algorithm>

namespace vessel::detail {

bool refine_map(const Mesh& mesh, Pins pins, const FlattenOptions& options,
                const std::string& crossing, std::string restart, FlattenResult& result)
{
    if (restart.empty() && options.refinement != Refinement::None &&
        options.arap.max_iterations > 0)
        result.arap = arap(mesh, result.uv, pins, options.arap);
    if (options.refinement != Refinement::Injective)
        return false;
    if (restart.empty())
    {
        result.untangle = untangle(mesh, result.uv, pins, options.untangle);
        if (result.untangle.flipped_before > 0)
            result.notes.push_back(result.untangle.report);
        if (result.untangle.flipped_after > 0)
            restart = "untangling left " + std::to_string(result.untangle.flipped_after) +
                      " flipped triangles";
        else if (options.overlaps != OverlapPolicy::Keep &&
                 boundary_self_intersection(mesh, result.uv).first >= 0)
            restart = crossing;
    }
    InjectiveOptions slim = options.injective;
    if (!restart.empty())
    {
        // Tutte's map of the disk onto a circle is one-to-one; SLIM never flips a triangle of
        // it, and with a scaffold (from the start, or from the first contact of the boundary
        // with itself) never lets its boundary cross either. The initial arrangement is lost;
        // the loops keep their order around the map.
        result.notes.push_back(restart + "; restarted from the Tutte embedding");
        result.uv = tutte_embedding(mesh);
        pins.clear();  // the Tutte map cannot hold the pins where they were
        slim.scaffold = options.overlaps == OverlapPolicy::RestartWithScaffold;
        slim.max_iterations = std::max(slim.max_iterations, 1);
    }
    if (slim.max_iterations > 0)
    {
        slim.scaffold_on_contact = options.overlaps == OverlapPolicy::Prevent;
        result.injective = injective_refine(mesh, result.uv, pins, slim);
        if (result.injective.scaffold_from >= 0)
            result.notes.push_back(result.injective.report);
    }
    return !restart.empty();
}

}  // namespace vessel::detail
