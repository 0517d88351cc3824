#pragma once
// Stage F of flatten(): the map of the cut mesh, from the layout's pins.

#include "vessel/pipeline.h"

namespace vessel::detail {

//! \brief Stage F: the initial map, its refinement (refine_map.h) and, after a restart, the look
//! retry (look_retry.h) into result.uv (and the refinement summaries and notes). With
//! Refinement::Injective and a cut mesh more than twice FlattenOptions::multilevel's coarse
//! size, the map is solved on a decimated copy, carried to the full mesh and relaxed there
//! (multilevel.h); if that map is not one-to-one, F runs again at full resolution (noted).
//! \return whether the map still holds the layout's inlet pins (no restart).
bool solve_map(const Mesh& mesh, const LayoutInput& input, const LayoutResult& placed,
               const FlattenOptions& options, FlattenResult& result);

//! \brief FlattenOptions::refiner on the initial map in result.uv (and its notes), checked: one
//! finite row per vertex of \p mesh. \p input and \p placed are null for a disk input.
//! \return \p at_layout and whether the refiner left every pin where it was.
//! \throw InvalidInputError naming the refiner if its map is not of that shape.
bool refine_by_policy(const Mesh& mesh, const LayoutInput* input, const LayoutResult* placed,
                      const MapRefiner& refiner, const Pins& pins, bool at_layout,
                      FlattenResult& result);

}  // namespace vessel::detail
