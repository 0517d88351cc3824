#include "prepare.h"

#include "vessel/core/errors.h"

#include <string>
#include <vector>

namespace vessel::cli {

PreparedInput prepare_input(RawMesh raw, const TreeSurfaceOptions& options,
                            const std::optional<RepairOptions>& repair)
{
    PreparedInput in;
    if (repair)
    {
        RepairedMesh repaired = repair_raw_mesh(raw, *repair);
        raw = std::move(repaired.mesh);
        in.repairs = repaired.summary;
    }
    in.raw = std::move(raw);
    const std::vector<std::string> notes = in.repairs ? in.repairs->notes() : std::vector<std::string>{};
    try
    {
        in.surface = make_tree_surface(in.raw, options);
    }
    catch (const InvalidInputError& e)
    {
        if (!in.repairs)
            throw;
        std::string done;
        for (const auto& note : notes)
            done += (done.empty() ? "" : "; ") + note.substr(note.find(' ') + 1);
        const bool only_holes = !repair->orient && !repair->stitch_borders &&
                                !repair->remove_duplicate_faces && !repair->remove_degenerate_faces;
        throw InvalidInputError(std::string(e.what()) + " [still, after " +
                                (only_holes ? "--fill-holes " : "--repair ") +
                                (done.empty() ? "changed nothing" : "(" + done + ")") + "]");
    }
    in.surface.notes.insert(in.surface.notes.begin(), notes.begin(), notes.end());
    return in;
}

}  // namespace vessel::cli
