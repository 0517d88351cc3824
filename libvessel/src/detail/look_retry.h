#pragma once

#include "vessel/pipeline.h"

#include <atomic>
#include <functional>
#include <future>

namespace vessel::detail {

//! \brief FlattenOptions::look_retry after a restarted map: measure the look of result.uv; if it
//! is broken (or LookRetry::Force), redo the restart, SLIM and the polish with the hinge pull
//! (refine_map() with FlattenOptions::look_pull's weight = LookRetryOptions::pull) and keep
//! that map only if it has no flipped or overlapping triangle, a simple boundary, a better look
//! (fewer outlets below the inlet, or as many and fewer walk inversions), and a mean
//! |log area| within LookRetryOptions::max_area_over_keep of the `keep` map's (OverlapPolicy::Keep from
//! \p initial and \p pins; used only when the pulled map's area is above the default's).
//! Fills result.look_retry, and on keeping result.uv and .injective; one line in result.notes.
//! Does nothing with LookRetry::Off, a look_pull already set, OverlapPolicy::Keep, or no
//! outlets.
//! \param initial the map refine_map() started from (the LSCM map at the layout).
//! \param pins the layout's inlet pins refine_map() was given.
//! \param ahead if valid: pulled_map() already under way (solve_single_level() starts it beside
//! the restarted map); the retry takes its map instead of solving it again. While it is not
//! ready, the `keep` map is solved on the calling thread, whether or not the bound turns out to
//! need it: time the thread would spend waiting.
void retry_look(const Mesh& mesh, const Pins& pins, const Eigen::MatrixX2d& initial,
                const FlattenOptions& options, FlattenResult& result, const LayoutInput& layout,
                const LayoutResult& placed, std::future<FlattenResult>* ahead = nullptr);

//! Whether retry_look() can make a retry with \p options: LookRetry not Off, no look_pull
//! already set, overlaps not OverlapPolicy::Keep.
bool may_retry_look(const FlattenOptions& options);

//! \brief The look retry's pulled map: refine_map() restarted (from the layout circle, as the
//! restarted default map) with FlattenOptions::look_pull's weight = LookRetryOptions::pull.
//! It depends on the mesh, the layout and the options alone, not on the map it may replace, so it
//! can be solved beside that map. \p cancel as cancellable()'s.
FlattenResult pulled_map(const Mesh& mesh, const Pins& pins, const FlattenOptions& options,
                         const LayoutInput& layout, const LayoutResult& placed,
                         const std::atomic<bool>* cancel = nullptr);

//! \brief The look retry's reference: the distortion (map_distortion(): no overlap search) of
//! the `keep` map (OverlapPolicy::Keep, refine_map() from \p initial holding \p pins, the area
//! polish included). \p cancel as cancellable()'s.
FlatQuality keep_quality(const Mesh& mesh, const Pins& pins, const Eigen::MatrixX2d& initial,
                         const FlattenOptions& options, const LayoutInput& layout,
                         const LayoutResult& placed, const std::atomic<bool>* cancel = nullptr);

//! \brief \p options whose solvers (ARAP's local/global sweeps, not Ceres', SLIM's iterations,
//! the area polish's steps) read \p cancel after every iteration and, once it is set, stop by throwing
//! an exception of a private type: for a solve made ahead on another thread whose result may
//! not be wanted (its std::future is then waited for and never read). The callbacks already in
//! \p options are still called. \p options itself if \p cancel is null.
FlattenOptions cancellable(const FlattenOptions& options, const std::atomic<bool>* cancel);

//! \brief Whether \p map is within LookRetryOptions::max_area_over_keep of \p keep by both
//! measures of mean |log area| (the normalized one is flatcheck's): the bound holds for either.
bool within_area_bound(const FlatQuality& map, const FlatQuality& keep,
                       const LookRetryOptions& retry);

}  // namespace vessel::detail
