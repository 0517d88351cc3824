#pragma once

#include "vessel/pipeline.h"

#include <chrono>

namespace vessel::detail {

//! Times the pipeline's stages under their Table 1 names and reports each to
//! FlattenOptions::on_stage.
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
        return seconds;
    }

private:
    const FlattenOptions& options_;
    std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
};

}  // namespace vessel::detail
