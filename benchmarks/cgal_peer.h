#pragma once
// The CGAL peer of vessel-bench-table: the stages of the method assembled from CGAL's components
// (and Boost Graph) as a user without libvessel would. Benchmark code only: CGAL is never used by
// the library. See docs/benchmarks.md.

#include "vessel/mesh.h"

#include <nlohmann/json.hpp>

#include <cstddef>
#include <memory>

namespace vessel_bench {

struct PeerSettings
{
    int runs = 5;              //!< runs of the whole peer pipeline
    double time_box_s = 180.0;  //!< no further run after a run longer than this (seconds)
    double scale = 5.0;         //!< jet-fitting ball radius, in mean edge lengths (as ours)
    int min_neighbors = 8;      //!< the ball grows by rings until it holds this many (as ours)
};

//! \brief Runs the CGAL peer pipeline on \p mesh (a valid vessel tree) `settings.runs` times.
//! \return JSON: "samples" {Z, GC, VC, AC, F, F_lscm, Total: seconds per run}, "runs",
//! "time_boxed", "quality" {lscm, arap: flat_quality() of the peer's uv on its seam mesh},
//! "seam_edges", "cut_paths", "errors" (stage -> message; a failed stage ends that run).
nlohmann::json run_cgal_peer(const vessel::Mesh& mesh, const PeerSettings& settings);

//! The peer's stage Z once (in the constructor), then its GC and VC as often as asked: what
//! vessel-cut-bench times beside the library's cut stages. CGAL types stay in cgal_peer.cpp.
class PeerCutStages
{
public:
    PeerCutStages(const vessel::Mesh& mesh, const PeerSettings& settings);
    ~PeerCutStages();
    void build_graph();       //!< GC: the boost graph with the travel costs
    std::size_t cut_paths();  //!< VC on the last graph; returns the number of seam edges

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace vessel_bench
