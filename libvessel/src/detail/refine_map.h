#pragma once

#include "vessel/pipeline.h"

#include <optional>
#include <string>

namespace vessel::detail {

//! \brief Step 7 as FlattenOptions::refinement asks, shared by the tree pipeline and the
//! one-loop disk: ARAP holding \p pins, then (Refinement::Injective) untangling and SLIM. When
//! untangling leaves flips, or the boundary crosses itself (unless OverlapPolicy::Keep), the map
//! restarts from the Tutte embedding and SLIM runs unpinned (with the scaffold the policy asks).
//! Fills result.uv (in: the initial map), .arap, .untangle, .injective and .notes.
//! \param crossing how a crossing boundary is named in the note.
//! \param restart set: restart at once, skipping ARAP and untangling (the caller knows the
//! initial map crosses itself, or asks for the restarted map), with this reason in the note.
//! \param layout, placed the tree's layout input and pins: with
//! FlattenOptions::restart_on_layout_circle the restart starts from layout_circle_start()
//! instead of Tutte's circle. Null: Tutte's circle.
//! \return true if the map restarted (the pins were then dropped).
bool refine_map(const Mesh& mesh, Pins pins, const FlattenOptions& options,
                const std::string& crossing, std::optional<std::string> restart,
                FlattenResult& result,
                const LayoutInput* layout = nullptr, const LayoutResult* placed = nullptr);

}  // namespace vessel::detail
