#include "prepare.h"

#include "vessel/core/errors.h"

#include <string>
#include <vector>

namespace vessel::cli {

PreparedInput prepare_input(RawMesh raw, const TreeSurfaceOptions& options, bool repair)
{
    PreparedInput in;
    if (repair)
    {
        RepairedMesh repaired = repair_raw_mesh(raw);
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
        throw InvalidInputError(std::string(e.what()) + " [still, after --repair " +
                                (done.empty() ? "changed nothing" : "(" + done + ")") + "]");
    }
    in.surface.notes.insert(in.surface.notes.begin(), notes.begin(), notes.end());
    return in;
}

}  // namespace vessel::cli
