#pragma once

#include "prepare.h"
#include "report.h"

#include "vessel/pipeline.h"

#include <optional>
#include <string>

namespace vessel::cli {

struct BatchOptions
{
    //! A directory (its .obj/.off/.ply/.stl files, searched recursively) or a text file with one mesh path per line
    //! (blank lines and lines starting with '#' skipped; relative paths are relative to the
    //! list file's directory).
    std::string inputs;
    //! Receives <stem>.obj, <stem>.json (<file name>.obj/.json for inputs whose stems repeat,
    //! e.g. x.ply.obj and x.stl.obj), summary.csv and summary.json.
    std::string output_dir;
    int jobs = 2;            //!< worker threads, each flattening one mesh at a time
    //! Memory (MB) the meshes running at the same time may need together, by
    //! estimated_peak_mb() (memory_budget.h) of each; 0 = 80% of the machine's memory. A mesh whose estimate is
    //! above it is refused before it is flattened; one that fits waits until the running meshes
    //! leave it room, so that large meshes run one after the other instead of together.
    double memory_mb = 0.0;
    bool resume = false;     //!< keep inputs whose <stem>.obj and <stem>.json already exist
    bool quiet = false;      //!< no progress lines on stderr
    TreeSurfaceOptions surface;  //!< how every input is validated
    bool repair = false;         //!< apply repair_raw_mesh() before the validation
    //! Fill holes of perimeter below this (mesh units) before the validation
    //! (RepairOptions::fill_holes_below), with or without the other repairs; 0 = none.
    double fill_holes = 0.0;
    //! The repairs asked for (`repair`, `fill_holes`), or none.
    std::optional<RepairOptions> repair_options() const;
};

//! \brief Flatten every input of \p batch with \p options (its `on_stage` is ignored) and write
//! the per-mesh outputs and the summaries, each to a temporary name renamed when complete.
//! SIGINT/SIGTERM stop the batch after the running meshes (a second signal abandons them).
//! \return the exit code: 0 if every mesh was flattened, 1 if any was refused or failed (or the
//! batch could not start), 128 + signal number if interrupted.
int run_batch(const BatchOptions& batch, const FlattenOptions& options);

}  // namespace vessel::cli
