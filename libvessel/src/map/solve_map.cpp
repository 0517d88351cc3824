// Stage F (solve_map.h): the single-level map, and the coarse-to-fine one (multilevel.h) that
// runs the single level on a decimated copy of the cut mesh.
#include "detail/solve_map.h"

#include "detail/boundary_guard.h"
#include "detail/face_jacobian.h"
#include "detail/look_retry.h"
#include "detail/map_distortion.h"
#include "detail/refine_map.h"
#include "detail/segments.h"
#include "detail/vertex_order.h"
#include "vessel/core/errors.h"
#include "vessel/map/area_polish.h"
#include "vessel/map/centre_pull.h"
#include "vessel/map/embedding.h"
#include "vessel/map/lscm.h"
#include "vessel/map/map_look.h"
#include "vessel/map/multilevel.h"
#include "vessel/map/spectral.h"
#include "vessel/map/untangle.h"
#include "vessel/quality/metrics.h"
#include "vessel/solve/ordering.h"

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <functional>
#include <future>
#include <limits>
#include <optional>

namespace vessel::detail {

namespace {

Pins concat(const Pins& a, const Pins& b)
{
    Pins all = a;
    all.insert(all.end(), b.begin(), b.end());
    return all;
}

// The map refinement starts from (FlattenOptions::initialization).
Eigen::MatrixX2d initial_map(const Mesh& mesh, const LayoutResult& placed,
                             Initialization initialization, const VertexOrdering* order)
{
    switch (initialization)
    {
        case Initialization::SpectralConformal:
            return spectral_conformal(mesh);
        case Initialization::Tutte:
            return tutte_embedding(mesh);
        case Initialization::LayoutLscm:
            break;
    }
    return lscm(mesh, concat(placed.inlet, placed.outlets), order);
}

// The inlet's pins for the refinement of \p initial: the layout's, or where the initial map
// put them when it is not the layout's LSCM map.
Pins inlet_pins(const LayoutResult& placed, const Eigen::MatrixX2d& initial, bool at_layout)
{
    Pins pins = placed.inlet;
    if (!at_layout)
        for (auto& pin : pins)
            pin.uv = initial.row(pin.vertex.idx()).transpose();
    return pins;
}

// Runs `stop` when it goes out of scope: declared after the std::future of a solve made ahead
// with a cancel flag, it sets the flag before the future's destructor waits for the solve to
// end (cancellable(): at its next iteration; the exception stays in the future, unread).
struct StopAhead
{
    std::function<void()> stop;
    ~StopAhead() { stop(); }
};

// Outlets of a tree (the loops of its boundary segments but the inlet, loop 0).
int outlet_count(const LayoutInput& input)
{
    int outlets = 0;
    for (const BoundarySegment& segment : input.segments)
        outlets = std::max(outlets, segment.loop);
    return outlets;
}

// The fewest outlets for which solve_single_level() solves the look retry's pulled map ahead.
// The more outlets, the likelier a restart from the layout circle breaks the fan's order and the
// retry follows; where it does not, the pulled map was solved for nothing beside the restarted
// one, which it slows (two cores: docs/benchmarks.md, "The look retry ahead").
constexpr int kPulledAheadOutlets = 16;

// The fewest outlets for which the hierarchy makes no new chords (coarsen()'s
// `no_new_chords`): on 30-outlet tree phantoms a chord's sliver in the coarse map's start held
// SLIM to steps of nothing and the map was solved again at full resolution; on the carotid
// phantoms (two outlets) chords did not raise the start's energy, and without them the
// finest level's relaxation took longer (docs/benchmarks.md "No new chords on many-outlet trees").
constexpr int kChordFreeOutlets = 16;

// The map at full resolution: initial map, refinement with the inlet pinned, look retry.
// \p start as refine_map()'s, for the default map's restart (not the look retry's).
bool solve_single_level(const Mesh& mesh, const LayoutInput& input, const LayoutResult& placed,
                        const FlattenOptions& options, FlattenResult& result,
                        const RestartStart* start = nullptr)
{
    const bool may_restart =
        options.refinement == Refinement::Injective && options.overlaps != OverlapPolicy::Keep;
    // Where ARAP surely runs (no restart can skip it: the paper's refinement, or overlaps
    // kept), its factorization, which depends on the cut mesh and the inlet but not on the
    // initial map, is made on the second core while the initial map is solved (same bits).
    // LSCM and it share one elimination ordering of the cut mesh (AMD on its whole vertex
    // graph; each system leaves out its pinned vertices). Carrying stage Z's ordering of the
    // uncut mesh over instead would skip this AMD but costs more in fill (carotid-300k: LSCM
    // 9.6 against 7.2 GFlop); the whole graph's gives less than LSCM's own AMD of its free
    // vertices (7.96 GFlop), and ARAP's own AMD is saved.
    const bool arap_ahead = !options.refiner && options.refinement != Refinement::None &&
                            options.arap.max_iterations > 0 &&
                            options.arap.solver == ArapSolver::LocalGlobal &&
                            !options.arap.prefactored && !may_restart;
    const bool at_lscm = options.initialization == Initialization::LayoutLscm;
    const VertexOrdering cut_order =
        arap_ahead || at_lscm ? laplacian_ordering(mesh) : VertexOrdering{};
    std::future<std::shared_ptr<const ArapFactor>> arap_factor;
    if (arap_ahead)
        arap_factor = std::async(std::launch::async, [&mesh, &placed, &cut_order] {
            return arap_prefactor(mesh, placed.inlet, &cut_order);
        });
    bool at_layout = at_lscm;
    result.uv = initial_map(mesh, placed, options.initialization, &cut_order);
    FlattenOptions prefactored;  // options with the factor, when made ahead
    const FlattenOptions& refine_options = arap_factor.valid() ? prefactored : options;
    if (arap_factor.valid())
    {
        prefactored = options;
        prefactored.arap.prefactored = arap_factor.get();
    }
    const Pins pins = inlet_pins(placed, result.uv, at_layout);
    if (options.refiner)
        return refine_by_policy(mesh, &input, &placed, *options.refiner, pins, at_layout, result);
    const std::string crossing = "the map at the layout overlaps itself (its boundary crosses)";
    // A restart discards ARAP and untangling. When the LSCM map at the layout already crosses
    // itself, restart before them: on the 9 valid real trees and the 13k/44k carotid phantoms,
    // ARAP never removed a crossing of the LSCM map (9 of 9 stayed crossed), so this skips
    // only work whose result was thrown away (docs/benchmarks.md).
    const bool crosses_at_once =
        may_restart && at_layout && boundary_self_intersection(mesh, result.uv).first >= 0;
    const Eigen::MatrixX2d initial = result.uv;  // for the look retry's `keep` map
    // Where the map restarts at once on a tree of many outlets, the look retry's pulled map is
    // solved beside it on the second core: it starts from the layout circle as the restarted
    // map does and depends on nothing that map gives, and a restart from the circle often loses
    // the fan's order on such trees, so that the retry follows. Where the look turns out whole,
    // the pulled map is stopped at its next iteration and dropped. Either way the maps are those
    // of the retry made after the fact. It runs at the caller's priority: the retry waits for
    // it, and a thread at a lower one (nice 19) starves behind any other busy process, so that
    // the whole run waits on it (docs/benchmarks.md, "The look retry ahead").
    std::atomic<bool> cancel_ahead{false};
    std::future<FlattenResult> pulled_ahead;
    const StopAhead stop_ahead{[&] { cancel_ahead = true; }};
    if (crosses_at_once && may_retry_look(options) && outlet_count(input) >= kPulledAheadOutlets)
    {
        pulled_ahead = std::async(std::launch::async, [&] {
            return pulled_map(mesh, pins, options, input, placed, &cancel_ahead);
        });
    }
    if (refine_map(mesh, pins, refine_options, crossing,
                   crosses_at_once ? std::optional<std::string>(crossing) : std::nullopt, result,
                   &input, &placed, start))
    {
        at_layout = false;
        retry_look(mesh, pins, initial, options, result, input, placed, &pulled_ahead);
    }
    return at_layout;
}

// Pins on kept vertices, renumbered: `index[v]` is v's new index, or -1 if it was dropped.
Pins renumbered(const Pins& pins, const std::vector<int>& index)
{
    Pins kept;
    for (const Pin& pin : pins)
        if (const int c = index[pin.vertex.idx()]; c >= 0)
            kept.push_back({VertexHandle(c), pin.uv});
    return kept;
}

// Index of each fine vertex in level `depth` of the hierarchy (0 = the fine mesh), or -1.
std::vector<int> index_at(const std::vector<CoarseMesh>& levels, std::size_t depth,
                          std::size_t n_fine)
{
    std::vector<int> index(n_fine);
    for (std::size_t v = 0; v < n_fine; ++v)
    {
        int c = static_cast<int>(v);
        for (std::size_t k = 0; k < depth && c >= 0; ++k)
            c = levels[k].coarse_of[c];
        index[v] = c;
    }
    return index;
}

// A face whose doubled area is below this fraction of the squared lengths of its two edges at
// a vertex counts as collapsed: its Jacobian's determinant, computed from other differences,
// is then within rounding of 0 and can come out non-positive, which relax_area() refuses.
constexpr double kCollapsed = 1e-10;

// Whether every face around v stays counter-clockwise with v at p, none collapsed; `at(w)` is
// the map's point of vertex w (v's own is not read).
template <class At>
bool star_positive_at(const Mesh& mesh, VertexHandle v, const Eigen::Vector2d& p, const At& at)
{
    for (auto h : mesh.voh_range(v))
    {
        if (mesh.is_boundary(h))
            continue;
        const Eigen::Vector2d a = at(mesh.to_vertex_handle(h).idx());
        const Eigen::Vector2d b = at(mesh.to_vertex_handle(mesh.next_halfedge_handle(h)).idx());
        if (!(detail::orient(p, a, b) > kCollapsed * ((a - p).squaredNorm() + (b - p).squaredNorm())))
            return false;
    }
    return true;
}

// The mean of the map's points (`at(w)`) of v's one ring.
template <class At>
Eigen::Vector2d ring_centre(const Mesh& mesh, VertexHandle v, const At& at)
{
    Eigen::Vector2d centre = Eigen::Vector2d::Zero();
    int ring = 0;
    for (auto w : mesh.vv_range(v))
    {
        centre += at(w.idx());
        ++ring;
    }
    return centre / std::max(ring, 1);
}

// Where two parts of the coarse map's boundary nearly touch (two branches laid side by side),
// vertices put back onto their coarse edges can cross the other part by rounding. Each
// crossing is undone by moving one of its four ends that is not pinned part of the way toward
// the centre of its one ring, into the interior, to the first point where its faces stay
// positive and that crossing is gone (another crossing found then is taken in the next round).
// Returns whether the boundary is simple at the end.
bool open_contacts(const Mesh& mesh, Eigen::MatrixX2d& uv, const Pins& pins)
{
    std::vector<char> fixed(mesh.n_vertices(), 0);
    for (const Pin& pin : pins)
        fixed[pin.vertex.idx()] = 1;
    const auto row = [&](int w) { return Eigen::Vector2d(uv.row(w).transpose()); };
    for (int round = 0; round < 100; ++round)
    {
        const auto [h0, h1] = boundary_self_intersection(mesh, uv);
        if (h0 < 0)
            return true;
        bool moved = false;
        for (int h : {h0, h1})
            for (VertexHandle v : {mesh.from_vertex_handle(mesh.halfedge_handle(h)),
                                   mesh.to_vertex_handle(mesh.halfedge_handle(h))})
            {
                if (moved || fixed[v.idx()])
                    continue;
                const Eigen::Vector2d centre = ring_centre(mesh, v, row);
                const Eigen::Vector2d start = row(v.idx());
                for (double t : {1e-3, 1e-2, 0.05, 0.1, 0.25, 0.5, 0.75, 0.9})
                {
                    const Eigen::Vector2d p = start + t * (centre - start);
                    uv.row(v.idx()) = p.transpose();
                    if (star_positive_at(mesh, v, p, row) &&
                        boundary_self_intersection(mesh, uv) != std::make_pair(h0, h1))
                    {
                        moved = true;
                        break;
                    }
                }
                if (!moved)
                    uv.row(v.idx()) = start.transpose();
            }
        if (!moved)
            return false;
    }
    return boundary_self_intersection(mesh, uv).first < 0;
}

// Where two parts of the carried map's boundary come nearer each other than the boundary
// guard's clearance (detail/boundary_guard.h: the coarse map's slits between branches laid side
// by side, carried up), the map is one-to-one only up to the rounding of its written
// coordinates. Each end of such a contact that is not pinned is moved part of the way toward
// the centre of its one ring (into the map, away from the gap), to the first point where its
// faces stay positive, the guard allows the move and its edges clear every other by the
// clearance (or, where none does, the point that widens the gap most); a few rounds, the guard
// rebuilt between them. Returns the number of boundary vertices still at a contact.
std::size_t open_near_contacts(const Mesh& mesh, Eigen::MatrixX2d& uv, const Pins& pins)
{
    std::vector<char> fixed(mesh.n_vertices(), 0);
    for (const Pin& pin : pins)
        fixed[pin.vertex.idx()] = 1;
    Eigen::VectorXd xv = detail::interleaved(uv);
    double* x = xv.data();
    const auto at = [&](int v) { return Eigen::Vector2d(x[2 * v], x[2 * v + 1]); };
    detail::BoundaryGuard guard(mesh);
    for (int round = 0; round < 8; ++round)
    {
        guard.rebuild(x);
        const std::vector<int> ends = guard.near_contacts(x);
        if (ends.empty())
            return 0;
        for (const int v : ends)
        {
            if (fixed[v])
                continue;
            const Eigen::Vector2d start = at(v);
            const double before = guard.gap(x, v, start);
            if (before >= guard.clearance())
                continue;
            Eigen::Vector2d toward = ring_centre(mesh, VertexHandle(v), at) - start;
            if (toward.norm() > guard.max_step())
                toward *= guard.max_step() / toward.norm();
            Eigen::Vector2d best = start;
            double widest = before;
            for (const double t : {0.05, 0.1, 0.2, 0.35, 0.5, 0.75, 1.0})
            {
                const Eigen::Vector2d p = start + t * toward;
                if (!star_positive_at(mesh, VertexHandle(v), p, at) || !guard.allows(x, v, start, p))
                    continue;
                const double gap = guard.gap(x, v, p);
                if (gap > widest)
                {
                    best = p;
                    widest = gap;
                }
                if (gap >= guard.clearance())
                    break;
            }
            x[2 * v] = best.x();
            x[2 * v + 1] = best.y();
        }
    }
    detail::deinterleave(xv, uv);
    guard.rebuild(x);
    return guard.near_contacts(x).size();
}

// The area weight lambda the carried maps are relaxed with: the area polish's when it runs,
// else an even mix of the two energies.
double relax_weight(const FlattenOptions& options)
{
    return options.polish_area ? options.area_polish.area_weight : 0.5;
}

// A note of what relax_area() did at full resolution, after \p prefix; returns the energy's
// isometric minimum (twice the surface area).
double relax_note(const char* prefix, const Mesh& mesh, const RelaxSummary& relaxed,
                  FlattenResult& result)
{
    const double minimum = 2.0 * face_areas(mesh).sum();
    char line[200];
    std::snprintf(line, sizeof line,
                  "%s%d relaxation sweeps, %d coarse-grid corrections, energy / minimum %.5f -> "
                  "%.5f%s",
                  prefix, relaxed.sweeps, relaxed.corrections, relaxed.energy_before / minimum,
                  relaxed.energy_after / minimum,
                  relaxed.area_within_tolerance ? " (the map's area within the area tolerance)"
                                                : "");
    result.notes.push_back(line);
    return minimum;
}

// The area polish's options for a carried map of \p options' flattening: the energy the carry
// relaxes (weight \p lambda), its boundary kept simple unless overlaps are kept, and a pulled
// map's \p pulls (empty: none) taken as the look pull's solvers take them.
AreaPolishOptions carried_polish(const FlattenOptions& options, double lambda,
                                 std::vector<CentrePull> pulls)
{
    AreaPolishOptions polish = options.area_polish;
    polish.area_weight = lambda;  // the energy the bound is held on
    polish.keep_boundary_simple = options.overlaps != OverlapPolicy::Keep;
    polish.centre_pulls = std::move(pulls);
    polish.pull_steps = options.look_pull.solver_steps();
    return polish;
}

// The energy of \p uv that relax_area() lowers (its sweeps' energy, no sweep made).
double relaxed_energy(const Mesh& mesh, const Eigen::MatrixX2d& uv, const Pins& pins,
                      double lambda, const MultilevelOptions& multilevel)
{
    MultilevelOptions measure = multilevel;
    measure.relax_sweeps = 0;
    Eigen::MatrixX2d copy = uv;
    return relax_area(mesh, copy, pins, lambda, measure).energy_after;
}

// Where the carry's relaxation of the finest level stopped at MultilevelOptions::relax_sweeps
// short of its minimum, the map is finished with kFinishNewtonSteps projected Newton steps of
// the whole map (area_polish(), one scaffold; a pulled map with its pulls): its energy above
// kFinishRatio times the isometric minimum, and its last sweep still lowering it by more than
// kFinishProgress of that excess. Carries whose sweeps have converged end below the ratio on the
// carotids and most trees; above it, many-outlet trees whose coarse map moved far are still
// moving, where the sweeps and coarse-grid corrections remove the rest only slowly (the
// energy's own slow tail near its minimum); a surface of intrinsic distortion (an aneurysm's
// sac) is not. Three steps cost about as much as the 32 sweeps and 16 corrections they replaced
// and leave less area distortion (docs/benchmarks.md "The carry finished by Newton steps where
// it stops short").
// A carry whose sweeps have stalled is finished as well where it stopped above
// kStalledFinishRatio: the sweeps' local steps are then held, by the boundary's near contacts,
// short of what Newton steps of the whole map reach, where the surface's own distortion ends
// its sweeps below it (AneuRisk's sac at 1.006).
// A carry is finished as well where its mean |log area| is still above that of the coarse map it
// came from, whatever its energy: the energy hardly sees the area's last error, so neither its
// ratio to the minimum nor how much the last sweep lowered it says whether the map has arrived,
// and a finer mesh's map that reads worse than its coarse solve has not. A pulled carry (the
// look pulls) is finished by this test alone: its energy does not see the area's error at all,
// and Newton steps taken where its area has arrived only trade the look for area
// (docs/benchmarks.md, "The carry finished by Newton steps where it stops short").
// The finish goes on, kFinishNewtonSteps at a time up to kFinishMaxNewtonSteps, while its last
// steps removed at least kFinishGoOnShare of the energy's excess over the minimum and left it
// above kFinishRatio times that minimum: such a carry (held by near contacts where the cuts
// leave narrow strips between branches) is still far from where Newton's convergence ends it,
// while one whose steps remove little (the pulmonary tree's, a fifth) gains little from more.
constexpr double kFinishRatio = 1.001;
constexpr double kFinishProgress = 0.01;
constexpr double kStalledFinishRatio = 1.01;
constexpr int kFinishNewtonSteps = 3;
constexpr int kFinishMaxNewtonSteps = 9;
constexpr double kFinishGoOnShare = 1.0 / 3.0;

// A finest level whose relaxation stalls far above its minimum: the sweeps removed less than
// kStalledShare of the carried map's excess over the isometric minimum and left it above
// kStalledRatio times that minimum. Such a carry has squeezed faces that the sweeps cannot
// open, as their steps hold the boundary's near contacts (relax_area()); the polish at full
// resolution then spends its whole budget and can still end above the bound, while the second
// try (the whole boundary kept on every level) solves it at a fraction of that cost. Where that
// second try is to come, such a carry goes to it at once. The carries that the polish does bring
// within the bound end their sweeps far below kStalledRatio (docs/benchmarks.md, "A stalled
// carry goes to the second try at once").
constexpr double kStalledRatio = 10.0;
constexpr double kStalledShare = 0.5;

// The look pulls on a level's map: level l of a carry (0 = its finest mesh, l > 0 =
// levels[l - 1].mesh) and the map there.
using LevelPulls = std::function<std::vector<CentrePull>(std::size_t, const Eigen::MatrixX2d&)>;

// The coarse map \p uv (on levels.back()) carried up every level of \p levels to \p mesh into
// result.uv (notes into result.notes); on failure the reason, and result.uv untouched.
// \param second_try_follows a failure is followed by a second try: a finest level whose
// relaxation stalls (kStalledRatio) fails without the polish.
// \param pulls_at if set: a pulled map (FlattenOptions::look_pull from the start, or the look
// retry's kept on the coarse mesh). Each level relaxes with the pulls made on its carried map;
// the finest is finished by Newton steps with them where its mean |log area| is still above its
// coarse map's (the pulled map's energy does not see the area's error; see kFinishRatio), and
// polished with them where its energy is above the bound (without them the polish undoes the
// look; docs/overlaps.md, "The steps and the carry").
std::string carry_up(const Mesh& mesh, const std::vector<CoarseMesh>& levels,
                     const LayoutResult& placed, const FlattenOptions& options,
                     std::size_t boundary_levels, bool at_layout, Eigen::MatrixX2d uv,
                     FlattenResult& result, bool second_try_follows,
                     const LevelPulls& pulls_at = {})
{
    const MultilevelOptions& multilevel = options.multilevel;
    char line[200];
    // Carried up level by level (cascadic multigrid, Bornemann and Deuflhard 1996): at each
    // level the pins (when they held) put back exactly, flips untangled, then the error of the
    // level's own wavelength relaxed away, which the finer levels' local steps would remove
    // only slowly.
    const double lambda = relax_weight(options);
    // The map's area on the coarse mesh, which its carry should come down to (the finish below).
    const double coarse_area =
        detail::map_distortion(levels.back().mesh, uv).mean_abs_log_area_normalized;
    const bool keep_simple = options.overlaps != OverlapPolicy::Keep;
    Eigen::MatrixX2d below_uv;  // the map of levels[l + 1].mesh, which levels[l]'s came from
    for (std::size_t l = levels.size(); l-- > 0;)
    {
        const Mesh& above = l == 0 ? mesh : levels[l - 1].mesh;
        Eigen::MatrixX2d coarser_uv = std::move(uv);
        uv = prolongate(above, levels[l], coarser_uv, lambda, keep_simple);
        const Pins pins =
            at_layout ? renumbered(placed.inlet, index_at(levels, l, mesh.n_vertices())) : Pins{};
        for (const Pin& pin : pins)
            uv.row(pin.vertex.idx()) = pin.uv.transpose();
        // Where this level kept the whole boundary, untangling leaves it where the coarser map
        // put it, so that the boundary stays that map's simple polygon.
        Pins held = pins;
        if (l < boundary_levels)
        {
            const std::vector<int> pinned = pin_index(above, pins, "coarse-to-fine");
            for (VertexHandle v : above.vertices())
                if (above.is_boundary(v) && pinned[v.idx()] < 0)
                    held.push_back({v, uv.row(v.idx()).transpose()});
        }
        const UntangleSummary untangled = untangle(above, uv, held, options.untangle);
        if (untangled.flipped_before > 0)
            result.notes.push_back("coarse-to-fine: " + untangled.report);
        if (untangled.flipped_after > 0)
            return std::to_string(untangled.flipped_after) + " flipped triangles after untangling";
        if (keep_simple && !open_contacts(above, uv, pins))
            return "the carried map's boundary crosses itself";
        if (keep_simple)
            if (const std::size_t touching = open_near_contacts(above, uv, pins); touching > 0)
                result.notes.push_back("coarse-to-fine: " + std::to_string(touching) +
                                       " boundary vertices nearer another part than the "
                                       "clearance after the carry");
        const bool deeper = l + 1 < levels.size();
        // The area tolerance is the finished map's: a coarser level's area does not say it.
        MultilevelOptions level_options = multilevel;
        if (l > 0)
            level_options.area_tolerance = 0.0;
        // A pulled carry's finest level makes no coarse-grid corrections: their coarse step
        // moves the pulled outlets' centres across the look pulls' hinges, which it does not
        // see, so that their line search takes at most a sliver of it; its sweeps visit every
        // vertex instead (relax_area(); docs/benchmarks.md, "A pulled carry's finest level").
        else if (pulls_at)
            level_options.coarse_corrections = 0;
        const std::vector<CentrePull> level_pulls =
            pulls_at ? pulls_at(l, uv) : std::vector<CentrePull>{};
        const RelaxSummary relaxed =
            relax_area(above, uv, pins, lambda, level_options, &levels[l], &coarser_uv,
                       keep_simple, deeper ? &levels[l + 1] : nullptr,
                       deeper ? &below_uv : nullptr, pulls_at ? &level_pulls : nullptr);
        if (keep_simple && boundary_self_intersection(above, uv).first >= 0)
            return "the relaxed map's boundary crosses itself";
        if (l == 0)
        {
            const double minimum = relax_note("coarse-to-fine: ", mesh, relaxed, result);
            double energy = relaxed.energy_after;
            const bool pulled = static_cast<bool>(pulls_at);
            if (second_try_follows && energy > kStalledRatio * minimum &&
                energy - minimum > kStalledShare * (relaxed.energy_before - minimum))
            {
                std::snprintf(line, sizeof line,
                              "the carried map's relaxation stalled at %.3g times its minimum",
                              energy / minimum);
                return line;
            }
            // A carry whose area is still above its coarse map's has not arrived, whatever its
            // energy and its last sweep; its area is measured only where the rest of the rule
            // leaves the finish open.
            const auto area_short = [&] {
                return detail::map_distortion(above, uv).mean_abs_log_area_normalized > coarse_area;
            };
            if (!relaxed.area_within_tolerance && energy <= multilevel.max_energy_ratio * minimum &&
                ((!pulled && energy > kFinishRatio * minimum &&
                  (relaxed.last_decrease > kFinishProgress * (energy - minimum) ||
                   energy > kStalledFinishRatio * minimum)) ||
                 area_short()))
            {
                AreaPolishOptions polish = carried_polish(
                    options, lambda, pulled ? pulls_at(0, uv) : std::vector<CentrePull>{});
                polish.newton = true;  // whatever the polish's own minimizer
                polish.newton_max_iterations = kFinishNewtonSteps;
                polish.newton_chunk_iterations = kFinishNewtonSteps;
                AreaPolishSummary finished = area_polish(above, uv, pins, polish);
                const double before = energy;
                energy = relaxed_energy(above, uv, pins, lambda, multilevel);
                // Still converging fast and short of the ratio: go on (kFinishGoOnShare).
                for (double chunk_start = before;
                     energy > kFinishRatio * minimum &&
                     finished.iterations + kFinishNewtonSteps <= kFinishMaxNewtonSteps &&
                     chunk_start - energy >= kFinishGoOnShare * (chunk_start - minimum);)
                {
                    chunk_start = energy;
                    const AreaPolishSummary more = area_polish(above, uv, pins, polish);
                    if (more.iterations == 0)
                        break;
                    finished.iterations += more.iterations;
                    energy = relaxed_energy(above, uv, pins, lambda, multilevel);
                }
                std::snprintf(line, sizeof line,
                              "coarse-to-fine: finished with %d Newton steps: energy / minimum "
                              "%.5f -> %.5f",
                              finished.iterations, before / minimum, energy / minimum);
                result.notes.push_back(line);
                if (keep_simple && boundary_self_intersection(above, uv).first >= 0)
                    return "the finished map's boundary crosses itself";
            }
            if (!(energy <= multilevel.max_energy_ratio * minimum))
            {
                // Local steps and coarse-grid corrections can stall on what is left of such a
                // carry, Newton steps of the whole map do not, at a fraction of the cost of
                // solving the map again (docs/benchmarks.md "Coarse-to-fine").
                const AreaPolishSummary polished = area_polish(
                    above, uv, pins,
                    carried_polish(options, lambda,
                                   pulled ? pulls_at(0, uv) : std::vector<CentrePull>{}));
                energy = relaxed_energy(above, uv, pins, lambda, multilevel);
                std::snprintf(line, sizeof line,
                              "coarse-to-fine: above the bound, polished (%d steps): "
                              "energy / minimum %.5f",
                              polished.iterations, energy / minimum);
                result.notes.push_back(line);
                if (keep_simple && boundary_self_intersection(above, uv).first >= 0)
                    return "the polished map's boundary crosses itself";
            }
            if (!(energy <= multilevel.max_energy_ratio * minimum))
            {
                std::snprintf(line, sizeof line,
                              "the carried map's energy is %.3g times its minimum (more than %g)",
                              energy / minimum, multilevel.max_energy_ratio);
                return line;
            }
        }
        else
            below_uv = std::move(coarser_uv);
    }
    result.uv = std::move(uv);
    return "";
}

// The area polish (FlattenOptions::area_polish, boundary kept simple) of a carried map at full
// resolution with the look retry's pulls (mend_look()), at most \p newton_steps Newton steps if
// > 0; one note. The hinges ask for the look's whole margin: made from the broken map, they
// would pull an outlet below the inlet's line only onto it (HingeMargin).
AreaPolishSummary polish_carried(const Mesh& mesh, const LayoutInput& input,
                                 const FlattenOptions& options, Eigen::MatrixX2d& uv,
                                 FlattenResult& result, int newton_steps = 0)
{
    AreaPolishOptions polish = options.area_polish;
    polish.keep_boundary_simple = true;
    if (newton_steps > 0)
        polish.newton_max_iterations = std::min(polish.newton_max_iterations, newton_steps);
    polish.centre_pulls = look_pulls(input.segments, uv, options.look_retry.pull,
                                     options.look_pull.form, options.look_pull.margin_deg,
                                     options.look_pull.hold, HingeMargin::Whole);
    // The mend moves each broken loop as a whole (the proxy), as it was measured.
    polish.pull_steps = PullSteps::DiagonalProxy;
    AreaPolishSummary summary = area_polish(mesh, uv, {}, polish);
    result.notes.push_back("coarse-to-fine: " + summary.report);
    return summary;
}

// Whether the look retry's rule calls the look of \p uv broken.
bool look_broken_in(const Mesh& mesh, const LayoutInput& input, const LayoutResult& placed,
                    const FlattenOptions& options, const Eigen::MatrixX2d& uv)
{
    return options.look_retry.look_broken(map_look(mesh, uv, input.segments, placed));
}

// The carry and the relaxation lower the area without the pulls, and can break the look the
// retry made on the coarse mesh (docs/overlaps.md, "Rounding"): a kept pulled map whose look is
// broken is polished with the pulls (whose hinges cost nothing where the look holds), a chunk
// of Newton steps at a time until the look is whole again (or the polish converges, or has made
// the area polish's steps in all). Whether it was broken (then a note, \p where the map is).
bool mend_look(const Mesh& mesh, const LayoutInput& input, const LayoutResult& placed,
               const FlattenOptions& options, const std::string& where, Eigen::MatrixX2d& uv,
               FlattenResult& result)
{
    if (!look_broken_in(mesh, input, placed, options, uv))
        return false;
    result.notes.push_back("coarse-to-fine: look retry " + where +
                           ": the carry broke the pulled map's look; polished with the pulls "
                           "until it is whole");
    const AreaPolishOptions& polish = options.area_polish;
    if (!polish.newton)  // L-BFGS: no chunks of Newton steps to stop between
        polish_carried(mesh, input, options, uv, result);
    else
    {
        const int chunk = std::max(polish.newton_chunk_iterations, 1);
        for (int made = 0; made < polish.newton_max_iterations; made += chunk)
            if (polish_carried(mesh, input, options, uv, result, chunk).iterations < chunk ||
                !look_broken_in(mesh, input, placed, options, uv))
                break;
    }
    return true;
}

// The layout problem on a decimation of its mesh, \p level: every per-vertex input renumbered
// or dropped (`index[v]`: v's index on \p level, or -1).
void input_on(const LayoutInput& input, const LayoutResult& placed, const Mesh& level,
              const std::vector<int>& index, LayoutInput& level_input, LayoutResult& level_placed)
{
    level_input = input;
    level_input.mesh = &level;
    level_input.origin.resize(level.n_vertices());
    for (std::size_t v = 0; v < index.size(); ++v)
        if (index[v] >= 0)
            level_input.origin[index[v]] = input.origin[v];
    for (BoundarySegment& segment : level_input.segments)
    {
        BoundarySegment kept{segment.loop, {}, {}};
        for (std::size_t i = 0; i < segment.vertices.size(); ++i)
            if (const int c = index[segment.vertices[i].idx()]; c >= 0)
            {
                kept.vertices.push_back(VertexHandle(c));
                kept.arc_length.push_back(segment.arc_length[i]);
            }
        segment = std::move(kept);
    }
    level_placed = placed;
    level_placed.inlet = renumbered(placed.inlet, index);
    level_placed.outlets = renumbered(placed.outlets, index);
}

// The fewest outlets for which the coarse map's restart starts from a coarser solve
// (NestedStart). From the layout circle, the more outlets, the more of SLIM's iterations go to
// unrolling the branches; on the carotid phantoms and 4-outlet tree phantoms the restart is a
// few iterations from its end, and the coarser solve only adds its own time
// (docs/benchmarks.md, "The coarse map's start solved coarser"; MultilevelOptions::coarser_start).
constexpr int kNestedStartOutlets = 6;

// The fewest coarse-mesh vertices for which NestedStart is made: a quarter of fewer would be
// under 100 vertices. The default coarse mesh has 4000 (MultilevelOptions::coarse_vertices);
// smaller ones, asked for with a small coarse_vertices, restart from the circle.
constexpr std::size_t kNestedStartMinVertices = 400;

// The coarser solve's stopping rule once its scaffold is in use
// (InjectiveOptions::scaffold_tolerance): the coarse mesh's own SLIM and area polish follow it,
// so its slow tail is left to them.
constexpr double kNestedScaffoldTolerance = 1e-3;

// A restart's start for the coarse mesh (detail::RestartStart): the same restart from the layout
// circle solved first on a decimation of the coarse mesh to a quarter of its vertices, one level
// further down the hierarchy, then carried up to it as the coarse map is carried up
// (prolongate() and relax_area(), multilevel.h). SLIM's iterations from the circle, which unroll
// the branches with a scaffold triangulated anew at almost every step, are made on a mesh a
// quarter as large, and those on the coarse mesh start near their end (a cascadic start,
// Bornemann and Deuflhard 1996). The look retry's pulled map is not started so: carried up from a
// coarser solve, it kept less of the look (docs/benchmarks.md, "The coarse map's start solved
// coarser"). An empty map where the coarser solve stalls above twice its isometric minimum, or
// the carried start has a flip or a crossing.
class NestedStart
{
public:
    // \p keep: coarse vertices the decimation keeps (the boundary segments' ends and spacing).
    NestedStart(const Mesh& coarse, const LayoutInput& input, const LayoutResult& placed,
                const std::vector<VertexHandle>& keep, bool no_new_chords, double lambda)
        : coarse_(coarse),
          level_(coarsen(coarse, static_cast<int>(coarse.n_vertices() / 4), keep, no_new_chords)),
          area_(face_areas(level_.mesh).sum()),
          lambda_(lambda)
    {
        input_on(input, placed, level_.mesh, level_.coarse_of, level_input_, level_placed_);
    }
    NestedStart(const NestedStart&) = delete;  // level_input_ points at level_.mesh
    NestedStart& operator=(const NestedStart&) = delete;

    Eigen::MatrixX2d operator()(const FlattenOptions& options,
                                std::vector<std::string>& notes) const
    {
        FlattenOptions coarser = options;
        coarser.polish_area = false;
        coarser.injective.scaffold_tolerance = kNestedScaffoldTolerance;
        FlattenResult solved;
        refine_map(level_.mesh, {}, coarser, "",
                   "solved on " + std::to_string(level_.mesh.n_vertices()) + " vertices", solved,
                   &level_input_, &level_placed_);
        notes.insert(notes.end(), solved.notes.begin(), solved.notes.end());
        // SLIM's energy is 4 x area at an isometry: a solve stalled far above it (a sliver held
        // its steps) is no nearer the coarse map's end than the circle.
        if (!(solved.injective.final_energy <= 2.0 * 4.0 * area_))
        {
            char line[160];
            std::snprintf(line, sizeof line,
                          "stalled at %.3g times its isometric minimum: not used",
                          solved.injective.final_energy / (4.0 * area_));
            notes.push_back(line);
            return {};
        }
        const bool keep_simple = options.overlaps != OverlapPolicy::Keep;
        Eigen::MatrixX2d uv = prolongate(coarse_, level_, solved.uv, lambda_, keep_simple);
        // The carry leaves slivers where the vertices it puts back are squeezed: relaxed before
        // SLIM, whose energy they would hold up.
        MultilevelOptions relax = options.multilevel;
        relax.area_tolerance = 0.0;
        relax_area(coarse_, uv, {}, lambda_, relax, &level_, &solved.uv, keep_simple);
        if (map_distortion(coarse_, uv).flipped_triangles > 0)
        {
            notes.push_back("carried up with a flipped face: not used");
            return {};
        }
        if (keep_simple && boundary_self_intersection(coarse_, uv).first >= 0)
        {
            notes.push_back("carried up with its boundary crossing itself: not used");
            return {};
        }
        return uv;
    }

private:
    const Mesh& coarse_;
    CoarseMesh level_;
    LayoutInput level_input_;
    LayoutResult level_placed_;
    double area_;  // of level_.mesh's surface
    double lambda_;
};

// The coarse-to-fine map (multilevel.h) into result.uv; on failure (a flip left after
// untangling, a crossing boundary, an energy far above its minimum) the reason, and result.uv
// untouched. \p second_try_follows: a failure is followed by a second try
// (solve_multilevel()), so a carry whose relaxation stalls fails at once (kStalledRatio).
std::string solve_coarse_to_fine(const Mesh& mesh, const LayoutInput& input,
                                 const LayoutResult& placed, const FlattenOptions& options,
                                 std::size_t boundary_levels, bool second_try_follows,
                                 FlattenResult& result, bool& at_layout)
{
    // The hierarchy, each segment keeping its ends and evenly spaced vertices between them,
    // so that each loop keeps its run of the boundary and its shape: an outlet loop decimated
    // to a spike between its ends leaves its fine vertices no room on the coarse edges.
    std::vector<VertexHandle> keep;
    constexpr int per_segment = 8;
    for (const BoundarySegment& segment : input.segments)
    {
        const std::size_t n = segment.vertices.size();
        for (int i = 0; i < per_segment && n > 0; ++i)
            keep.push_back(segment.vertices[(n - 1) * i / (per_segment - 1)]);
    }
    const MultilevelOptions& multilevel = options.multilevel;
    std::vector<CoarseMesh> levels =
        coarsen_levels(mesh, multilevel.coarse_vertices, keep, boundary_levels,
                       outlet_count(input) >= kChordFreeOutlets);
    const Mesh& coarsest = levels.back().mesh;
    const std::size_t n = mesh.n_vertices();

    // The problem on level `depth` of the hierarchy.
    const auto at_level = [&](std::size_t depth, const Mesh& level, LayoutInput& level_input,
                              LayoutResult& level_placed) {
        input_on(input, placed, level, index_at(levels, depth, n), level_input, level_placed);
    };
    const std::vector<int> coarse_index = index_at(levels, levels.size(), n);
    LayoutInput coarse_input;
    LayoutResult coarse_placed;
    input_on(input, placed, coarsest, coarse_index, coarse_input, coarse_placed);

    // On many-outlet trees the coarse map's restart starts from a coarser solve (NestedStart);
    // not a map pulled from the start (FlattenOptions::look_pull), for the look retry's reason.
    // Its decimation is made when the restart first asks for it, on the thread of the default
    // map: the look retry's pulled map, which does not use it, starts without waiting for it.
    std::optional<NestedStart> nested;
    RestartStart start;
    if (multilevel.coarser_start && outlet_count(input) >= kNestedStartOutlets &&
        options.look_pull.weight == 0.0 && coarsest.n_vertices() >= kNestedStartMinVertices)
    {
        start = [&](const FlattenOptions& given, std::vector<std::string>& notes) {
            if (!nested)
            {
                std::vector<VertexHandle> coarse_keep;
                for (VertexHandle v : keep)
                    if (coarse_index[v.idx()] >= 0)
                        coarse_keep.push_back(VertexHandle(coarse_index[v.idx()]));
                nested.emplace(coarsest, coarse_input, coarse_placed, coarse_keep,
                               outlet_count(input) >= kChordFreeOutlets, relax_weight(options));
            }
            return (*nested)(given, notes);
        };
    }
    // The look retry runs on the coarse mesh, its area bound held there (retry_look()); a kept
    // pulled map is carried up with its pulls, as one pulled from the start, which keeps its
    // look (docs/overlaps.md, "The steps and the carry").
    FlattenResult solved;
    at_layout = solve_single_level(coarsest, coarse_input, coarse_placed, options, solved,
                                   start ? &start : nullptr);
    char line[200];
    std::snprintf(line, sizeof line,
                  "coarse-to-fine: the map solved on %zu of %zu vertices (%zu levels)",
                  coarsest.n_vertices(), mesh.n_vertices(), levels.size());
    result.notes.push_back(line);
    for (const std::string& note : solved.notes)
        result.notes.push_back("coarse: " + note);
    result.arap = solved.arap;
    result.untangle = solved.untangle;
    result.injective = solved.injective;
    result.look_retry = solved.look_retry;
    // A pulled map (FlattenOptions::look_pull from the start, or the look retry's kept) is
    // carried with its pulls, made on each level's carried map with hinges no tighter than it
    // has.
    const double pull_weight = options.look_pull.weight > 0.0 ? options.look_pull.weight
                               : result.look_retry.kept       ? options.look_retry.pull
                                                              : 0.0;
    LevelPulls pulls_at;
    std::vector<std::vector<BoundarySegment>> level_segments(levels.size() + 1);
    if (pull_weight > 0.0)
    {
        level_segments[0] = input.segments;
        for (std::size_t d = 1; d <= levels.size(); ++d)
        {
            LayoutInput level_input;
            LayoutResult level_placed;
            at_level(d, levels[d - 1].mesh, level_input, level_placed);
            level_segments[d] = std::move(level_input.segments);
        }
        pulls_at = [&](std::size_t l, const Eigen::MatrixX2d& uv) {
            const LookPullOptions& pull = options.look_pull;
            return look_pulls(level_segments[l], uv, pull_weight, pull.form, pull.margin_deg,
                              pull.hold, HingeMargin::AtMostTheMap);
        };
    }
    const std::string failed = carry_up(mesh, levels, placed, options, boundary_levels, at_layout,
                                        std::move(solved.uv), result, second_try_follows, pulls_at);
    if (!failed.empty())
        return failed;
    // The carry can still break the look on a few outlets: mended at full resolution.
    if (result.look_retry.kept)
        mend_look(mesh, input, placed, options, "at full resolution", result.uv, result);
    return "";
}

// The map and the solvers' summaries of \p solved into \p result (not its notes).
void take_map(FlattenResult& result, FlattenResult&& solved)
{
    result.uv = std::move(solved.uv);
    result.arap = solved.arap;
    result.untangle = solved.untangle;
    result.injective = solved.injective;
    result.look_retry = solved.look_retry;
}

}  // namespace

bool refine_by_policy(const Mesh& mesh, const LayoutInput* input, const LayoutResult* placed,
                      const MapRefiner& refiner, const Pins& pins, bool at_layout,
                      FlattenResult& result)
{
    const RefineInput given{&mesh, input, placed, pins};
    refiner.refine(given, result.uv, result.notes);
    const std::string name = "the refiner '" + refiner.name() + "'";
    if (result.uv.rows() != static_cast<Eigen::Index>(mesh.n_vertices()))
        throw InvalidInputError(name + " returned " + std::to_string(result.uv.rows()) +
                                " map rows for " + std::to_string(mesh.n_vertices()) +
                                " vertices; it must keep one row per cut-mesh vertex");
    if (!result.uv.allFinite())
        throw InvalidInputError(name + " returned a map with a non-finite coordinate");
    for (const Pin& pin : pins)
        at_layout = at_layout && result.uv.row(pin.vertex.idx()) == pin.uv.transpose();
    return at_layout;
}

namespace {

// The coarse-to-fine map (solve_map()'s path for large cut meshes).
bool solve_multilevel(const Mesh& mesh, const LayoutInput& input, const LayoutResult& placed,
                      const FlattenOptions& options, FlattenResult& result)
{
    const MultilevelOptions& multilevel = options.multilevel;
    // First with the whole boundary kept on the finest level only: the boundary is decimated
    // below it, so the coarse map is solved on few vertices, and the finest carry, whose
    // vertices are the most and the closest together, inserts no boundary vertex. Where a
    // coarser carry leaves the boundary crossing itself (branches laid side by side, the tip of
    // a narrow slit between two boundary parts), again with the whole boundary kept on every
    // level, which no carry can make cross but solves the coarse map on more vertices.
    // A boundary of more vertices than coarse_vertices, kept on every level, leaves the
    // coarse mesh mostly boundary, its faces needles on which the coarse map is no better
    // (docs/benchmarks.md, "Coarse-to-fine"): then the second try is not made.
    constexpr std::size_t kEveryLevel = std::numeric_limits<std::size_t>::max();
    std::size_t boundary = 0;
    for (VertexHandle v : mesh.vertices())
        boundary += mesh.is_boundary(v) ? 1 : 0;
    const bool every_level = boundary <= static_cast<std::size_t>(multilevel.coarse_vertices);
    for (const std::size_t boundary_levels : {std::size_t{1}, kEveryLevel})
    {
        if (boundary_levels == kEveryLevel && !every_level)
            break;
        bool at_layout = false;
        std::string failed;
        FlattenResult attempt;
        try
        {
            failed = solve_coarse_to_fine(mesh, input, placed, options, boundary_levels,
                                          boundary_levels == 1 && every_level, attempt,
                                          at_layout);
        }
        catch (const InvalidInputError& error)  // relax_area() refused a degenerate carried map
        {
            failed = error.what();
        }
        result.notes.insert(result.notes.end(), attempt.notes.begin(), attempt.notes.end());
        if (failed.empty())
        {
            take_map(result, std::move(attempt));
            return at_layout;
        }
        result.notes.push_back(
            "coarse-to-fine: " + failed +
            (boundary_levels == 1 && every_level
                 ? "; tried again with the whole boundary kept on every level"
                 : "; the map solved again at full resolution"));
    }
    FlattenResult full;
    const bool at_layout = solve_single_level(mesh, input, placed, options, full);
    result.notes.insert(result.notes.end(), full.notes.begin(), full.notes.end());
    take_map(result, std::move(full));
    return at_layout;
}

// The fewest cut-mesh vertices for which stage F renumbers a mesh whose vertex order scatters
// neighbours through memory, and how much farther apart, on average over the edges, the input
// order puts an edge's two ends than the space-filling curve does. Glenn split4 (142k vertices:
// the surface split 1 -> 4, each new vertex after all the old ones) puts them 78 times as far
// apart, and its relaxation sweeps and decimation, which read every vertex's neighbours, take
// about a fifth less in the curve's order; the tree phantoms (30k, 10 times as far) and AneuRisk
// (14k, 16 times) gain nothing beyond the noise, their arrays fitting the cache either way; the
// carotid phantoms and pulmonary Glenn are within twice the curve's gap already
// (docs/benchmarks.md, "Coarse-to-fine").
constexpr std::size_t kRenumberVertices = 50000;
constexpr double kScatteredGap = 4.0;

// \p pins with each vertex v as `new_of[v]`.
Pins renumbered_pins(const Pins& pins, const std::vector<int>& new_of)
{
    Pins out = pins;
    for (Pin& pin : out)
        pin.vertex = VertexHandle(new_of[static_cast<std::size_t>(pin.vertex.idx())]);
    return out;
}

}  // namespace

bool solve_map(const Mesh& mesh, const LayoutInput& input, const LayoutResult& placed,
               const FlattenOptions& options, FlattenResult& result)
{
    const MultilevelOptions& multilevel = options.multilevel;
    if (options.refiner || options.refinement != Refinement::Injective ||
        multilevel.coarse_vertices == 0 ||
        mesh.n_vertices() <= 2 * static_cast<std::size_t>(multilevel.coarse_vertices))
        return solve_single_level(mesh, input, placed, options, result);
    if (mesh.n_vertices() < kRenumberVertices)
        return solve_multilevel(mesh, input, placed, options, result);
    const std::vector<int> old_of = space_filling_order(mesh);
    std::vector<int> new_of(old_of.size());
    for (std::size_t k = 0; k < old_of.size(); ++k)
        new_of[static_cast<std::size_t>(old_of[k])] = static_cast<int>(k);
    if (!(mean_edge_index_gap(mesh) > kScatteredGap * mean_edge_index_gap(mesh, new_of)))
        return solve_multilevel(mesh, input, placed, options, result);
    // The same problem on the renumbered mesh, the map read back in the mesh's own order.
    const Mesh renumbered = renumbered_mesh(mesh, old_of);
    LayoutInput renumbered_input = input;
    renumbered_input.mesh = &renumbered;
    if (input.origin.size() == old_of.size())  // per cut-mesh vertex (empty: none given)
        for (std::size_t k = 0; k < old_of.size(); ++k)
            renumbered_input.origin[k] = input.origin[static_cast<std::size_t>(old_of[k])];
    for (BoundarySegment& segment : renumbered_input.segments)
        for (VertexHandle& v : segment.vertices)
            v = VertexHandle(new_of[static_cast<std::size_t>(v.idx())]);
    LayoutResult renumbered_placed = placed;
    renumbered_placed.inlet = renumbered_pins(placed.inlet, new_of);
    renumbered_placed.outlets = renumbered_pins(placed.outlets, new_of);
    result.notes.push_back("the cut mesh renumbered along a space-filling curve for stage F");
    const bool at_layout =
        solve_multilevel(renumbered, renumbered_input, renumbered_placed, options, result);
    Eigen::MatrixX2d uv(result.uv.rows(), 2);
    for (std::size_t v = 0; v < new_of.size(); ++v)
        uv.row(static_cast<Eigen::Index>(v)) = result.uv.row(new_of[v]);
    result.uv = std::move(uv);
    return at_layout;
}

}  // namespace vessel::detail
