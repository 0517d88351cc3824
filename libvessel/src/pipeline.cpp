#include "vessel/pipeline.h"

#include "vessel/cut/cut_route.h"

#include "vessel/cut/cut.h"
#include "vessel/cut/cut_metrics.h"
#include "vessel/cut/endpoints.h"
#include "vessel/direction/direction.h"
#include "vessel/map/embedding.h"
#include "vessel/core/errors.h"
#include "vessel/map/lscm.h"
#include "vessel/core/properties.h"
#include "vessel/map/spectral.h"
#include "detail/disk_flatten.h"
#include "detail/look_retry.h"
#include "detail/refine_map.h"
#include "detail/solve_map.h"
#include "detail/stage_clock.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <future>
#include <mutex>
#include <optional>

namespace vessel {

FlattenOptions FlattenOptions::paper()
{
    FlattenOptions o;
    o.refinement = Refinement::Arap;
    o.overlaps = OverlapPolicy::Keep;
    o.relief.max_cuts = 0;
    return o;
}

void FlattenOptions::validate() const
{
    curvature.validate();
    geodesic.validate();
    direction.validate();
    cuts.validate();
    relief.validate();
    if (!(progress_interval_s >= 0.0 && std::isfinite(progress_interval_s)))
        throw InvalidInputError(
            "FlattenOptions: progress_interval_s must be >= 0 and finite, got " +
            std::to_string(progress_interval_s));
    if (refinement != Refinement::None && arap.max_iterations > 0)
        arap.validate();
    if (refinement == Refinement::Injective)
    {
        untangle.validate();
        layout_circle.validate();
        look_pull.validate();
        look_retry.validate();
        multilevel.validate();
        if (polish_area)
            area_polish.validate();
        if (injective.max_iterations > 0)
            injective.validate();
    }
    cost.validate();
    if (!(alpha_deg >= 0.0 && alpha_deg < 90.0))
        throw InvalidInputError("FlattenOptions: alpha_deg must be in [0, 90), got " +
                                std::to_string(alpha_deg));
}

namespace {

using detail::StageClock;

template <class T>
void store(Mesh& mesh, const char* name, const std::function<T(int)>& value)
{
    auto property = OpenMesh::VProp<T>(mesh, name);
    for (auto v : mesh.vertices())
        property[v] = value(v.idx());
}

// Rotates and translates the map so that the inlet runs along the u axis, centred at the origin,
// with the rest of the map above it (the paper's look).
void put_inlet_at_bottom(const Pins& inlet, Eigen::MatrixX2d& uv)
{
    const Eigen::Vector2d right = uv.row(inlet.front().vertex.idx()).transpose();
    const Eigen::Vector2d left = uv.row(inlet.back().vertex.idx()).transpose();
    const Eigen::Vector2d chord = right - left;
    const double angle = -std::atan2(chord.y(), chord.x());
    const Eigen::Matrix2d R = Eigen::Rotation2Dd(angle).toRotationMatrix();
    const Eigen::RowVector2d centre = (0.5 * (left + right)).transpose();
    uv = ((uv.rowwise() - centre) * R.transpose()).eval();
}



// Stage Z (step 3) on the uncut mesh: boundary loops, geodesic distance from the inlet, the
// harmonic longitudinal coordinate (read by the direction's guide, the streamline route, the
// winding of the cuts and the report) and the aligned direction field. Also stored as vertex
// properties, which the seam split copies to the duplicates. A relief cut re-cuts the same
// surface, so its passes reuse this.
struct DirectionStage
{
    std::vector<BoundaryLoop> loops;
    Eigen::VectorXd G;
    Eigen::VectorXd H;  // harmonic_longitudinal()
    Eigen::MatrixX3d z;
    Eigen::MatrixX3d winding;  // winding_rate() of z, for the cut planner
    Eigen::VectorXd kmax;      // |k_max|
    // The field the streamline routes trace (CutPlanOptions::stream_field): the descent of H
    // (empty for a route that traces none, or when it is z itself).
    Eigen::MatrixX3d stream;
    double seconds = 0.0;
};

// Whether the cut route of \p cuts traces a stream field (CutRoutePolicy::needs_stream_field()).
bool traces_stream(const CutPlanOptions& cuts)
{
    return (cuts.router ? cuts.router : route_policy(cuts.route))->needs_stream_field();
}

// Meshes from this many vertices get the stream field on the second core beside the vessel
// direction and its winding rate; below it a thread's start (50-100 us here) costs more than
// the field (aorta, 9k vertices: 0.5 ms).
constexpr std::size_t kStreamThreadVertices = 4000;

DirectionStage direction_stage(Mesh& mesh, const FlattenOptions& options)
{
    StageClock clock(options, "Z");
    DirectionStage stage;
    stage.loops = boundary_loops(mesh);
    if (stage.loops.size() < 2)
        throw InvalidInputError("flatten: the mesh has " + std::to_string(stage.loops.size()) +
                                " boundary loop(s); a vessel tree needs an inlet and an outlet");
    // The elimination ordering of the uncut mesh (the heat method's two factorizations and the
    // harmonic coordinate's share it), then the harmonic coordinate's factorization (it needs
    // only the loops), run on their own thread beside the curvature fits and the heat method's
    // factorizations, which leave the second core idle part of the time (single-threaded
    // symbolic analyses and solves). The heat method waits for the ordering.
    std::promise<std::shared_ptr<const VertexOrdering>> ordering;
    std::future<std::shared_ptr<const VertexOrdering>> ordered = ordering.get_future();
    std::future<HarmonicLongitudinal> harmonic =
        std::async(std::launch::async, [&mesh, &stage, &ordering] {
            std::shared_ptr<const VertexOrdering> order;
            try
            {
                order = std::make_shared<const VertexOrdering>(laplacian_ordering(mesh));
            }
            catch (...)
            {
                ordering.set_exception(std::current_exception());
                throw;
            }
            ordering.set_value(order);
            return HarmonicLongitudinal(mesh, stage.loops, order.get());
        });
    const PrincipalCurvature curvature = principal_curvature(mesh, options.curvature);
    HeatGeodesicsOptions geodesic = options.geodesic;
    const std::shared_ptr<const VertexOrdering> uncut_order = ordered.get();
    if (!geodesic.ordering)
        geodesic.ordering = uncut_order;
    const HeatGeodesics heat(mesh, geodesic);
    stage.G = heat.distance(stage.loops[0].vertices);
    stage.H = harmonic.get().solve(stage.G);
    // The streamline routes' field, an alignment field like z (it runs along every vessel
    // toward the root), made here beside z rather than in VC, on the otherwise idle core.
    const bool harmonic_stream =
        traces_stream(options.cuts) && options.cuts.stream_field == StreamField::Harmonic;
    std::future<Eigen::MatrixX3d> stream;
    if (harmonic_stream && mesh.n_vertices() >= kStreamThreadVertices)
        stream = std::async(std::launch::async,
                            [&mesh, &stage] { return descent_direction(mesh, stage.H); });
    else if (harmonic_stream)
        stage.stream = descent_direction(mesh, stage.H);
    stage.z = vessel_direction_guided(mesh, curvature, stage.G, stage.H, options.direction);
    stage.kmax = curvature.k_max.cwiseAbs();
    const Eigen::VectorXd& kmax = stage.kmax;
    stage.winding = winding_rate(mesh, stage.z, kmax);
    if (stream.valid())  // before the properties are added: the thread reads the mesh
        stage.stream = stream.get();
    store<double>(mesh, prop::geodesic, [&](int i) { return stage.G[i]; });
    store<double>(mesh, prop::longitudinal, [&](int i) { return stage.H[i]; });
    store<double>(mesh, prop::kmax, [&](int i) { return kmax[i]; });
    store<OpenMesh::Vec3d>(mesh, prop::direction,
                           [&](int i) { return to_openmesh(stage.z.row(i).transpose()); });
    stage.seconds = clock.lap("Z");
    return stage;
}

// The cost options' weights, before the facing price (price_facing()) of CostOptions::viewpoint.
HalfedgeWeights unpriced_weights(const Mesh& mesh, const DirectionStage& zstage,
                                 const FlattenOptions& options)
{
    const Eigen::MatrixX3d& z = zstage.z;
    if (options.cost.custom)
        return evaluate_cost(mesh, options.cost.custom,
                             {&z, &zstage.G, &zstage.H, &zstage.kmax, mean_edge_length(mesh)});
    const CurvatureCost curvature{&z};
    switch (options.cost.kind)
    {
        case CostKind::Curvature:
            return evaluate_cost(mesh, curvature);
        case CostKind::Geodesic:
            return evaluate_cost(mesh, LengthCost{mean_edge_length(mesh)});
        case CostKind::Blend:
            return evaluate_cost(mesh, BlendCost{curvature, LengthCost{mean_edge_length(mesh)},
                                                 options.cost.blend});
    }
    throw InvalidInputError("flatten: unknown cost kind");
}

HalfedgeWeights travel_weights(const Mesh& mesh, const DirectionStage& zstage,
                               const FlattenOptions& options)
{
    HalfedgeWeights weights = unpriced_weights(mesh, zstage, options);
    if (options.cost.viewpoint)
        price_facing(mesh, *options.cost.viewpoint, options.cost.facing_weight, weights);
    return weights;
}

// One pass of steps 4-7 on \p mesh (uncut, with stage Z's properties); with \p forced_plan the
// cuts are taken from it instead of planned.
FlattenResult flatten_once(Mesh mesh, const FlattenOptions& options, const DirectionStage& zstage,
                           const CutPlan* forced_plan)
{
    FlattenResult result;
    result.viewpoint = options.cost.viewpoint;
    // A copied mesh's arrays are exactly full, so the seam split's first new vertex would
    // reallocate them all (O(V)) inside the cut stage; make room for the duplicates up front.
    mesh.reserve(mesh.n_vertices() + mesh.n_vertices() / 8 + 64,
                 mesh.n_edges() + mesh.n_edges() / 8 + 64, mesh.n_faces());
    StageClock clock(options, "GC");
    result.loops = zstage.loops;
    const Eigen::VectorXd& G = zstage.G;
    const Eigen::MatrixX3d& z = zstage.z;
    result.timings.Z = zstage.seconds;

    // GC: the directed cut graph (arc weights, arcs per vertex), released after VC.
    const HalfedgeWeights weights =
        forced_plan ? HalfedgeWeights() : travel_weights(mesh, zstage, options);
    auto graph = forced_plan ? nullptr : std::make_unique<CutGraph>(mesh, weights);
    result.timings.GC = clock.lap("GC", "VC");

    // VC: cut paths (the streamline routes also trace a field toward the root, made in Z).
    const bool trace_z =
        traces_stream(options.cuts) && options.cuts.stream_field == StreamField::Direction;
    result.plan = forced_plan ? *forced_plan
                              : plan_cuts(*graph, result.loops, zstage.winding, options.cuts,
                                          trace_z ? z : zstage.stream, zstage.H, z);
    graph.reset();
    result.timings.VC = clock.lap("VC", "AC");

    // AC: split the seam in place.
    const std::size_t n_before = mesh.n_vertices();
    const CutSummary cut = cut_along_edges(mesh, result.plan.seam_edges(mesh));
    result.seam_edges = cut.seam_edges;
    result.duplicated_vertices = cut.duplicated_vertices;
    result.timings.AC = clock.lap("AC", "L");

    // L: pin the inlet and outlets.
    std::vector<int> loop_of(n_before, -1);
    for (std::size_t l = 0; l < result.loops.size(); ++l)
        for (auto v : result.loops[l].vertices)
            loop_of[v.idx()] = static_cast<int>(l);
    LayoutInput input;
    input.mesh = &mesh;
    input.loops = &result.loops;
    input.plan = &result.plan;
    input.geodesic = &G;
    auto origin = OpenMesh::VProp<int>(mesh, prop::origin);
    input.origin.resize(mesh.n_vertices());
    for (auto v : mesh.vertices())
        input.origin[v.idx()] = origin[v];
    input.segments = boundary_segments(mesh, input.origin, loop_of);
    const std::shared_ptr<const Layout> layout =
        options.layout ? options.layout : std::make_shared<BranchFanLayout>(options.alpha_deg);
    const LayoutResult placed = layout->place(input);
    result.timings.L = clock.lap("L", "F");

    // F: the map (solve_map.h: coarse-to-fine on large meshes), the inlet at the bottom.
    if (!detail::solve_map(mesh, input, placed, options, result))
        put_inlet_at_bottom(placed.inlet, result.uv);
    store<OpenMesh::Vec2d>(
        mesh, prop::uv, [&](int i) { return OpenMesh::Vec2d(result.uv(i, 0), result.uv(i, 1)); });
    result.timings.F = clock.lap("F");

    result.quality = flat_quality(mesh, result.uv);
    result.look = map_look(mesh, result.uv, input.segments, placed);
    result.mesh = std::move(mesh);
    return result;
}

// Stage Z ran once for all passes; the other stages ran once per pass.
void add_timings(StageTimings& to, const StageTimings& from)
{
    to.GC += from.GC;
    to.VC += from.VC;
    to.AC += from.AC;
    to.L += from.L;
    to.F += from.F;
}

}  // namespace

namespace detail {

FlattenOptions with_progress(const FlattenOptions& options)
{
    if (!options.on_progress)
        return options;
    FlattenOptions wired = options;
    using Clock = std::chrono::steady_clock;
    // The last iteration report (none yet: the first is made at once), under a lock: the
    // coarse-to-fine path solves the look retry's reference on a second thread, whose solvers
    // report too, and on_progress is called from one thread at a time.
    struct Last
    {
        std::mutex mutex;
        std::optional<Clock::time_point> at;
    };
    auto last = std::make_shared<Last>();
    const auto report = [last, on_progress = options.on_progress,
                         interval = options.progress_interval_s](const char* phase, int iteration,
                                                                 int max_iterations) {
        const std::lock_guard<std::mutex> lock(last->mutex);
        const Clock::time_point now = Clock::now();
        if (last->at && std::chrono::duration<double>(now - *last->at).count() < interval)
            return;
        last->at = now;
        Progress progress;
        progress.stage = "F";
        progress.phase = phase;
        progress.iteration = iteration;
        progress.max_iterations = max_iterations;
        on_progress(progress);
    };
    // Ceres' ARAP would pay an energy evaluation per call: not reported.
    if (options.arap.solver == ArapSolver::LocalGlobal)
        wired.arap.on_iteration = [report, caller = options.arap.on_iteration,
                                   limit = options.arap.max_iterations](int it, double energy) {
            report("arap", it, limit);
            return caller ? caller(it, energy) : true;
        };
    wired.injective.on_iteration = [report, caller = options.injective.on_iteration,
                                    limit = options.injective.max_iterations](int it,
                                                                              bool scaffold) {
        report(scaffold ? "scaffold" : "slim", it, limit);
        if (caller)
            caller(it, scaffold);
    };
    const AreaPolishOptions& polish = options.area_polish;
    wired.area_polish.on_step = [report, caller = polish.on_step,
                                  limit = polish.newton ? polish.newton_max_iterations
                                                        : polish.max_iterations](int done) {
        report("polish", done, limit);
        if (caller)
            caller(done);
    };
    wired.multilevel.on_sweep = [report, caller = options.multilevel.on_sweep,
                                 limit = options.multilevel.relax_sweeps](int sweeps) {
        report("relax", sweeps, limit);
        if (caller)
            caller(sweeps);
    };
    return wired;
}

}  // namespace detail

FlattenResult flatten(Mesh mesh, const FlattenOptions& caller_options)
{
    caller_options.validate();
    FlattenOptions options = detail::with_progress(caller_options);
    if (options.cost.face_on)
    {
        options.cost.viewpoint = face_on_viewpoint(mesh);
        options.cost.face_on = false;
        if (!options.cuts.endpoints)
            options.cuts.endpoints = std::make_shared<FarSideEndpoints>(*options.cost.viewpoint);
    }
    if (boundary_loops(mesh).size() == 1)  // a disk already: no cuts, no relief cuts
        return detail::flatten_disk(std::move(mesh), options);
    const ReliefCutOptions& relief = options.relief;
    // Without refinement the map is the raw initialization, whose distortion says nothing
    // about where the surface needs a slit.
    const DirectionStage zstage = direction_stage(mesh, options);
    if (relief.max_cuts == 0 || (options.refinement == Refinement::None && !options.refiner))
        return flatten_once(std::move(mesh), options, zstage, nullptr);
    const Mesh uncut = mesh;  // each relief cut re-cuts the mesh as it came in (with stage Z)
    FlattenResult result = flatten_once(std::move(mesh), options, zstage, nullptr);
    std::vector<std::string> relief_notes;
    while (static_cast<int>(result.plan.relief.size()) < relief.max_cuts &&
           result.quality.mean_abs_log_area_normalized > relief.target_mean_abs_log_area)
    {
        const Eigen::VectorXd log_area =
            vertex_log_area_ratio(uncut, result.mesh, result.uv, relief.smoothing_passes);
        std::optional<CutPath> slit = plan_relief_cut(uncut, result.loops, result.plan, log_area, relief.min_rings);
        if (!slit)
            break;
        CutPlan plan = result.plan;
        plan.relief.push_back(std::move(*slit));
        FlattenResult next = flatten_once(uncut, options, zstage, &plan);
        add_timings(next.timings, result.timings);
        const FlatQuality& before = result.quality;
        const FlatQuality& after = next.quality;
        char line[200];
        std::snprintf(line, sizeof line,
                      "relief cut %zu (%zu edges): mean |log area| %.3f -> %.3f, %d -> %d "
                      "overlapping triangles",
                      plan.relief.size(), plan.relief.back().halfedges.size(),
                      before.mean_abs_log_area_normalized, after.mean_abs_log_area_normalized,
                      before.overlapping_triangles, after.overlapping_triangles);
        const bool better = after.mean_abs_log_area_normalized <
                                before.mean_abs_log_area_normalized &&
                            after.flipped_triangles <= before.flipped_triangles &&
                            after.overlapping_triangles <= before.overlapping_triangles;
        if (!better)
        {
            result.timings = next.timings;
            relief_notes.push_back(std::string(line) + "; not better, not kept");
            break;
        }
        relief_notes.push_back(line);
        result = std::move(next);
    }
    result.notes.insert(result.notes.end(), relief_notes.begin(), relief_notes.end());
    return result;
}

Eigen::VectorXd uncut_longitudinal(const FlattenResult& result, std::size_t uncut_vertices)
{
    OpenMesh::VPropHandleT<double> longitudinal;
    if (!result.mesh.get_property_handle(longitudinal, prop::longitudinal))
        throw InvalidInputError(std::string("uncut_longitudinal: the mesh has no '") +
                                prop::longitudinal + "' property; pass the result of flatten()");
    if (result.mesh.n_vertices() < uncut_vertices)
        throw InvalidInputError("uncut_longitudinal: the cut mesh has " +
                                std::to_string(result.mesh.n_vertices()) + " vertices, fewer "
                                "than the " + std::to_string(uncut_vertices) +
                                " of the uncut mesh; pass the mesh given to flatten()'s size");
    Eigen::VectorXd H(static_cast<Eigen::Index>(uncut_vertices));
    for (std::size_t v = 0; v < uncut_vertices; ++v)
        H[static_cast<Eigen::Index>(v)] =
            result.mesh.property(longitudinal, VertexHandle(static_cast<int>(v)));
    return H;
}

}  // namespace vessel
