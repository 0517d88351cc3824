#pragma once
// flatten()'s stages shown by a tool: on its status line (live_line.h) while each runs, and, for
// vessel-flatten, as one line per stage when it ends.

#include "common/live_line.h"
#include "vessel/pipeline.h"

#include <cstdio>
#include <map>
#include <string>

namespace vessel::cli {

//! What a stage of flatten() (Table 1's name: "Z", "GC", "VC", "AC", "L" or "F") does.
inline const std::string& stage_title(const std::string& stage)
{
    static const std::map<std::string, std::string> titles = {
        {"Z", "curvature, geodesic distance, alignment"},
        {"GC", "cut graph costs"},
        {"VC", "cut paths"},
        {"AC", "applying the cuts"},
        {"L", "layout"},
        {"F", "initial map + refinement"}};
    return titles.at(stage);
}

//! \brief \p options report to \p live: while a stage runs the status line names it (with stage
//! F's solver phase and iteration), where \p live draws. With \p stage_lines each stage's end
//! is also printed as a line that stays, e.g. `[Z ] curvature, ... 1.234 s` (on a terminal or
//! not). \p live must outlive every flatten() made with \p options.
inline void show_stages(FlattenOptions& options, LiveLine& live, bool stage_lines)
{
    if (stage_lines)
        options.on_stage = [&live](const std::string& stage, double seconds) {
            char line[128];
            std::snprintf(line, sizeof line, "[%-2s] %-42s %8.3f s", stage.c_str(),
                          stage_title(stage).c_str(), seconds);
            live.print(line);  // the stage is over: its line replaces the status line
        };
    if (!live.live())
        return;
    options.on_progress = [&live](const Progress& p) {
        if (p.stage_begins)
        {
            char label[96];
            std::snprintf(label, sizeof label, "[%-2s] %s", p.stage.c_str(),
                          stage_title(p.stage).c_str());
            live.show(label);
        }
        else if (p.stage_done)
            live.hide();
        else
            live.detail(p.phase + " " + std::to_string(p.iteration) + "/" +
                        std::to_string(p.max_iterations));
    };
}

}  // namespace vessel::cli
