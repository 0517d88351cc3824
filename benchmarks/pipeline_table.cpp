// vessel-bench-table: whole-pipeline timings in the columns of the paper's Table 1 (Z, GC, VC,
// AC, L, F, Total), per mesh, as the median (min, max) of several runs, with reading time and
// peak memory. Each mesh runs in its own forked child, so that ru_maxrss is that mesh's own peak
// (a process's high-water mark never goes down); the child sends its results back as JSON over a
// pipe. A CGAL peer pipeline (cgal_peer.cpp) runs on the same meshes, each in its own child too.
// `--solvers` compares the refinement solvers instead. See docs/benchmarks.md.
#include "cgal_peer.h"
#include "common/quality_json.h"
#include "common/restart.h"
#include "vessel/check/validation.h"
#include "vessel/core/errors.h"
#include "vessel/core/properties.h"
#include "vessel/cut/boundary.h"
#include "vessel/cut/cut_metrics.h"
#include "vessel/cut/cut_winding.h"
#include "vessel/direction/geodesic.h"
#include "vessel/io/io.h"
#include "vessel/io/vtk_io.h"  // inputs may be .vtp/.vtk
#include "vessel/map/arap.h"
#include "vessel/phantom/phantom.h"
#include "vessel/pipeline.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#ifndef VESSEL_SHARED_DATA
#define VESSEL_SHARED_DATA "../shared/data/real"
#endif
#ifndef VESSEL_BENCH_CACHE
#define VESSEL_BENCH_CACHE "vessel-bench-phantoms"
#endif

namespace {

using Clock = std::chrono::steady_clock;
using nlohmann::json;

double seconds_since(Clock::time_point start)
{
    return std::chrono::duration<double>(Clock::now() - start).count();
}

// The valid tree surfaces of ../shared/data/real (MANIFEST.md: #1, #5, #6, #7, #8, #9, #10, #11,
// #13), in the manifest's order.
const char* const real_meshes[] = {
    "vmtk-test-data/aorta-surface-open-ends.ply",
    "vampy/artery.ply",
    "vampy/artery-coarse.ply",
    "vmtk-old-website/aneurisk-id1-lateral-aneurysm.ply",
    "svfsi-tests/pulmonary-glenn-wall.ply",
    "svfsi-tests/pulmonary-glenn-wall-split4.ply",
    "x-ray-angio-data/coronary-phantom-tri3-coarse.ply",
    "x-ray-angio-data/coronary-clinical-branch-fine.ply",
    "simvascular-tests/demo-model-open.ply",
};

struct PhantomSize
{
    const char* name;
    double edge_length;  // carotid_phantom() edge_length (mm)
    double stenosis;     // carotid_phantom() stenosis; other options at their defaults
    long faces;          // triangles it gives (for --max-faces before generating)
};

// carotid_phantom() settings for the paper's sizes, triangles measured with this build
// (carotid_phantom is deterministic). With the default 50% stenosis the edge is capped at
// 0.69 mm (>= 1.6 samples per throat radius), which gives at least 6.5k triangles, so the
// smallest size uses a 30% stenosis. Check a new edge length with `--phantom-edge L`.
const PhantomSize phantom_sizes[] = {
    {"carotid-4k", 0.9, 0.3, 4021},
    {"carotid-13k", 0.49, 0.5, 13023},
    {"carotid-20k", 0.395, 0.5, 20134},
    {"carotid-44k", 0.263, 0.5, 44976},
    {"carotid-100k", 0.1756, 0.5, 100018},
    {"carotid-300k", 0.1013, 0.5, 300940},
    {"carotid-1M", 0.0555, 0.5, 999851},    // generating it takes 23 s and 1.5 GB
};

struct Case
{
    std::string name;
    std::string path;          // the mesh file (for a phantom: its cached PLY)
    double edge_length = 0.0;  // phantom: carotid_phantom() options; 0 = a real mesh
    double stenosis = 0.5;
    long nominal_faces = 0;  // phantom: expected triangles
};

struct Settings
{
    int runs = 5;
    std::string cache_dir = VESSEL_BENCH_CACHE;  // generated phantoms, as binary PLY
    long max_faces = 0;  // 0 = no limit
    double time_box_s = 180.0;
    double timeout_s = 3600.0;
    std::vector<int> solver_iterations;  // empty = library defaults only
    bool peer = true;                    // also run the CGAL peer on each mesh
    double curve_budget_s = 60.0;        // solver curves: seconds per solver and mesh
    double peer_timeout_s = 900.0;       // kill the peer's child after this long
    long peer_max_faces = 0;             // no peer on larger meshes (0 = no limit)
    std::string method = "default";      // the timed pipeline: see pipeline_options()
    std::string cuts = "default";        // the cut rule: see pipeline_options()
    // Stage F coarse-to-fine (MultilevelOptions); 0 = every map at full resolution
    int coarse_vertices = vessel::MultilevelOptions{}.coarse_vertices;
};

// The options of the timed pipeline: the library's defaults; with --method paper
// FlattenOptions::paper() (F = LSCM at the layout, then ARAP with the inlet pinned; no
// untangling, no SLIM, no area polish, overlaps allowed; no relief cuts); with --method paper-untangled
// the same, then the flipped triangles untangled locally (untangle.h; no SLIM, no polish), so
// the map has no flipped triangle. Z, GC, AC and L are the library's in every case; VC too,
// unless --cuts paper: the paper's cut rule, the cheapest path per outlet, later cuts ending
// where they first meet the tree (the rule the peer follows; the library's tie tolerance kept).
// The library's default route also traces a streamline per outlet and keeps the candidate that
// winds less (CutRoute::Aligned, CutJoin::Approach).
vessel::FlattenOptions pipeline_options(const Settings& s)
{
    vessel::FlattenOptions o =
        s.method == "default" ? vessel::FlattenOptions{} : vessel::FlattenOptions::paper();
    if (s.cuts == "paper")
    {
        o.cuts.route = vessel::CutRoute::ShortestPath;
        o.cuts.join = vessel::CutJoin::Cheapest;
    }
    o.multilevel.coarse_vertices = s.coarse_vertices;
    if (s.method == "paper-untangled")
    {
        o.refinement = vessel::Refinement::Injective;  // ARAP, untangling, then SLIM ...
        o.injective.max_iterations = 0;                // ... with no SLIM iteration
        o.polish_area = false;
    }
    return o;
}

double median(std::vector<double> v)
{
    if (v.empty())
        return std::nan("");
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

json stats(const std::vector<double>& v)
{
    if (v.empty())
        return json{{"median", nullptr}, {"min", nullptr}, {"max", nullptr}, {"samples", v}};
    return {{"median", median(v)},
            {"min", *std::min_element(v.begin(), v.end())},
            {"max", *std::max_element(v.begin(), v.end())},
            {"samples", v}};
}

const char* const stage_names[] = {"Z", "GC", "VC", "AC", "L", "F"};

std::vector<double> stage_values(const vessel::StageTimings& t)
{
    return {t.Z, t.GC, t.VC, t.AC, t.L, t.F};
}

// Reads the case's mesh \p loads times (timing each), as a user would: read + validate.
vessel::Mesh load_case(const Case& c, int loads, std::vector<double>& read_s,
                       std::vector<std::string>& notes)
{
    vessel::Mesh mesh;
    for (int i = 0; i < std::max(1, loads); ++i)
    {
        const auto start = Clock::now();
        vessel::TreeSurface s = vessel::load_tree_surface(c.path);
        read_s.push_back(seconds_since(start));
        mesh = std::move(s.mesh);
        if (i == 0)
            notes = s.notes;
    }
    return mesh;
}

// --- child side ---------------------------------------------------------------------------------

// How far the cuts turn around their vessels: the library's WindingMeter on the harmonic
// longitudinal coordinate \p H of the uncut \p mesh, for cuts given as CutPaths or as vertex
// paths (outlet to end). One yardstick for both pipelines' cuts (a natural cut stays near 0).
template <class Path>
json seam_winding_of(const vessel::Mesh& mesh, const Eigen::VectorXd& H,
                     const std::vector<Path>& cuts)
{
    const vessel::WindingMeter meter(mesh, H);
    std::vector<vessel::PathWinding> windings;
    long measured = 0, vertices = 0;
    for (const auto& cut : cuts)
    {
        windings.push_back(meter.measure(cut));
        measured += windings.back().measured;
        vertices += windings.back().vertices;
    }
    const vessel::SeamWinding seam = vessel::seam_winding(windings);
    // Vertices off a clean ring (junctions, sacs, ends, coarse tubes) add no angle.
    return {{"max_abs_deg", seam.max_abs_deg},
            {"mean_abs_deg", seam.mean_abs_deg},
            {"measured_fraction", vertices > 0 ? static_cast<double>(measured) / vertices : 0.0}};
}

struct CpuSeconds
{
    double user = 0.0, kernel = 0.0;
};

// This process's CPU seconds so far, all its threads.
CpuSeconds cpu_seconds()
{
    struct rusage usage = {};
    getrusage(RUSAGE_SELF, &usage);
    const auto seconds = [](const timeval& t) { return t.tv_sec + 1e-6 * t.tv_usec; };
    return {seconds(usage.ru_utime), seconds(usage.ru_stime)};
}

json run_table_case(const Case& c, const Settings& s)
{
    json out{{"name", c.name}, {"path", c.path}, {"kind", "real"}};
    std::vector<double> read_s;
    std::vector<std::string> load_notes;
    const vessel::Mesh mesh = load_case(c, s.runs, read_s, load_notes);
    out["vertices"] = mesh.n_vertices();
    out["faces"] = mesh.n_faces();
    out["read"] = stats(read_s);
    out["load_notes"] = load_notes;
    if (s.max_faces > 0 && static_cast<long>(mesh.n_faces()) > s.max_faces)
    {
        out["skipped"] = "more than --max-faces triangles";
        return out;
    }

    std::vector<std::vector<double>> stage(6);
    std::vector<double> total, wall;
    vessel::FlattenResult last;
    bool time_boxed = false;
    const vessel::FlattenOptions options = pipeline_options(s);
    out["method"] = s.method;
    out["cuts"] = s.cuts;
    out["coarse_vertices"] = s.coarse_vertices;
    // The CPU seconds of each run, its threads' together: in user space, and in the kernel
    // (mostly page faults: on a guest whose host discards the pages the guest frees, each fresh
    // page is backed again at its first touch; docs/benchmarks.md, "Machine and conditions").
    std::vector<double> user_s, kernel_s;
    for (int run = 0; run < s.runs; ++run)
    {
        vessel::Mesh copy = mesh;
        const CpuSeconds cpu_before = cpu_seconds();
        const auto start = Clock::now();
        vessel::FlattenResult r = vessel::flatten(std::move(copy), options);
        wall.push_back(seconds_since(start));
        const CpuSeconds cpu_after = cpu_seconds();
        user_s.push_back(cpu_after.user - cpu_before.user);
        kernel_s.push_back(cpu_after.kernel - cpu_before.kernel);
        const auto v = stage_values(r.timings);
        for (int k = 0; k < 6; ++k)
            stage[k].push_back(v[k]);
        total.push_back(r.timings.total());
        std::fprintf(stderr, "    %s run %d/%d: total %.3f s (Z %.3f GC %.3f VC %.3f AC %.3f L %.3f "
                     "F %.3f)\n", c.name.c_str(), run + 1, s.runs, r.timings.total(), v[0], v[1],
                     v[2], v[3], v[4], v[5]);
        last = std::move(r);
        if (wall.back() > s.time_box_s && run + 1 < s.runs)
        {
            time_boxed = true;
            break;
        }
    }
    for (int k = 0; k < 6; ++k)
        out["stages"][stage_names[k]] = stats(stage[k]);
    out["stages"]["Total"] = stats(total);
    out["wall"] = stats(wall);
    out["cpu"] = {{"user", stats(user_s)}, {"kernel", stats(kernel_s)}};
    out["runs"] = static_cast<int>(total.size());
    out["time_boxed"] = time_boxed;
    const auto& q = last.quality;
    out["quality"] = vessel::cli::quality_json(q);
    if (!last.plan.paths.empty())  // the vessel cuts, not relief cuts (the peer makes none)
        out["quality"]["seam_winding"] = seam_winding_of(
            mesh, vessel::uncut_longitudinal(last, mesh.n_vertices()), last.plan.paths);
    out["refinement"] = {{"iterations", last.arap.iterations},
                         {"initial_energy", last.arap.initial_energy},
                         {"final_energy", last.arap.final_energy},
                         {"converged", last.arap.converged}};
    out["seam_edges"] = last.seam_edges;
    out["cut_paths"] = last.plan.paths.size();
    out["notes"] = last.notes;
    return out;
}

struct Variant
{
    const char* name;
    vessel::Refinement refinement;
    vessel::ArapSolver solver;
};

const Variant variants[] = {
    {"none (LSCM only)", vessel::Refinement::None, vessel::ArapSolver::Ceres},
    {"ARAP, Ceres", vessel::Refinement::Arap, vessel::ArapSolver::Ceres},
    {"ARAP, local/global", vessel::Refinement::Arap, vessel::ArapSolver::LocalGlobal},
    {"injective (default)", vessel::Refinement::Injective, vessel::ArapSolver::Ceres},
};

// Reads the case's mesh once into \p mesh; returns the result's header, with "skipped" set when
// the mesh has more than --max-faces triangles.
json open_case(const Case& c, const Settings& s, vessel::Mesh& mesh)
{
    json out{{"name", c.name}, {"path", c.path}};
    std::vector<double> read_s;
    std::vector<std::string> load_notes;
    mesh = load_case(c, 1, read_s, load_notes);
    out["faces"] = mesh.n_faces();
    if (s.max_faces > 0 && static_cast<long>(mesh.n_faces()) > s.max_faces)
        out["skipped"] = "more than --max-faces triangles";
    return out;
}

// Wraps a study `work(case, settings, mesh, out)` into a child's work: reads the mesh once and
// skips the work when the mesh is too large.
template <class Work>
auto on_mesh(Work work)
{
    return [work](const Case& c, const Settings& s) {
        vessel::Mesh mesh;
        json out = open_case(c, s, mesh);
        if (!out.contains("skipped"))
            work(c, s, mesh, out);
        return out;
    };
}

void run_solver_case(const Case& c, const Settings& s, const vessel::Mesh& mesh, json& out)
{
    // 0 stands for "the library's default iteration limit".
    std::vector<int> caps = s.solver_iterations;
    if (caps.empty())
        caps.push_back(0);
    json rows = json::array();
    for (const Variant& var : variants)
        for (int cap : caps)
        {
            if (var.refinement == vessel::Refinement::None && cap != caps.front())
                continue;
            vessel::FlattenOptions o;
            o.refinement = var.refinement;
            o.arap.solver = var.solver;
            if (cap > 0)
            {
                o.arap.max_iterations = cap;
                o.injective.max_iterations = cap;
            }
            std::vector<double> f_s, total_s;
            vessel::FlattenResult last;
            json row{{"variant", var.name},
                     {"max_iterations", var.refinement == vessel::Refinement::Injective
                                            ? o.injective.max_iterations
                                            : var.refinement == vessel::Refinement::Arap
                                                  ? o.arap.max_iterations
                                                  : 0}};
            try
            {
                for (int run = 0; run < s.runs; ++run)
                {
                    vessel::FlattenResult r = vessel::flatten(mesh, o);
                    f_s.push_back(r.timings.F);
                    total_s.push_back(r.timings.total());
                    last = std::move(r);
                    if (total_s.back() > s.time_box_s)
                        break;
                }
            }
            catch (const std::exception& e)
            {
                row["error"] = e.what();
                rows.push_back(row);
                continue;
            }
            row["F"] = stats(f_s);
            row["Total"] = stats(total_s);
            row["iterations"] = last.arap.iterations;
            row["converged"] = last.arap.converged;
            row["solver_initial_energy"] = last.arap.initial_energy;
            row["solver_final_energy"] = last.arap.final_energy;
            // The same measure for every variant: the ARAP energy of the final map.
            row["arap_energy"] = vessel::arap_energy(last.mesh, last.uv);
            row["flipped_triangles"] = last.quality.flipped_triangles;
            row["area_ratio"] = last.quality.area_ratio;
            row["mean_conformal_distortion"] = last.quality.mean_conformal;
            row["notes"] = last.notes;
            std::fprintf(stderr, "    %s / %s (max %d it): F %.3f s, %d it, ARAP energy %.6g\n",
                         c.name.c_str(), var.name, row["max_iterations"].get<int>(),
                         median(f_s), last.arap.iterations, row["arap_energy"].get<double>());
            rows.push_back(row);
        }
    out["variants"] = rows;
}

// The CGAL peer on the case's mesh (read as ours reads it), in its own child (own peak RSS).
void run_peer_case(const Case&, const Settings& s, const vessel::Mesh& mesh, json& out)
{
    vessel_bench::PeerSettings p;
    p.runs = s.runs;
    p.time_box_s = s.time_box_s;
    json r = vessel_bench::run_cgal_peer(mesh, p);
    if (r.contains("cut_vertex_paths"))
    {
        // Measured on our harmonic coordinate, computed here as flatten()'s stage Z does.
        const auto loops = vessel::boundary_loops(mesh);
        const Eigen::VectorXd G = vessel::HeatGeodesics(mesh).distance(loops[0].vertices);
        std::vector<std::vector<vessel::VertexHandle>> cuts;
        for (const auto& path : r["cut_vertex_paths"].get<std::vector<std::vector<int>>>())
            cuts.emplace_back(path.begin(), path.end());
        r["quality"]["seam_winding"] =
            seam_winding_of(mesh, vessel::harmonic_longitudinal(mesh, loops, G), cuts);
        r.erase("cut_vertex_paths");
    }
    for (const auto& [stage, v] : r["samples"].items())
        out["stages"][stage] = stats(v.get<std::vector<double>>());
    r.erase("samples");
    out.update(r);
}

// Solver curves: from the pipeline's own start (cut mesh, LSCM at the layout, inlet pinned at
// the layout), the Ceres and the local/global ARAP each run with a tight tolerance until they
// stop or exceed the budget, recording arap_energy() after every iteration with the seconds
// since the call began (setup and factorization included).
void run_curve_case(const Case& c, const Settings& s, const vessel::Mesh& mesh, json& out)
{
    vessel::FlattenOptions o;
    o.refinement = vessel::Refinement::None;
    vessel::FlattenResult start = vessel::flatten(mesh, o);
    // Every copy of an inlet vertex, at its layout position (LSCM held it there).
    std::vector<char> on_inlet(mesh.n_vertices(), 0);
    for (auto v : start.loops[0].vertices)
        on_inlet[v.idx()] = 1;
    const auto origin = OpenMesh::VProp<int>(start.mesh, vessel::prop::origin);
    vessel::Pins pins;
    for (auto v : start.mesh.vertices())
        if (on_inlet[origin[v]])
            pins.push_back({v, start.uv.row(v.idx()).transpose()});
    out["pins"] = pins.size();
    const double e0 = vessel::arap_energy(start.mesh, start.uv);
    out["initial_energy"] = e0;
    json solvers = json::array();
    const std::pair<const char*, vessel::ArapSolver> kinds[] = {
        {"Ceres", vessel::ArapSolver::Ceres}, {"local/global", vessel::ArapSolver::LocalGlobal}};
    for (const auto& [label, kind] : kinds)
    {
        vessel::ArapOptions a;
        a.solver = kind;
        a.max_iterations = 100000;
        a.tolerance = 1e-12;
        std::vector<double> t{0.0}, e{e0};
        const auto begin = Clock::now();
        a.on_iteration = [&](int, double energy) {
            t.push_back(seconds_since(begin));
            e.push_back(energy);
            return t.back() < s.curve_budget_s;
        };
        Eigen::MatrixX2d uv = start.uv;
        json row{{"solver", label}};
        try
        {
            const vessel::ArapSummary summary = vessel::arap(start.mesh, uv, pins, a);
            row["seconds"] = seconds_since(begin);
            row["iterations"] = summary.iterations;
            row["converged"] = summary.converged;
            row["report"] = summary.report;
            row["flipped_triangles"] = vessel::flat_quality(start.mesh, uv).flipped_triangles;
        }
        catch (const std::exception& ex)
        {
            row["error"] = ex.what();
        }
        row["time"] = t;
        row["energy"] = e;
        std::fprintf(stderr, "    %s / %s: %zu iterations in %.2f s, energy %.6g -> %.6g\n",
                     c.name.c_str(), label, t.size() - 1, t.back(), e.front(), e.back());
        solvers.push_back(row);
    }
    out["solvers"] = solvers;
}

// Generates a phantom into the cache (binary PLY) unless it is there already. Runs in its own
// child, so that generation (1.5 GB at 1M triangles) does not count in the pipeline's peak RSS.
json generate_phantom(const Case& c, const Settings&)
{
    json out{{"name", c.name}, {"path", c.path}, {"edge_length", c.edge_length},
             {"stenosis", c.stenosis}};
    if (std::filesystem::exists(c.path))
    {
        out["cached"] = true;
        return out;
    }
    const auto start = Clock::now();
    vessel::CarotidPhantomOptions o;
    o.edge_length = c.edge_length;
    o.stenosis = c.stenosis;
    const vessel::Mesh mesh = vessel::carotid_phantom(o);
    out["generate_s"] = seconds_since(start);
    out["faces"] = mesh.n_faces();
    std::filesystem::create_directories(std::filesystem::path(c.path).parent_path());
    const std::string tmp = c.path + ".tmp." + std::to_string(getpid()) + ".ply";
    vessel::write_mesh(mesh, tmp);
    std::filesystem::rename(tmp, c.path);
    out["cached"] = false;
    return out;
}

// --- parent side --------------------------------------------------------------------------------

// Runs `work` in a forked child and returns its JSON, with the child's peak RSS added.
template <class Work>
json in_child(const Case& c, const Settings& s, Work work)
{
    int fds[2];
    if (pipe(fds) != 0)
        throw std::runtime_error(std::string("pipe: ") + std::strerror(errno));
    std::fflush(nullptr);
    const pid_t pid = fork();
    if (pid < 0)
        throw std::runtime_error(std::string("fork: ") + std::strerror(errno));
    if (pid == 0)
    {
        close(fds[0]);
        alarm(static_cast<unsigned>(std::ceil(s.timeout_s)));  // SIGALRM ends a runaway child
        json out;
        int code = 0;
        try
        {
            out = work(c, s);
        }
        catch (const std::exception& e)
        {
            out = {{"name", c.name}, {"path", c.path}, {"error", e.what()}};
            code = 1;
        }
        const std::string text = out.dump();
        std::size_t done = 0;
        while (done < text.size())
        {
            const ssize_t n = write(fds[1], text.data() + done, text.size() - done);
            if (n <= 0)
                break;
            done += static_cast<std::size_t>(n);
        }
        close(fds[1]);
        std::fflush(nullptr);
        _exit(code);
    }
    close(fds[1]);
    std::string text;
    char buffer[1 << 16];
    for (;;)
    {
        const ssize_t n = read(fds[0], buffer, sizeof buffer);
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0)
            break;
        text.append(buffer, static_cast<std::size_t>(n));
    }
    close(fds[0]);
    int status = 0;
    struct rusage usage = {};
    while (wait4(pid, &status, 0, &usage) < 0 && errno == EINTR)
    {
    }
    json out;
    if (!text.empty())
        out = json::parse(text, nullptr, false);
    if (out.is_discarded() || !out.is_object())
        out = {{"name", c.name}, {"path", c.path}};
    if (WIFSIGNALED(status))
        out["error"] = WTERMSIG(status) == SIGALRM
                           ? "timed out after " + std::to_string(s.timeout_s) + " s (--timeout)"
                           : std::string("killed by signal ") + strsignal(WTERMSIG(status));
    out["peak_rss_mb"] = usage.ru_maxrss / 1024.0;  // Linux: kilobytes
    return out;
}

std::string fmt(double x)
{
    if (std::isnan(x))
        return "-";
    char b[32];
    std::snprintf(b, sizeof b, x < 0.1 ? "%.4f" : x < 100 ? "%.3f" : "%.1f", x);
    return b;
}

std::string fmt_json(const json& j, const char* key)
{
    return j.contains(key) && j[key].is_number() ? fmt(j[key].get<double>()) : "-";
}

using Table = std::vector<std::vector<std::string>>;  // first row = header

// Display width of UTF-8 text (code points; the tables use "–" and "→").
std::size_t width_of(const std::string& text)
{
    std::size_t n = 0;
    for (unsigned char ch : text)
        n += (ch & 0xC0) != 0x80;
    return n;
}

void print_table(const Table& t, bool markdown, std::ostream& os)
{
    if (t.empty())
        return;
    std::vector<std::size_t> width(t[0].size(), 0);
    for (const auto& row : t)
        for (std::size_t i = 0; i < row.size(); ++i)
            width[i] = std::max(width[i], width_of(row[i]));
    auto line = [&](const std::vector<std::string>& row) {
        for (std::size_t i = 0; i < row.size(); ++i)
        {
            const bool left = i == 0;
            const std::string pad(width[i] - width_of(row[i]), ' ');
            os << (markdown ? "| " : (i ? "  " : ""))
               << (left ? row[i] + pad : pad + row[i]) << (markdown ? " " : "");
        }
        os << (markdown ? "|\n" : "\n");
    };
    line(t[0]);
    if (markdown)
    {
        os << "|";
        for (std::size_t i = 0; i < width.size(); ++i)
            os << (i == 0 ? ":" : "") << std::string(width[i] + 1, '-') << (i ? ":|" : "|");
        os << "\n";
    }
    else
    {
        std::size_t total = 0;
        for (auto w : width)
            total += w + 2;
        os << std::string(total - 2, '-') << "\n";
    }
    for (std::size_t r = 1; r < t.size(); ++r)
        line(t[r]);
}

const char* const table_stages[] = {"Z", "GC", "VC", "AC", "L", "F", "Total"};

bool has_timings(const json& r)
{
    return !r.contains("error") && !r.contains("skipped") && r.contains("stages");
}

std::string status_of(const json& r)
{
    if (r.contains("error"))
        return "error: " + r["error"].get<std::string>();
    if (r.contains("skipped"))
        return "skipped: " + r["skipped"].get<std::string>();
    return "";
}

// The --method (and --cuts, if not the default) the table's pipeline ran with.
std::string method_of(const std::vector<json>& results)
{
    for (const json& r : results)
        if (r.contains("method"))
        {
            std::string m = r["method"].get<std::string>();
            if (r.value("cuts", std::string("default")) != "default")
                m += " --cuts " + r["cuts"].get<std::string>();
            const int library_default = vessel::MultilevelOptions{}.coarse_vertices;
            const int coarse = r.value("coarse_vertices", library_default);
            if (coarse != library_default)
                m += " --coarse-vertices " + std::to_string(coarse);
            return m;
        }
    return "default";
}

void print_results(const std::vector<json>& results, bool markdown, std::ostream& os)
{
    Table med{{"mesh", "triangles", "runs", "Z", "GC", "VC", "AC", "L", "F", "Total", "read",
               "peak RSS MB"}};
    Table range{{"mesh", "Z", "GC", "VC", "AC", "L", "F", "Total"}};
    Table extra{{"mesh", "wall", "wall - Total", "AC %", "flips", "overlapping", "area ratio",
                 "refine it",
                 "seam edges", "notes"}};
    std::string skipped;
    for (const json& r : results)
    {
        const std::string name = r.value("name", std::string("?"));
        const std::string faces = r.contains("faces") ? std::to_string(r["faces"].get<long>()) : "-";
        if (r.contains("skipped"))
        {
            skipped += (skipped.empty() ? "" : ", ") + name + " (" + faces + ")";
            continue;
        }
        if (!has_timings(r))
        {
            std::vector<std::string> row{name, faces, "0"};
            row.resize(med[0].size(), "-");
            row.back() = fmt(r.value("peak_rss_mb", std::nan("")));
            med.push_back(row);
            extra.push_back({name, "-", "-", "-", "-", "-", "-", "-", "-", status_of(r)});
            continue;
        }
        std::vector<std::string> row{name, faces, std::to_string(r["runs"].get<int>()) +
                                                       (r["time_boxed"].get<bool>() ? "*" : "")};
        std::vector<std::string> rrow{name};
        for (const char* st : table_stages)
        {
            const json& s = r["stages"][st];
            row.push_back(fmt_json(s, "median"));
            rrow.push_back(fmt_json(s, "min") + "–" + fmt_json(s, "max"));
        }
        row.push_back(fmt_json(r["read"], "median"));
        char rss[32];
        std::snprintf(rss, sizeof rss, "%.1f", r["peak_rss_mb"].get<double>());
        row.push_back(rss);
        med.push_back(row);
        range.push_back(rrow);
        const double total = r["stages"]["Total"]["median"].get<double>();
        const double wall = r["wall"]["median"].get<double>();
        char ac[16];
        std::snprintf(ac, sizeof ac, "%.1f", 100.0 * r["stages"]["AC"]["median"].get<double>() /
                                                 std::max(total, 1e-12));
        std::string notes;
        for (const auto& n : r["notes"])
            notes += (notes.empty() ? "" : "; ") + n.get<std::string>();
        char area[16];
        std::snprintf(area, sizeof area, "%.4f", r["quality"]["area_ratio"].get<double>());
        extra.push_back({name, fmt(wall), fmt(wall - total), ac,
                         std::to_string(r["quality"]["flipped_triangles"].get<int>()),
                         std::to_string(r["quality"].value("overlapping_triangles", -1)), area,
                         std::to_string(r["refinement"]["iterations"].get<int>()),
                         std::to_string(r["seam_edges"].get<int>()), notes});
    }
    const std::string title = "Median seconds per stage (--method " + method_of(results) + ")";
    os << (markdown ? "\n**" + title + "**\n\n" : "\n" + title + "\n");
    print_table(med, markdown, os);
    os << (markdown ? "\n**Min–max seconds per stage**\n\n" : "\nMin-max seconds per stage\n");
    print_table(range, markdown, os);
    os << (markdown ? "\n**Overhead and result**\n\n" : "\nOverhead and result\n");
    print_table(extra, markdown, os);
    if (!skipped.empty())
        os << "\nSkipped (more than --max-faces triangles): " << skipped << "\n";

    // Log-log slopes of the phantoms' medians: time ~ faces^slope. 1 = linear.
    std::vector<const json*> ph;
    for (const json& r : results)
        if (has_timings(r) && r.value("kind", std::string()) == "phantom")
            ph.push_back(&r);
    std::sort(ph.begin(), ph.end(), [](const json* a, const json* b) {
        return (*a)["faces"].get<long>() < (*b)["faces"].get<long>();
    });
    if (ph.size() >= 2)
    {
        Table slope{{"phantoms", "Z", "GC", "VC", "AC", "L", "F", "Total"}};
        auto log_t = [](const json& r, const char* st) {
            return std::log(std::max(r["stages"][st]["median"].get<double>(), 1e-6));
        };
        auto log_f = [](const json& r) { return std::log(r["faces"].get<double>()); };
        for (std::size_t i = 0; i + 1 < ph.size(); ++i)
        {
            std::vector<std::string> row{(*ph[i])["name"].get<std::string>() + " → " +
                                         (*ph[i + 1])["name"].get<std::string>()};
            for (const char* st : table_stages)
            {
                const double d = (log_t(*ph[i + 1], st) - log_t(*ph[i], st)) /
                                 (log_f(*ph[i + 1]) - log_f(*ph[i]));
                char b[16];
                std::snprintf(b, sizeof b, "%.2f", d);
                row.push_back(b);
            }
            slope.push_back(row);
        }
        // Least-squares fit over all phantoms from 13k triangles up (the range).
        std::vector<const json*> fit;
        for (const json* r : ph)
            if ((*r)["faces"].get<long>() >= 12000)
                fit.push_back(r);
        if (fit.size() >= 2)
        {
            std::vector<std::string> row{"least squares, ≥ 13k"};
            for (const char* st : table_stages)
            {
                double sx = 0, sy = 0, sxx = 0, sxy = 0;
                const double n = static_cast<double>(fit.size());
                for (const json* r : fit)
                {
                    const double x = log_f(*r), y = log_t(*r, st);
                    sx += x, sy += y, sxx += x * x, sxy += x * y;
                }
                char b[16];
                std::snprintf(b, sizeof b, "%.2f", (n * sxy - sx * sy) / (n * sxx - sx * sx));
                row.push_back(b);
            }
            slope.push_back(row);
        }
        os << (markdown ? "\n**Scaling: log-log slope of the median time against triangles "
                          "(1 = linear)**\n\n"
                        : "\nScaling: log-log slope of median time vs triangles (1 = linear)\n");
        print_table(slope, markdown, os);
    }
}

std::string ratio_of(const json& peer_stage, const json& our_stage)
{
    if (!peer_stage.is_object() || !our_stage.is_object() || !peer_stage["median"].is_number() ||
        !our_stage["median"].is_number())
        return "-";
    const double ours = our_stage["median"].get<double>();
    if (!(ours > 0.0))
        return "-";
    char b[32];
    const double x = peer_stage["median"].get<double>() / ours;
    std::snprintf(b, sizeof b, x < 10 ? "%.2f" : x < 1000 ? "%.1f" : "%.0f", x);
    return b;
}

std::string quality_cell(const json& q, const char* key, const char* format)
{
    if (!q.is_object() || !q.contains(key) || !q[key].is_number())
        return "-";
    char b[32];
    if (q[key].is_number_integer())
        std::snprintf(b, sizeof b, "%lld", q[key].get<long long>());
    else
        std::snprintf(b, sizeof b, format, q[key].get<double>());
    return b;
}

// "max / mean (measured %)" degrees of a quality object's seam_winding; "-" when no cut vertex
// lies on a clean ring.
std::string winding_cell(const json& q)
{
    if (!q.is_object() || !q.contains("seam_winding"))
        return "-";
    const json& w = q["seam_winding"];
    const double measured = w.value("measured_fraction", 0.0);
    if (!(measured > 0.0))
        return "-";
    char b[64];
    std::snprintf(b, sizeof b, "%.0f / %.0f (%.0f%%)", w["max_abs_deg"].get<double>(),
                  w["mean_abs_deg"].get<double>(), 100.0 * measured);
    return b;
}

// The CGAL peer's timings, the per-stage ratios peer / ours, and both results' quality.
void print_peer(const std::vector<json>& results, bool markdown, std::ostream& os)
{
    Table med{{"mesh", "triangles", "runs", "Z", "GC", "VC", "AC", "L", "F (ARAP)", "Total",
               "LSCM alone", "peak RSS MB", "failed stage"}};
    Table ratio{{"mesh", "triangles", "Z", "GC", "VC", "AC", "F", "Total", "peak RSS"}};
    Table quality{{"mesh", "ours flips", "ours area ratio", "ours mean |log A|",
                   "ours cut winding max / mean deg (measured)", "peer LSCM flips",
                   "peer ARAP flips", "peer area ratio", "peer mean |log A|",
                   "peer cut winding max / mean deg (measured)"}};
    const char* const peer_stages[] = {"Z", "GC", "VC", "AC", "L", "F", "Total", "F_lscm"};
    for (const json& r : results)
    {
        if (!r.contains("peer"))
            continue;
        const json& p = r["peer"];
        const std::string name = r.value("name", std::string("?"));
        const std::string faces = r.contains("faces") ? std::to_string(r["faces"].get<long>()) : "-";
        std::string failed;
        if (p.contains("error"))
            failed = p["error"].get<std::string>();
        if (p.contains("skipped"))
            failed = "not run: " + p["skipped"].get<std::string>();
        const json errors = p.value("errors", json::object());
        for (const auto& [stage, message] : errors.items())
            failed += (failed.empty() ? "" : "; ") + stage + ": " + message.get<std::string>();
        const json stages = p.value("stages", json::object());
        const int runs = p.value("runs", 0);
        std::vector<std::string> row{name, faces,
                                     std::to_string(runs) + (p.value("time_boxed", false) ? "*" : "")};
        std::vector<std::string> rrow{name, faces};
        for (const char* st : peer_stages)
        {
            const bool timed = runs > 0 && stages.contains(st);
            row.push_back(timed ? fmt_json(stages[st], "median") : "-");
            if (std::string(st) != "L" && std::string(st) != "F_lscm")
                rrow.push_back(timed && has_timings(r) ? ratio_of(stages[st], r["stages"][st]) : "-");
        }
        row.push_back(fmt(p.value("peak_rss_mb", std::nan(""))));
        row.push_back(failed.empty() ? "" : failed);
        med.push_back(row);
        char rss[32] = "-";
        if (r.contains("peak_rss_mb") && p.contains("peak_rss_mb") && !p.contains("skipped"))
            std::snprintf(rss, sizeof rss, "%.2f",
                          p["peak_rss_mb"].get<double>() / r["peak_rss_mb"].get<double>());
        rrow.push_back(rss);
        ratio.push_back(rrow);
        const json ours = r.value("quality", json());
        const json peer_q = p.value("quality", json::object());
        quality.push_back({name, quality_cell(ours, "flipped_triangles", "%g"),
                           quality_cell(ours, "area_ratio", "%.4f"),
                           quality_cell(ours, "mean_abs_log_area_ratio", "%.4f"),
                           winding_cell(ours),
                           quality_cell(peer_q.value("lscm", json()), "flipped_triangles", "%g"),
                           quality_cell(peer_q.value("arap", json()), "flipped_triangles", "%g"),
                           quality_cell(peer_q.value("arap", json()), "area_ratio", "%.4f"),
                           quality_cell(peer_q.value("arap", json()), "mean_abs_log_area_ratio", "%.4f"),
                           winding_cell(peer_q)});
    }
    if (med.size() == 1)
        return;
    os << (markdown ? "\n**CGAL peer: median seconds per stage**\n\n"
                    : "\nCGAL peer: median seconds per stage\n");
    print_table(med, markdown, os);
    os << (markdown ? "\n**Ratio peer / ours (medians; > 1 = ours faster)**\n\n"
                    : "\nRatio peer / ours (medians; > 1 = ours faster)\n");
    print_table(ratio, markdown, os);
    const std::string title =
        "Quality of the final maps (ours: --method " + method_of(results) + "; peer: ARAP)";
    os << (markdown ? "\n**" + title + "**\n\n" : "\n" + title + "\n");
    print_table(quality, markdown, os);
}

void print_solver_results(const std::vector<json>& results, bool markdown, std::ostream& os)
{
    Table t{{"mesh", "triangles", "variant", "max it", "F median", "F min–max", "Total", "it",
             "conv", "ARAP energy", "solver energy", "flips", "area ratio"}};
    for (const json& r : results)
    {
        const std::string name = r.value("name", std::string("?"));
        const std::string faces = r.contains("faces") ? std::to_string(r["faces"].get<long>()) : "-";
        if (!r.contains("variants"))
        {
            std::vector<std::string> row{name, faces, status_of(r)};
            row.resize(t[0].size(), "-");
            t.push_back(row);
            continue;
        }
        for (const json& v : r["variants"])
        {
            if (v.contains("error"))
            {
                std::vector<std::string> row{name, faces, v["variant"].get<std::string>(),
                                             std::to_string(v["max_iterations"].get<int>()),
                                             "error: " + v["error"].get<std::string>()};
                row.resize(t[0].size(), "-");
                t.push_back(row);
                continue;
            }
            char e1[32], e2[32], area[16];
            std::snprintf(e1, sizeof e1, "%.6g", v["arap_energy"].get<double>());
            if (v["max_iterations"].get<int>() > 0)
                std::snprintf(e2, sizeof e2, "%.6g", v["solver_final_energy"].get<double>());
            else
                std::snprintf(e2, sizeof e2, "-");
            std::snprintf(area, sizeof area, "%.4f", v["area_ratio"].get<double>());
            t.push_back({name, faces, v["variant"].get<std::string>(),
                         std::to_string(v["max_iterations"].get<int>()),
                         fmt_json(v["F"], "median"),
                         fmt_json(v["F"], "min") + "–" + fmt_json(v["F"], "max"),
                         fmt_json(v["Total"], "median"), std::to_string(v["iterations"].get<int>()),
                         v["converged"].get<bool>() ? "yes" : "no", e1, e2,
                         std::to_string(v["flipped_triangles"].get<int>()), area});
        }
    }
    os << (markdown ? "\n**Refinement solvers (F = LSCM + refinement, seconds)**\n\n"
                    : "\nRefinement solvers (F = LSCM + refinement, seconds)\n");
    print_table(t, markdown, os);
}

// Which solver first reaches the converged energy: within 1e-4 (relative) of the lowest energy
// either reached. Also writes every curve as CSV.
void print_curves(const std::vector<json>& results, const std::string& csv_path, bool markdown,
                  std::ostream& os)
{
    std::ofstream csv(csv_path);
    csv << "mesh,faces,solver,iteration,seconds,energy\n";
    csv.precision(12);
    Table t{{"mesh", "triangles", "solver", "iterations", "seconds", "final energy", "flips",
             "best energy", "reaches best + 1e-4 at (s)", "at iteration", "first"}};
    for (const json& r : results)
    {
        const std::string name = r.value("name", std::string("?"));
        const std::string faces = r.contains("faces") ? std::to_string(r["faces"].get<long>()) : "-";
        if (!r.contains("solvers"))
        {
            std::vector<std::string> row{name, faces, status_of(r)};
            row.resize(t[0].size(), "-");
            t.push_back(row);
            continue;
        }
        double best = std::numeric_limits<double>::infinity();
        for (const json& v : r["solvers"])
            for (const json& e : v["energy"])
                best = std::min(best, e.get<double>());
        const double target = best * (1.0 + 1e-4);
        std::vector<std::vector<std::string>> rows;
        double first_time = std::numeric_limits<double>::infinity();
        std::string first_solver = "neither";
        for (const json& v : r["solvers"])
        {
            const auto time = v["time"].get<std::vector<double>>();
            const auto energy = v["energy"].get<std::vector<double>>();
            const std::string solver = v["solver"].get<std::string>();
            for (std::size_t i = 0; i < time.size(); ++i)
                csv << name << "," << faces << "," << solver << "," << i << "," << time[i] << ","
                    << energy[i] << "\n";
            std::size_t hit = 0;
            while (hit < energy.size() && energy[hit] > target)
                ++hit;
            char e1[32], e2[32];
            std::snprintf(e1, sizeof e1, "%.6g", energy.back());
            std::snprintf(e2, sizeof e2, "%.6g", best);
            const bool reached = hit < energy.size();
            if (reached && time[hit] < first_time)
            {
                first_time = time[hit];
                first_solver = solver;
            }
            rows.push_back({name, faces,
                            solver + (v.contains("error") ? " (error: " +
                                                                v["error"].get<std::string>() + ")"
                                                          : ""),
                            std::to_string(time.size() - 1), fmt(time.back()), e1,
                            v.contains("flipped_triangles")
                                ? std::to_string(v["flipped_triangles"].get<int>())
                                : "-",
                            e2, reached ? fmt(time[hit]) : "not reached",
                            reached ? std::to_string(hit) : "-", ""});
        }
        for (auto& row : rows)
        {
            row.back() = first_solver;
            t.push_back(row);
        }
    }
    os << (markdown ? "\n**ARAP solvers: energy against time (curves in " + csv_path + ")**\n\n"
                    : "\nARAP solvers: energy against time (curves in " + csv_path + ")\n");
    print_table(t, markdown, os);
}

// The paper's Table 1 (Eulzer et al.; Python + libigl on a Ryzen 7 5800X), wall seconds per
// stage, by the phantom of that size (stages it does not list are absent).
const json& paper_table_1()
{
    static const json table = {
        {"carotid-44k", {{"AC", 5.6}, {"Total", 11.2}}},
        {"carotid-300k",
         {{"Z", 16.2}, {"GC", 9.1}, {"VC", 38.1}, {"AC", 109.0}, {"L", 1.0}, {"F", 2.3},
          {"Total", 175.8}}}};
    return table;
}

void print_paper(bool markdown, std::ostream& os)
{
    Table t{{"paper (Python + libigl, Ryzen 7 5800X)", "triangles", "Z", "GC", "VC", "AC", "L", "F",
             "Total"}};
    for (const std::string name : {"carotid-44k", "carotid-300k"})
    {
        const json& stages = paper_table_1()[name];
        std::vector<std::string> row{"Table 1 row", name.substr(name.find('-') + 1)};
        for (const char* stage : {"Z", "GC", "VC", "AC", "L", "F", "Total"})
        {
            char cell[32] = "-";
            if (stages.contains(stage))
                std::snprintf(cell, sizeof cell, "%.1f", stages[stage].get<double>());
            row.push_back(cell);
        }
        t.push_back(row);
    }
    os << (markdown ? "\n**The paper's Table 1 (seconds)**\n\n" : "\nThe paper's Table 1 (s)\n");
    print_table(t, markdown, os);
}

std::string cpu_model()
{
    std::ifstream in("/proc/cpuinfo");
    std::string line;
    while (std::getline(in, line))
        if (line.rfind("model name", 0) == 0)
            return line.substr(line.find(':') + 2);
    return "unknown";
}

std::string now_utc()
{
    const std::time_t t = std::time(nullptr);
    char b[64];
    std::strftime(b, sizeof b, "%Y-%m-%d %H:%M UTC", std::gmtime(&t));
    return b;
}

std::string base_name(const std::string& path)
{
    const auto slash = path.find_last_of('/');
    std::string name = slash == std::string::npos ? path : path.substr(slash + 1);
    const auto dot = name.find_last_of('.');
    return dot == std::string::npos ? name : name.substr(0, dot);
}

}  // namespace

int main(int argc, char** argv)
{
    // The meshes' children are forked from this process and keep its malloc and BLAS: with
    // huge pages, as vessel-flatten runs a large mesh, and its BLAS kernels
    // (tools/common/restart.h).
    vessel::cli::restart_for_run(argv, true);
    CLI::App app{"vessel-bench-table: run the whole flatten() pipeline per mesh several times and "
                 "print the median (min-max) seconds per stage in the columns of the paper's "
                 "Table 1, with reading time and peak RSS (each mesh runs in its own child "
                 "process).\nDefault meshes: the valid trees of " VESSEL_SHARED_DATA
                 " plus carotid phantoms of about 4k, 13k, 20k, 44k, 100k, 300k and 1M "
                 "triangles."};
    std::vector<std::string> meshes;
    std::vector<double> phantom_edges;
    Settings s;
    bool phantoms_only = false, real_only = false, markdown = false, solvers = false;
    std::string json_path;
    app.add_option("meshes", meshes, "Meshes to run (.ply, .stl, .obj, .off); default: see above")
        ->check(CLI::ExistingFile);
    app.add_option("--runs", s.runs, "Runs per mesh")->check(CLI::PositiveNumber)->capture_default_str();
    app.add_flag("--phantoms-only", phantoms_only, "Only the generated phantoms");
    app.add_flag("--real-only", real_only, "Only the real meshes");
    app.add_option("--max-faces", s.max_faces, "Skip meshes with more triangles (0 = no limit)")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str();
    app.add_option("--cache-dir", s.cache_dir, "Where generated phantoms are kept (binary PLY)")
        ->capture_default_str();
    app.add_option("--phantom-edge", phantom_edges,
                   "Add a carotid phantom with this edge length (mm); repeatable")
        ->check(CLI::PositiveNumber);
    app.add_flag("--markdown", markdown, "Print Markdown tables");
    bool no_peer = false, skip_1m = false;
    app.add_flag("--no-peer", no_peer, "Do not run the CGAL peer pipeline");
    app.add_flag("--skip-1m", skip_1m, "Leave out the 1M-triangle phantom");
    std::string method = "default";
    app.add_option("--method", method,
                   "Pipeline timed: default (the library's defaults: one-to-one map, area polish), "
                   "paper (F = LSCM + ARAP as in the paper, overlaps allowed, no relief cuts) or "
                   "paper-untangled (the same, then flipped triangles untangled locally)")
        ->check(CLI::IsMember({"default", "paper", "paper-untangled"}))
        ->capture_default_str();
    app.add_option("--cuts", s.cuts,
                   "Cut rule timed in VC: default (the library's: per outlet the cheapest path "
                   "and a traced streamline's band, the one that winds less) or paper (the "
                   "paper's: the cheapest path, later cuts ending where they meet the tree)")
        ->check(CLI::IsMember({"default", "paper"}))
        ->capture_default_str();
    app.add_option("--coarse-vertices", s.coarse_vertices,
                   "Stage F coarse-to-fine on a mesh decimated to N vertices, as vessel-flatten's "
                   "--coarse-vertices (0 = every map at full resolution)")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str();
    app.add_option("--peer-timeout", s.peer_timeout_s,
                   "Kill the CGAL peer's child for a mesh after this long (s); recorded, not fatal")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    app.add_option("--json", json_path, "Also write all results (every sample) as JSON");
    app.add_flag("--solvers", solvers, "Solver study: each refinement variant on the real meshes");
    std::string curves_csv;
    app.add_option("--solver-curves", curves_csv,
                   "Solver study: ARAP energy after every iteration against time, Ceres and "
                   "local/global, on the real meshes; writes the curves to this CSV file");
    app.add_option("--curve-budget", s.curve_budget_s,
                   "With --solver-curves: stop a solver after this many seconds")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    app.add_option("--solver-iterations", s.solver_iterations,
                   "With --solvers: iteration limits to sweep (energy against time); default: "
                   "the library's defaults")
        ->check(CLI::PositiveNumber);
    app.add_option("--time-box", s.time_box_s,
                   "Stop repeating a mesh after a run longer than this (s); it is then reported "
                   "from the runs made, marked *")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    app.add_option("--peer-max-faces", s.peer_max_faces,
                   "Skip the CGAL peer on meshes with more triangles (0 = no limit)")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str();
    app.add_option("--timeout", s.timeout_s, "Kill a mesh's child process after this long (s)")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    CLI11_PARSE(app, argc, argv);
    if (phantoms_only && real_only)
    {
        std::cerr << "vessel-bench-table: --phantoms-only and --real-only exclude each other\n";
        return 1;
    }

    s.peer = !no_peer;
    s.method = method;
    const bool curves = !curves_csv.empty();
    if (curves)
        solvers = true;  // same mesh list: the real meshes
    std::vector<Case> cases;
    auto phantom = [&](const std::string& name, double edge, double stenosis, long faces) {
        char file[96];
        std::snprintf(file, sizeof file, "/carotid-e%g-s%g.ply", edge, stenosis);
        cases.push_back({name, s.cache_dir + file, edge, stenosis, faces});
    };
    if (!meshes.empty() || !phantom_edges.empty())
    {
        for (const auto& m : meshes)
            cases.push_back({base_name(m), m});
        for (double e : phantom_edges)
            phantom("carotid-edge-" + fmt(e), e, 0.5, 0);
    }
    else
    {
        if (!phantoms_only)
            for (const char* m : real_meshes)
                cases.push_back({base_name(m), std::string(VESSEL_SHARED_DATA) + "/" + m});
        if (!real_only && !solvers)
            for (const auto& p : phantom_sizes)
                if (!(skip_1m && p.faces > 900000))
                    phantom(p.name, p.edge_length, p.stenosis, p.faces);
    }

    std::vector<json> results;
    for (std::size_t i = 0; i < cases.size(); ++i)
    {
        const Case& c = cases[i];
        if (s.max_faces > 0 && c.nominal_faces > s.max_faces)
        {
            results.push_back({{"name", c.name},
                               {"faces", c.nominal_faces},
                               {"skipped", "more than --max-faces triangles"}});
            continue;
        }
        std::fprintf(stderr, "[%zu/%zu] %s\n", i + 1, cases.size(), c.name.c_str());
        const auto start = Clock::now();
        json generated;
        if (c.edge_length > 0)
        {
            generated = in_child(c, s, generate_phantom);
            if (generated.contains("error"))
            {
                generated["error"] = "generating the phantom: " +
                                     generated["error"].get<std::string>();
                results.push_back(generated);
                continue;
            }
            if (!generated["cached"].get<bool>())
                std::fprintf(stderr, "    generated %s: %ld triangles in %.1f s\n", c.path.c_str(),
                             generated["faces"].get<long>(), generated["generate_s"].get<double>());
        }
        json r = curves    ? in_child(c, s, on_mesh(run_curve_case))
                 : solvers ? in_child(c, s, on_mesh(run_solver_case))
                           : in_child(c, s, run_table_case);
        if (s.peer && !solvers && !r.contains("skipped"))
        {
            Settings peer_settings = s;
            peer_settings.timeout_s = s.peer_timeout_s;
            if (s.peer_max_faces > 0)
                peer_settings.max_faces = s.peer_max_faces;
            r["peer"] = in_child(c, peer_settings, on_mesh(run_peer_case));
            std::fprintf(stderr, "    CGAL peer: %s, peak RSS %.0f MB\n",
                         r["peer"].contains("error") ? r["peer"]["error"].get<std::string>().c_str()
                         : r["peer"].value("errors", json::object()).empty() ? "ok" : "a stage failed",
                         r["peer"]["peak_rss_mb"].get<double>());
        }
        if (c.edge_length > 0)
        {
            r["kind"] = "phantom";
            r["phantom"] = generated;
        }
        std::fprintf(stderr, "[%zu/%zu] %s: %s%.1f s, peak RSS %.0f MB\n", i + 1, cases.size(),
                     c.name.c_str(), status_of(r).empty() ? "" : (status_of(r) + ", ").c_str(),
                     seconds_since(start), r["peak_rss_mb"].get<double>());
        results.push_back(std::move(r));
    }

    struct rusage self = {};
    getrusage(RUSAGE_SELF, &self);
    std::ostream& os = std::cout;
    os << (markdown ? "" : "# ") << "vessel-bench-table, " << now_utc() << ", " << cpu_model()
       << ", " << sysconf(_SC_NPROCESSORS_ONLN) << " logical CPUs, " << s.runs
       << " runs per mesh (* = time-boxed after a run over " << fmt(s.time_box_s)
       << " s); peak RSS per mesh includes ~" << fmt(self.ru_maxrss / 1024.0)
       << " MB of the harness inherited at fork.\n";
    if (curves)
        print_curves(results, curves_csv, markdown, os);
    else if (solvers)
        print_solver_results(results, markdown, os);
    else
    {
        print_results(results, markdown, os);
        print_peer(results, markdown, os);
        print_paper(markdown, os);
    }

    if (!json_path.empty())
    {
        json doc{{"date", now_utc()},
                 {"cpu", cpu_model()},
                 {"logical_cpus", sysconf(_SC_NPROCESSORS_ONLN)},
                 {"huge_pages", vessel::cli::asks_huge_pages(environ)},
                 {"blas_kernels", vessel::cli::running_blas_kernels()},
                 {"runs", s.runs},
                 {"mode", curves    ? "solver-curves"
                          : solvers ? "solvers"
                                    : "table"},
                 {"paper_table_1", paper_table_1()},
                 {"results", results}};
        std::ofstream(json_path) << doc.dump(2) << "\n";
    }
    for (const json& r : results)
        if (r.contains("error"))
            return 2;
    return 0;
}
