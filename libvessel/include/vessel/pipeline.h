#pragma once

#include "vessel/map/arap.h"
#include "vessel/map/area_polish.h"
#include "vessel/map/multilevel.h"
#include "vessel/map/refiner.h"
#include "vessel/cut/boundary.h"
#include "vessel/direction/curvature.h"
#include "vessel/cut/cut_cost.h"
#include "vessel/cut/cut_plan.h"
#include "vessel/direction/direction.h"
#include "vessel/direction/geodesic.h"
#include "vessel/map/injective.h"
#include "vessel/layout/layout.h"
#include "vessel/layout/layout_circle.h"
#include "vessel/map/look_retry.h"
#include "vessel/map/map_look.h"
#include "vessel/quality/metrics.h"
#include "vessel/cut/relief_cut.h"
#include "vessel/map/untangle.h"

#include <functional>
#include <memory>
#include <string>

namespace vessel {

//! How the map is started before ARAP (step 7).
enum class Initialization
{
    LayoutLscm,         //!< the paper: LSCM with inlet and outlets pinned at the layout
    SpectralConformal,  //!< free-boundary spectral conformal map (no layout), then ARAP
    Tutte,              //!< Tutte embedding on a circle: always flip-free, far from isometric
};

//! How the map is refined (step 7).
enum class Refinement
{
    None,       //!< keep the initial map
    Arap,       //!< the paper: ARAP with the inlet pinned (may leave flipped triangles)
    //! ARAP with the inlet pinned, then the flipped triangles untangled locally (untangle.h),
    //! then the symmetric Dirichlet energy lowered without flipping any triangle (SLIM,
    //! injective.h), which evens out area. Flip-free; keeps the layout's arrangement.
    Injective,
};
//! What Refinement::Injective does when the map at the layout overlaps itself (the paper's
//! layout does not prevent it; its boundary crosses on most real trees).
enum class OverlapPolicy
{
    Keep,     //!< keep the layout's map, overlaps and all
    //! restart from the Tutte embedding (one-to-one) and refine with SLIM, which cannot flip
    //! a triangle but can let the boundary cross (overlaps shrink, e.g. 42% -> 3% of the area
    //! on the pulmonary tree, but are not excluded)
    Restart,
    //! The default. As Restart, and the boundary is checked after every SLIM step; if the end
    //! map's boundary crosses itself, SLIM goes back to the last iterate whose boundary was
    //! simple and goes on with a scaffold that keeps the boundary's parts apart
    //! (InjectiveOptions::scaffold_on_contact). The map is one-to-one: no flips, no overlaps.
    //! The scaffold's cost (several times Restart's F) is paid only when the fast path's map
    //! would overlap; a map at the layout that does not cross itself is kept (and watched).
    Prevent,
};

//! What flatten() is doing, reported to FlattenOptions::on_progress.
struct Progress
{
    //! The stage under its Table 1 name: "Z", "GC", "VC", "AC", "L" or "F".
    std::string stage;
    //! Within stage F, the solver iterating: "arap", "slim" (SLIM without a scaffold),
    //! "scaffold" (SLIM with its scaffold), "polish" (the area polish) or "relax" (a level's
    //! relaxation sweeps of the coarse-to-fine map, multilevel.h); empty for a stage's start or end.
    std::string phase;
    int iteration = 0;       //!< the phase's iterations so far (0 for a stage's start or end)
    int max_iterations = 0;  //!< the phase's iteration limit (0 for a stage's start or end)
    //! A stage's start (no phase): a display can name the stage running before its first
    //! iteration report or its end, e.g. stage Z, which reports no iterations.
    bool stage_begins = false;
    bool stage_done = false;  //!< a stage's end (neither: an iteration report within stage F)
    double seconds = 0.0;     //!< at a stage's end, its seconds (Z: since flatten() began); else 0
};

//! Options of flatten(). A default-constructed FlattenOptions is the library's default method
//! (one-to-one map: no flipped triangle, no overlap; relief cuts where the area distortion is
//! high); FlattenOptions::paper() is the published method, for reproduction.
struct FlattenOptions
{
    //! \brief The method of Eulzer et al. \cite eulzer_2021_automatic, for reproducing its
    //! figures: stage F is LSCM with the inlet and outlets pinned at the layout, then ARAP with
    //! the inlet pinned (Refinement::Arap), with no untangling, no SLIM, no area polish, overlaps
    //! kept (OverlapPolicy::Keep), and only the vessel cuts (`relief.max_cuts = 0`). Stages Z to
    //! L are the defaults'. The map may have flipped triangles and overlaps, as the paper's may.
    //! CLI `vessel-flatten --preset paper`; `vessel-bench-table --method paper`.
    static FlattenOptions paper();

    CurvatureOptions curvature;    //!< step 3: quadric-fit scale (5 x mean edge) etc.
    HeatGeodesicsOptions geodesic;  //!< step 3: heat-method time step
    //! step 3: where the curvature direction is trusted; elsewhere z leans to the harmonic
    //! longitudinal descent (`direction.confident_anisotropy = 0`: the paper's pure field)
    DirectionOptions direction;
    //! step 4: the travel cost (E_c by default; E_g, E_cg, or a researcher's `cost.custom`)
    CostOptions cost;
    CutPlanOptions cuts;  //!< endpoint policy (imaginary node / viewpoint), winding control
    //! Relief cuts (relief_cut.h): when the map's mean |log area ratio| stays above the target,
    //! a slit from the most compressed point to the seam, and the map is made again. Default:
    //! at most 2, target 0.15; `relief.max_cuts = 0` keeps the paper's cuts only. Not tried
    //! with Refinement::None.
    ReliefCutOptions relief;
    double alpha_deg = 45.0;  //!< branch angle of the fan layout
    //! Layout policy; null = BranchFanLayout(alpha_deg).
    std::shared_ptr<const Layout> layout;
    Initialization initialization = Initialization::LayoutLscm;
    //! Step 7 refinement. With Injective, when untangling fails or the map at the layout
    //! overlaps itself (see `overlaps`), the map restarts from a Tutte embedding (by default
    //! the layout circle, restart_on_layout_circle: inlet at the bottom, outlets near their
    //! layout bearings; the pins are dropped, so SLIM may still move them). Noted in
    //! FlattenResult::notes. When the LSCM map at the layout already crosses itself, the restart
    //! comes before ARAP and untangling, which are then skipped (FlattenResult::arap and
    //! ::untangle stay empty).
    Refinement refinement = Refinement::Injective;
    //! A researcher's own refinement (refiner.h); when set it replaces `refinement` (and with it
    //! `overlaps`, ARAP, untangling, SLIM, the area polish, the look retry and coarse-to-fine):
    //! it gets the initial map and the inlet pins and returns the map. Like cost.custom for
    //! the travel cost.
    std::shared_ptr<const MapRefiner> refiner;
    OverlapPolicy overlaps = OverlapPolicy::Prevent;
    ArapOptions arap;            //!< ARAP of Refinement::Arap and Injective (0 iterations: skipped)
    UntangleOptions untangle;    //!< flip removal of Refinement::Injective
    InjectiveOptions injective;  //!< SLIM of Refinement::Injective (0 iterations: skipped)
    //! With Refinement::Injective, when the map restarts: start from the layout circle
    //! (layout_circle.h: Tutte's circle walked so that the inlet is at the bottom and each outlet
    //! near its layout bearing) instead of Tutte's constant-speed circle. CLI `--restart-circle
    //! layout|tutte`.
    bool restart_on_layout_circle = true;
    LayoutCircleOptions layout_circle;  //!< the start of restart_on_layout_circle
    //! With Refinement::Injective, when the map restarts on a tree's layout: SLIM and the area
    //! polish also keep the start's look with soft terms on the loops' centres (centre_pull.h,
    //! LookPullOptions). `look_pull.weight` 0 = off (default: no fixed weight keeps every
    //! tree's area distortion within 1.5x of the map without the pull, docs/overlaps.md "The
    //! look hinges"); the default gets it adaptively instead (look_retry).
    LookPullOptions look_pull;
    //! With `look_pull.weight` 0: after a restarted map whose look is broken (an outlet below the inlet,
    //! or many walk inversions), redo it with the hinge pull and keep that map if it is
    //! one-to-one and within the area bound (look_retry.h; on by default, LookRetry::Auto).
    //! CLI `--look-retry auto|off|force`.
    LookRetryOptions look_retry;
    //! With Refinement::Injective: after SLIM (when it runs), lower the area distortion with area_polish()
    //! (area_polish.h), trading conformal distortion for it; one-to-one maps stay one-to-one
    //! unless overlaps is OverlapPolicy::Keep. On by default (issue 7: the area distortion of
    //! the one-to-one map within 1.5x of the unconstrained map's with the same options; the
    //! maps keep their outline, mean conformal distortion goes up, docs/overlaps.md "Area polish
    //! by default"). CLI `--area-polish LAMBDA`, `--no-area-polish`.
    bool polish_area = true;
    AreaPolishOptions area_polish;  //!< the polish of polish_area
    //! With Refinement::Injective and `multilevel.coarse_vertices` > 0: cut meshes of more than
    //! twice that many vertices are mapped coarse-to-fine (multilevel.h): the whole F above
    //! (initial map, SLIM, polish, look retry) on a decimated copy, then carried to every
    //! vertex and relaxed there; 0 = every map at full resolution. CLI `--coarse-vertices N`.
    MultilevelOptions multilevel;
    //! Called after every stage with its Table 1 name and seconds (e.g. for progress lines).
    std::function<void(const std::string& stage, double seconds)> on_stage;
    //! Called at the start and end of every stage and, within stage F, after the solvers' outer
    //! iterations (ARAP sweeps, SLIM iterations, area polish steps, relaxation sweeps), at most
    //! once per `progress_interval_s` for the iterations, so that a display shows a long run
    //! going on without slowing it. Called from one thread at a time: the thread that called
    //! flatten(), or the second thread on which stage F makes the look retry's full-resolution
    //! reference after coarse-to-fine (multilevel.h) while the first waits or relaxes. Null (the
    //! default) = no calls. The vessel-flatten CLI draws it as one line on a terminal.
    std::function<void(const Progress&)> on_progress;
    //! The least time, in seconds, between two of on_progress's iteration reports (stages'
    //! starts and ends are always reported); 0 = every iteration.
    double progress_interval_s = 0.1;
    //! \throw InvalidInputError naming the bad field.
    void validate() const;
};

//! Per-stage wall-clock seconds under the names of the paper's Table 1.
struct StageTimings
{
    double Z = 0;   //!< curvature, geodesic distance and alignment
    double GC = 0;  //!< graph conversion (travel costs)
    double VC = 0;  //!< vessel cut paths (Dijkstra)
    double AC = 0;  //!< applying the cuts (seam split)
    double L = 0;   //!< layout
    double F = 0;   //!< flattening (LSCM + ARAP)
    double total() const { return Z + GC + VC + AC + L + F; }
};

struct FlattenResult
{
    //! The cut (disk) mesh. Vertex properties: `prop::origin` (pre-cut index), `prop::geodesic`,
    //! `prop::direction`, `prop::kmax`, `prop::uv`, and whatever the input mesh carried.
    Mesh mesh;
    Eigen::MatrixX2d uv;              //!< |V_cut| x 2, row `v.idx()` of `mesh`
    std::vector<BoundaryLoop> loops;  //!< pre-cut loops; handles index `mesh` too (cutting
                                      //!< only appends vertices)
    CutPlan plan;                     //!< the cuts, handles as for `loops`
    //! The viewpoint the cuts were planned behind the vessels from (CostOptions::viewpoint, or
    //! face_on_viewpoint() with CostOptions::face_on); none without one.
    std::optional<Eigen::Vector3d> viewpoint;
    int seam_edges = 0;
    int duplicated_vertices = 0;
    ArapSummary arap;                 //!< the ARAP run (Refinement::Arap or Injective)
    InjectiveSummary injective;       //!< the SLIM run (Refinement::Injective)
    UntangleSummary untangle;         //!< the flip removal (Refinement::Injective)
    FlatQuality quality;
    //! How the map keeps the layout's look (map_look.h): inlet at the bottom, outlets in the
    //! layout's fan order and directions. Empty (no outlets) for a surface flattened without cuts.
    MapLook look;
    LookRetrySummary look_retry;  //!< what FlattenOptions::look_retry did
    StageTimings timings;
    std::vector<std::string> notes;  //!< fallbacks taken, one line each
};

//! \brief Cut \p mesh open along natural vessel cuts and flatten it into one patch (steps 3-7).
//! A surface with one boundary loop (e.g. a vessel with its outlets capped) is a disk already:
//! it is flattened without cuts (the loop is the inlet; FlattenResult::notes says so; no relief
//! cuts), from the Tutte embedding scaled to its area, refined holding one loop vertex.
//! \param mesh A valid vessel tree surface (see validation.h), outward oriented; taken by value
//! because it is cut in place.
//! \throw InvalidInputError, TopologyError, SolverError from the stages.
FlattenResult flatten(Mesh mesh, const FlattenOptions& options = {});

//! \brief Stage Z's harmonic longitudinal coordinate (`prop::longitudinal`, see
//! harmonic_longitudinal()) of the surface flatten() cut, for measuring its cuts there (e.g.
//! with a WindingMeter): the first \p uncut_vertices vertices of the cut mesh are the uncut
//! mesh's own.
//! \return \p uncut_vertices values, `v.idx()` of the uncut mesh.
//! \throw InvalidInputError if \p result's mesh has no such property (it did not come from
//! flatten() of a tree with cuts) or fewer than \p uncut_vertices vertices.
Eigen::VectorXd uncut_longitudinal(const FlattenResult& result, std::size_t uncut_vertices);

}  // namespace vessel
