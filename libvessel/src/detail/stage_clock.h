#pragma once

#include "vessel/pipeline.h"

#include <chrono>

namespace vessel::detail {

//! Times the pipeline's stages under their Table 1 names and reports each to
//! FlattenOptions::on_stage and ::on_progress.
class StageClock
{
public:
    explicit StageClock(const FlattenOptions& options) : options_(options) {}
    //! Seconds since the previous call (or construction); reports the stage.
    double lap(const char* stage)
    {
        const auto now = std::chrono::steady_clock::now();
        const double seconds = std::chrono::duration<double>(now - last_).count();
        last_ = now;
        if (options_.on_stage)
            options_.on_stage(stage, seconds);
        if (options_.on_progress)
        {
            Progress done;
            done.stage = stage;
            done.stage_done = true;
            done.seconds = seconds;
            options_.on_progress(done);
        }
        return seconds;
    }

private:
    const FlattenOptions& options_;
    std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
};

//! \p options with stage F's solver callbacks (ARAP's local/global sweeps, SLIM's iterations,
//! the area polish's chunks) reporting to FlattenOptions::on_progress, at most once per
//! `progress_interval_s`, after any callback the caller set there. \p options itself when it
//! has no on_progress.
FlattenOptions with_progress(const FlattenOptions& options);

}  // namespace vessel::detail
