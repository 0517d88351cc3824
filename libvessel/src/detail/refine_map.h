#pragma once

#include "vessel/pipeline.h"

#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace vessel::detail {

//! A restart's start in place of refine_map()'s own (the layout circle, or Tutte's): a map of the
//! mesh with no flipped face and a simple boundary, made for the options in effect, or an empty
//! matrix where it could not make one (refine_map() then starts from its own, noted). What it
//! did goes into the notes it is given (refine_map() puts them after its restart's, each after
//! "coarser start: ").
using RestartStart =
    std::function<Eigen::MatrixX2d(const FlattenOptions&, std::vector<std::string>& notes)>;

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
//! \param start if set: the restart starts from its map instead; the look pulls are still made
//! on refine_map()'s own start, whose look is the layout's (centre_pull.h, HingeMargin).
//! \return true if the map restarted (the pins were then dropped).
bool refine_map(const Mesh& mesh, Pins pins, const FlattenOptions& options,
                const std::string& crossing, std::optional<std::string> restart,
                FlattenResult& result, const LayoutInput* layout = nullptr,
                const LayoutResult* placed = nullptr, const RestartStart* start = nullptr);

}  // namespace vessel::detail
