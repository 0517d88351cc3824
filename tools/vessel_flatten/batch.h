#pragma once

#include "prepare.h"
#include "report.h"

#include "vessel/pipeline.h"

#include <optional>
#include <string>
#include <vector>

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
    //! Memory (MB) the meshes running at the same time may use together; 0 = 80% of the
    //! machine's memory. Each mesh is admitted by estimated_peak_mb() (memory_budget.h): one whose
    //! estimate is above the cap is refused before it is flattened, one that fits waits until
    //! the running meshes leave it room, so that large meshes run one after the other. Whenever
    //! the running meshes' processes use more than the cap, the admitted one furthest above its
    //! estimate is stopped (a `failed` row that says so; MemoryWatchdog).
    double memory_mb = 0.0;
    //! The vessel-flatten command line (argv) of the batch: each mesh runs in a process of its
    //! own, `COMMAND --batch-case FILE NAME` (run_batch_case()), so that the memory cap is held
    //! (case_process.h) and a mesh that crashes its process stops only itself.
    std::vector<std::string> command;
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

//! \brief One mesh of run_batch() in the process the batch started for it (`--batch-case FILE
//! NAME`): reads and validates \p file, writes `faces N` to descriptor 3, waits for `go` on its
//! standard input (the batch's admission), flattens it into NAME.obj and NAME.json in the
//! batch's output folder and writes `ok`, or `refused MESSAGE` / `failed MESSAGE`, to
//! descriptor 3 (the batch reads an `ok` row from NAME.json).
int run_batch_case(const BatchOptions& batch, const FlattenOptions& options,
                   const std::string& file, const std::string& name);

}  // namespace vessel::cli
