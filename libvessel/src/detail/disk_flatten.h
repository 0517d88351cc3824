#pragma once

#include "vessel/pipeline.h"

namespace vessel::detail {

//! The note FlattenResult::notes gets for a surface with one open end.
inline constexpr const char* disk_note =
    "one open end: the surface is already a disk, flattened without cuts";

//! \brief flatten() of a surface with exactly one boundary loop (e.g. a vessel whose outlets
//! are capped, or an aneurysm dome): it is a disk already, so there are no cuts; the loop is
//! the inlet. See disk_flatten.cpp for how the map is made.
FlattenResult flatten_disk(Mesh mesh, const FlattenOptions& options);

}  // namespace vessel::detail
