#pragma once

#include "vessel/pipeline.h"

#include <chrono>

namespace vessel::detail {

//! Times the pipeline's stages under their Table 1 names and reports each to
//! FlattenOptions::on_stage and ::on_progress (its start to on_progress only).
class StageClock
{
public:
    //! Starts \p first, the stage the clock times first.
    StageClock(const FlattenOptions& options, const char* first) : options_(options)
    {
        begin(first);
    }
    //! Seconds since the previous call (or construction); reports the end of \p stage and,
    //! when given, the start of \p next (stages follow one another with no gap).
    double lap(const char* stage, const char* next = nullptr)
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
        if (next)
            begin(next);
        return seconds;
    }

private:
    void begin(const char* stage) const
    {
        if (!options_.on_progress)
            return;
        Progress start;
        start.stage = stage;
        start.stage_begins = true;
        options_.on_progress(start);
    }

    const FlattenOptions& options_;
    std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
};

//! \p options with stage F's solver callbacks (ARAP's local/global sweeps, SLIM's iterations,
//! the area polish's chunks) reporting to FlattenOptions::on_progress, at most once per
//! `progress_interval_s`, after any callback the caller set there. \p options itself when it
//! has no on_progress.
FlattenOptions with_progress(const FlattenOptions& options);

}  // namespace vessel::detail
