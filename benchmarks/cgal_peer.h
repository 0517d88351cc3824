#pragma once
// The CGAL peer of vessel-bench-table: the stages of the method assembled from CGAL's components
// (and Boost Graph) as a user without libvessel would. Benchmark code only: CGAL is never used by
// the library. See docs/benchmarks.md.

#include "vessel/core/mesh.h"

#include <nlohmann/json.hpp>

#include <cstddef>
#include <functional>
#include <memory>
#include <vector>

namespace vessel_bench {

//! Where the peer's later cuts (every outlet but the largest) may end.
enum class PeerJoin
{
    //! The method's rule, as the library's plan_cuts(): on an interior vertex already on a cut;
    //! the inlet is blocked after the first cut (default).
    Tree,
    //! The peer's former rule: on a cut or on the inlet loop. An easier problem (later searches
    //! settle 2.7-7x fewer vertices); kept measurable as VC/peer-inlet/ of vessel-cut-bench.
    TreeOrInlet,
};

//! A travel cost per arc (from, to vertex index), in place of the peer's own.
using PeerCost = std::function<double(std::size_t, std::size_t)>;

//! The peer's cuts: one vertex path per outlet (outlet -> end), in the order made.
struct PeerPaths
{
    std::vector<std::vector<std::size_t>> paths;
    std::size_t settled = 0;  //!< vertices examined (settled) over all searches
    std::size_t seam_edges() const;  //!< edges over all paths
};

struct PeerSettings
{
    int runs = 5;              //!< runs of the whole peer pipeline
    double time_box_s = 180.0;  //!< no further run after a run longer than this (seconds)
    double scale = 5.0;         //!< jet-fitting ball radius, in mean edge lengths (as ours)
    int min_neighbors = 8;      //!< the ball grows by rings until it holds this many (as ours)
    PeerJoin join = PeerJoin::Tree;  //!< where later cuts may end
};

//! \brief Runs the CGAL peer pipeline on \p mesh (a valid vessel tree) `settings.runs` times.
//! \return JSON: "samples" {Z, GC, VC, AC, F, F_lscm, Total: seconds per run}, "runs",
//! "time_boxed", "quality" {lscm, arap: flat_quality() of the peer's uv on its seam mesh},
//! "seam_edges", "cut_paths", "cut_vertex_paths" (the first run's cuts as vertex indices of
//! \p mesh, outlet to end), "errors" (stage -> message; a failed stage ends that run).
nlohmann::json run_cgal_peer(const vessel::Mesh& mesh, const PeerSettings& settings);

//! The peer's stage Z once (in the constructor), then its GC and VC as often as asked: what
//! vessel-cut-bench times beside the library's cut stages. CGAL types stay in cgal_peer.cpp.
class PeerCutStages
{
public:
    PeerCutStages(const vessel::Mesh& mesh, const PeerSettings& settings);
    ~PeerCutStages();
    //! GC: the boost graph with the peer's travel costs, or with \p cost (a check of VC alone).
    void build_graph(const PeerCost& cost = nullptr);
    PeerPaths cut_paths(PeerJoin join = PeerJoin::Tree);  //!< VC on the last graph

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace vessel_bench
