// vessel-cut-bench: the cut stages alone, GC (travel costs) and VC (cut paths), on the valid
// real trees and the carotid phantoms, beside the CGAL peer's GC (boost adjacency_list) and VC
// (boost Dijkstra per outlet). Google Benchmark reports wall and CPU time per iteration; stage Z
// runs once per mesh outside the timing, as the peer's does. Z/winding/ and Z/stream/ time the
// Z products the cut planner reads that the peer has no counterpart of (winding_rate() and the
// streamline routes' field, descent_direction() of H, both in flatten()'s Z).
// VC/peer/ follows the method's rule as ours; VC/peer-inlet/ the peer's former, easier rule
// (later cuts may end on the inlet); VC/check/ (no timing) compares the two sides' paths.
// VC/aligned/ is VC/default/ with --no-natural-cuts (no winding-bounded routes).
// VC/bare/ (ours with the method's bare rule) and VC/peer-our-costs/ (the peer's search on our
// travel costs) solve one problem and find the same paths: the like-for-like pair.
// See docs/benchmarks.md.
#include "bench_meshes.h"
#include "cgal_peer.h"

#include "vessel/cut/boundary.h"
#include "vessel/direction/curvature.h"
#include "vessel/cut/cut_cost.h"
#include "vessel/cut/cut_graph.h"
#include "vessel/cut/cut_metrics.h"
#include "vessel/cut/cut_plan.h"
#include "vessel/direction/direction.h"
#include "vessel/direction/geodesic.h"
#include "vessel/phantom/phantom.h"
#include "vessel/check/validation.h"

#include <benchmark/benchmark.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace {

// What flatten() has after stage Z, with its default options.
struct Ours
{
    vessel::Mesh mesh;
    std::vector<vessel::BoundaryLoop> loops;
    vessel::PrincipalCurvature curvature;
    Eigen::MatrixX3d z;
    Eigen::VectorXd H;  // harmonic_longitudinal(), as stage Z of flatten() computes it
    Eigen::MatrixX3d winding;  // winding_rate(), as stage Z of flatten() computes it
    Eigen::MatrixX3d stream;   // the streamline routes' field, as stage Z of flatten() makes it
    vessel::HalfedgeWeights weights;
    std::unique_ptr<vessel::CutGraph> graph;
};

// The cut planner's winding field, as stage Z of flatten() computes it.
Eigen::MatrixX3d winding(const Ours& o)
{
    return vessel::winding_rate(o.mesh, o.z, o.curvature.k_max.cwiseAbs());
}

std::shared_ptr<Ours> stage_z(vessel::Mesh mesh)
{
    auto ours = std::make_shared<Ours>();
    ours->mesh = std::move(mesh);
    ours->loops = vessel::boundary_loops(ours->mesh);
    ours->curvature = vessel::principal_curvature(ours->mesh);
    const vessel::HeatGeodesics heat(ours->mesh);
    const Eigen::VectorXd G = heat.distance(ours->loops[0].vertices);
    ours->z = vessel::align_to_root(ours->mesh, ours->curvature.min_direction, G);
    ours->H = vessel::harmonic_longitudinal(ours->mesh, ours->loops, G);
    ours->winding = winding(*ours);
    ours->stream = vessel::descent_direction(ours->mesh, ours->H);
    return ours;
}

// GC as flatten() runs it with the default CostKind::Curvature: the costs, then the graph.
std::unique_ptr<vessel::CutGraph> ours_gc(Ours& o)
{
    o.weights = vessel::evaluate_cost(o.mesh, vessel::CurvatureCost{&o.z});
    return std::make_unique<vessel::CutGraph>(o.mesh, o.weights);
}

// VC with the paper's cheapest-path route (flatten()'s default, CutRoute::Aligned, also
// traces a stream field): one path per outlet.
vessel::CutPlan ours_vc(Ours& o)
{
    vessel::CutPlanOptions shortest;
    shortest.route = vessel::CutRoute::ShortestPath;
    return vessel::plan_cuts(*o.graph, o.loops, o.winding, shortest);
}

// VC with the method's bare rule, the problem the peer solves: the cheapest path per outlet,
// later cuts ending on the first cut vertex reached (CutJoin::Cheapest), no winding tie-break
// (tie_tolerance 0, no winding field). VC/check/ finds the peer's paths on our costs equal.
vessel::CutPlanOptions bare_rule()
{
    vessel::CutPlanOptions bare;
    bare.route = vessel::CutRoute::ShortestPath;
    bare.join = vessel::CutJoin::Cheapest;
    bare.tie_tolerance = 0.0;
    return bare;
}

vessel::CutPlan bare_vc(Ours& o)
{
    return vessel::plan_cuts(*o.graph, o.loops, Eigen::MatrixX3d(), bare_rule());
}

// The peer's travel cost replaced by ours (the weight of the halfedge from -> to).
vessel_bench::PeerCost our_costs(const Ours& o)
{
    return [&o](std::size_t from, std::size_t to) {
        const auto h = o.mesh.find_halfedge(vessel::VertexHandle(static_cast<int>(from)),
                                            vessel::VertexHandle(static_cast<int>(to)));
        return o.weights[h.idx()];
    };
}

// VC with the paper's rule as `vessel-flatten --cut-route shortest --join cheapest` runs it:
// the cheapest path per outlet, later cuts ending where it meets the tree, with the library's
// tie tolerance (the least winding of nearly equal routes). The rule the peer follows.
vessel::CutPlan paper_vc(Ours& o)
{
    vessel::CutPlanOptions paper;
    paper.route = vessel::CutRoute::ShortestPath;
    paper.join = vessel::CutJoin::Cheapest;
    return vessel::plan_cuts(*o.graph, o.loops, o.winding, paper);
}

// VC as flatten() runs it with its default options (CutRoute::Aligned, CutJoin::Approach,
// natural cuts): the cheapest and the traced path per outlet (the stream field they trace is
// made in stage Z), a winding-bounded route where the winding price leaves one unnatural.
vessel::CutPlan default_vc(Ours& o)
{
    return vessel::plan_cuts(*o.graph, o.loops, o.winding, vessel::CutPlanOptions{}, o.stream, o.H,
                             o.z);
}

// The default with --no-natural-cuts (the aligned route alone: no winding-bounded routes).
vessel::CutPlan aligned_vc(Ours& o)
{
    vessel::CutPlanOptions options;
    options.natural_cuts = false;
    return vessel::plan_cuts(*o.graph, o.loops, o.winding, options, o.stream, o.H, o.z);
}

// FNV-1a over the halfedges of every path, in order, cut to 48 bits (exact in a double): equal
// checksums before and after a change of the search mean the same paths.
double checksum(const vessel::CutPlan& plan)
{
    std::uint64_t hash = 1469598103934665603ull;
    for (const auto& path : plan.paths)
        for (auto h : path.halfedges)
            hash = (hash ^ static_cast<std::uint64_t>(h.idx())) * 1099511628211ull;
    return static_cast<double>(hash & ((1ull << 48) - 1));
}

// The cuts of both sides as (from, to) vertex pairs, one set per side.
std::set<std::pair<std::size_t, std::size_t>> pairs_of(const vessel::Mesh& mesh,
                                                       const vessel::CutPlan& plan)
{
    std::set<std::pair<std::size_t, std::size_t>> out;
    for (const auto& path : plan.paths)
        for (auto h : path.halfedges)
            out.emplace(mesh.from_vertex_handle(h).idx(), mesh.to_vertex_handle(h).idx());
    return out;
}

std::set<std::pair<std::size_t, std::size_t>> pairs_of(const vessel_bench::PeerPaths& cuts)
{
    std::set<std::pair<std::size_t, std::size_t>> out;
    for (const auto& path : cuts.paths)
        for (std::size_t i = 0; i + 1 < path.size(); ++i)
            out.emplace(path[i], path[i + 1]);
    return out;
}

// Counters of VC/check/: whether the peer's search solves ours.
// - equal_paths / outlets: the peer's boost Dijkstra on OUR travel costs against plan_cuts()
//   with the method's bare rule (CutJoin::Cheapest, no tie tolerance, no winding): outlets
//   whose vertex paths are equal. Differences can only come from exact ties.
// - jaccard_ours: the peer on its own costs (its own z) against VC/ours, seam edges shared
//   over seam edges in either.
// - settled_same_cost, settled_inlet_same_cost: vertices the peer settles on our costs, with
//   the method's rule and with the inlet as a later target.
void same_cuts(Ours& o, vessel_bench::PeerCutStages& p, benchmark::State& state)
{
    const auto overlap = [](const auto& a, const auto& b) {
        std::size_t common = 0;
        for (const auto& e : a)
            common += b.count(e);
        return static_cast<double>(common) / static_cast<double>(a.size() + b.size() - common);
    };
    p.build_graph();
    state.counters["jaccard_ours"] = overlap(pairs_of(o.mesh, ours_vc(o)), pairs_of(p.cut_paths()));
    p.build_graph(our_costs(o));
    const vessel::CutPlan ours = bare_vc(o);
    const vessel_bench::PeerPaths peer = p.cut_paths();
    std::size_t equal = 0;
    for (std::size_t k = 0; k < ours.paths.size() && k < peer.paths.size(); ++k)
    {
        std::vector<std::size_t> mine{
            static_cast<std::size_t>(o.mesh.from_vertex_handle(ours.paths[k].halfedges.front()).idx())};
        for (auto h : ours.paths[k].halfedges)
            mine.push_back(static_cast<std::size_t>(o.mesh.to_vertex_handle(h).idx()));
        equal += mine == peer.paths[k] ? 1 : 0;
    }
    state.counters["equal_paths"] = static_cast<double>(equal);
    state.counters["outlets"] = static_cast<double>(ours.paths.size());
    state.counters["settled_same_cost"] = static_cast<double>(peer.settled);
    state.counters["settled_inlet_same_cost"] =
        static_cast<double>(p.cut_paths(vessel_bench::PeerJoin::TreeOrInlet).settled);
}

void add_mesh(const std::string& name, const std::function<vessel::Mesh()>& load)
{
    // Set up lazily, at the first benchmark of the mesh, so a filter skips the work.
    auto ours = std::make_shared<std::shared_ptr<Ours>>();
    auto peer = std::make_shared<std::shared_ptr<vessel_bench::PeerCutStages>>();
    auto get_ours = [=]() -> Ours& {
        if (!*ours)
        {
            *ours = stage_z(load());
            (*ours)->graph = ours_gc(**ours);
        }
        return **ours;
    };
    auto get_peer = [=]() -> vessel_bench::PeerCutStages& {
        if (!*peer)
        {
            *peer = std::make_shared<vessel_bench::PeerCutStages>(get_ours().mesh,
                                                                  vessel_bench::PeerSettings{});
            (*peer)->build_graph();
        }
        return **peer;
    };
    benchmark::RegisterBenchmark(("GC/ours/" + name).c_str(), [=](benchmark::State& state) {
        Ours& o = get_ours();
        for (auto _ : state)
            o.graph = ours_gc(o);
    })->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("GC/peer/" + name).c_str(), [=](benchmark::State& state) {
        auto& p = get_peer();
        for (auto _ : state)
            p.build_graph();
    })->Unit(benchmark::kMillisecond);
    for (const auto& [label, plan_of] :
         {std::pair{"VC/ours/", &ours_vc}, std::pair{"VC/default/", &default_vc},
          std::pair{"VC/aligned/", &aligned_vc},
          std::pair{"VC/bare/", &bare_vc},
          std::pair{"VC/paper/", &paper_vc}})
    {
        const auto run = plan_of;
        benchmark::RegisterBenchmark((label + name).c_str(), [=](benchmark::State& state) {
            Ours& o = get_ours();
            vessel::CutPlan plan;
            for (auto _ : state)
                plan = run(o);
            state.counters["seam_edges"] = static_cast<double>(plan.seam_edges(o.mesh).size());
            state.counters["path_checksum"] = checksum(plan);
        })->Unit(benchmark::kMillisecond);
    }
    benchmark::RegisterBenchmark(("Z/winding/" + name).c_str(), [=](benchmark::State& state) {
        Ours& o = get_ours();
        for (auto _ : state)
            benchmark::DoNotOptimize(winding(o));
    })->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("Z/stream/" + name).c_str(), [=](benchmark::State& state) {
        Ours& o = get_ours();
        for (auto _ : state)
            benchmark::DoNotOptimize(vessel::descent_direction(o.mesh, o.H));
    })->Unit(benchmark::kMillisecond);
    for (const auto& [label, join] : {std::pair{"VC/peer/", vessel_bench::PeerJoin::Tree},
                                      {"VC/peer-inlet/", vessel_bench::PeerJoin::TreeOrInlet}})
    {
        const auto rule = join;
        benchmark::RegisterBenchmark((label + name).c_str(), [=](benchmark::State& state) {
            auto& p = get_peer();
            vessel_bench::PeerPaths cuts;
            for (auto _ : state)
                cuts = p.cut_paths(rule);
            state.counters["seam_edges"] = static_cast<double>(cuts.seam_edges());
            state.counters["settled"] = static_cast<double>(cuts.settled);
        })->Unit(benchmark::kMillisecond);
    }
    // The peer's search on our costs: the same problem as VC/bare/, the same paths (VC/check/).
    benchmark::RegisterBenchmark(("VC/peer-our-costs/" + name).c_str(), [=](benchmark::State& state) {
        Ours& o = get_ours();
        auto& p = get_peer();
        p.build_graph(our_costs(o));
        vessel_bench::PeerPaths cuts;
        for (auto _ : state)
            cuts = p.cut_paths();
        state.counters["seam_edges"] = static_cast<double>(cuts.seam_edges());
        state.counters["settled"] = static_cast<double>(cuts.settled);
        p.build_graph();  // back to the peer's own costs
    })->Unit(benchmark::kMillisecond);
    // Not a timing: do both sides solve the same problem? See same_cuts().
    benchmark::RegisterBenchmark(("VC/check/" + name).c_str(), [=](benchmark::State& state) {
        Ours& o = get_ours();
        auto& p = get_peer();
        for (auto _ : state)
            same_cuts(o, p, state);
        p.build_graph();  // back to the peer's own costs
    })->Iterations(1)->Unit(benchmark::kMillisecond);
}

}  // namespace

int main(int argc, char** argv)
{
    return vessel_bench::run_on_bench_meshes(argc, argv, add_mesh);
}
