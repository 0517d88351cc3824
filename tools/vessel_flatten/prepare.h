#pragma once

#include "vessel/check/repair.h"
#include "vessel/check/validation.h"

#include <optional>

namespace vessel::cli {

//! An input mesh as read, repaired (with `--repair`) and validated.
struct PreparedInput
{
    RawMesh raw;  //!< the repaired mesh when repaired (its vertices are the output's `v` lines)
    std::optional<RepairSummary> repairs;  //!< set when repairs were requested
    TreeSurface surface;  //!< its notes start with the repairs that changed something
};

//! \brief Repairs \p raw with \p repair if given, then validates it with make_tree_surface().
//! \throw InvalidInputError as make_tree_surface(), saying what the repairs did.
PreparedInput prepare_input(RawMesh raw, const TreeSurfaceOptions& options,
                            const std::optional<RepairOptions>& repair);

}  // namespace vessel::cli
