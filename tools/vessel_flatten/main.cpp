// vessel-flatten: cut a vessel tree surface open along natural vessel cuts and flatten it.
#include "../vessel_view/command.h"
#include "batch.h"
#include "field_input.h"
#include "images.h"
#include "viewer_fields.h"
#include "vessel/core/errors.h"
#include "vessel/fields/field_series.h"
#include "vessel/io/flat_io.h"
#include "vessel/io/flat_vtk.h"
#include "vessel/io/io.h"
#include "vessel/pipeline.h"
#include "vessel/cut/split.h"
#include "vessel/check/validation.h"
#include "vessel/render/viewer.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start)
{
    return std::chrono::duration<double>(Clock::now() - start).count();
}

}  // namespace

int main(int argc, char** argv)
{
    CLI::App app{"Cut a vessel tree surface open along natural vessel cuts and flatten it into "
                 "one 2D patch.\nOUT.obj: seam form (v = input positions in input order, vt = "
                 "(u, v) per cut vertex, f v/vt). OUT.vtp: the 3D cut mesh with uv texture "
                 "coordinates and every field, plus OUT-map.vtp (the map, z = 0) and, for a time "
                 "series, OUT.pvd. OUT.ply: cut mesh with u v and the fields."};
    std::string input, output, report_path, html, cost = "curvature", solver = "local-global",
                                            init = "layout-lscm", refine = "injective",
                                            overlaps = "prevent", layout = "fan";
    std::vector<double> viewpoint;
    std::vector<std::vector<int>> split_at;
    vessel::cli::ImageRequest images;
    bool quiet = false;
    vessel::FlattenOptions options;
    vessel::cli::BatchOptions batch;
    // First, so that the options below (whose callbacks run in this order, and only when given)
    // override the preset's values.
    app.add_option_function<std::string>(
           "--preset",
           [&](const std::string& name) {
               options = name == "paper" ? vessel::FlattenOptions::paper() : vessel::FlattenOptions{};
           },
           "Options to start from: default (one-to-one map) or paper (the paper's method, "
           "FlattenOptions::paper(): LSCM + ARAP, overlaps kept, no relief cuts); the options "
           "below change it")
        ->check(CLI::IsMember({"default", "paper"}))
        ->default_str("default");
    auto* input_option =
        app.add_option("input", input, "Vessel surface (.obj, .off, .ply, .stl, .vtp, .vtk), "
                                        "open at inlet and outlets; arrays of a .vtp/.vtk are "
                                        "carried to the output")
            ->check(CLI::ExistingFile);
    app.add_option("-o,--output", output, "Flattened mesh (.obj, .vtp or .ply); with --batch, "
                                          "the output directory")
        ->required();
    vessel::cli::FieldArgs field_args;
    auto* fields_option =
        vessel::cli::add_field_options(app, field_args, "to carry to the output");
    app.add_option("--image", images.images,
                   "Also draw --field (default: the first point field) on the map: .png, .svg or "
                   ".pdf; a series shows step 0, "
                   "--image-step or --image-time; repeat --image for several files")
        ->allow_extra_args(false);
    app.add_option("--image-units", images.units, "With --image: units after the colorbar title");
    app.add_flag("--image-3d", images.view3d, "With --image: the 3D cut mesh beside the map");
    auto* image_step = app.add_option("--image-step", images.step,
                                      "With --image and a series: draw this step (0-based)")
                           ->check(CLI::NonNegativeNumber);
    app.add_option("--image-time", images.time, "With --image and a series: draw the field at "
                                                "this time (s), interpolated between steps")
        ->excludes(image_step);
    app.add_option("--frames", images.frames,
                   "With a --fields series: PNG frames of --field over time in this directory "
                   "(25 fps, linear interpolation between steps)");
    app.add_option("--batch", batch.inputs, "Flatten many meshes: a directory (its .obj/.off/"
                                            ".ply/.stl files, recursively) or a text file with "
                                            "one path per line; writes OUTDIR/<stem>.obj, "
                                            "<stem>.json (<file name>.obj/.json where stems "
                                            "repeat) and summary.csv/.json")
        ->excludes(input_option)
        ->excludes(fields_option);
    app.add_option("--jobs", batch.jobs, "With --batch: meshes flattened at the same time")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    app.add_flag("--resume", batch.resume, "With --batch: keep the inputs whose <stem>.obj and "
                                           "<stem>.json already exist in OUTDIR");
    vessel::TreeSurfaceOptions& surface_options = batch.surface;
    app.add_flag("--largest-component", surface_options.keep_largest_component,
                 "Keep only the largest connected component of the input (noted) instead of "
                 "refusing a surface in several pieces");
    app.add_flag("--repair", batch.repair,
                 "Apply the safe repairs (CGAL): remove degenerate and duplicate faces, orient "
                 "the faces consistently, stitch coincident borders; each is reported");
    bool refuse_polygons = false;
    app.add_flag("--refuse-polygons", refuse_polygons,
                 "Refuse faces with more than 3 corners instead of triangulating them (noted)");
    app.add_option("--report", report_path, "Write a JSON report (timings, counts, quality)");
    app.add_option("--html", html, "Also write an interactive HTML viewer of the result (single "
                                   "input only; see vessel-view for more fields)");
    app.add_option("--cost", cost, "Travel cost of the cuts: curvature (E_c), geodesic (E_g) or "
                                   "blend (E_cg)")
        ->check(CLI::IsMember({"curvature", "geodesic", "blend"}))
        ->capture_default_str();
    app.add_option("--blend", options.blend, "Weight a of E_c in E_cg = a E_c + (1 - a) E_g")
        ->check(CLI::Range(0.0, 1.0))
        ->capture_default_str();
    app.add_option("--viewpoint", viewpoint, "Start/end cuts at the loop vertices nearest this "
                                             "3D point (e.g. the camera), instead of the "
                                             "cheapest loop point")
        ->expected(3);
    app.add_option("--alpha", options.alpha_deg, "Branch angle of the layout, degrees")
        ->check(CLI::Range(0.0, 89.9))
        ->capture_default_str();
    app.add_option("--layout", layout, "Layout of the loops before the map: fan (the paper) or "
                                       "sector (each subtree in its own angular sector; pinned "
                                       "segments never cross)")
        ->check(CLI::IsMember({"fan", "sector"}))
        ->capture_default_str();
    app.add_option("--split-at", split_at, "Cut off the subtree carrying these outlets (loop "
                                           "indices, 1 = largest outlet; e.g. 3,5) just past "
                                           "its branch point and flatten it as its own map; "
                                           "repeat for several. Writes OUTPUT.pieceN.obj (the "
                                           "last piece keeps the inlet)")
        ->delimiter(',')
        ->type_size(1, -1)
        ->allow_extra_args(false);
    app.add_option("--curvature-scale", options.curvature.scale,
                   "Curvature fitting radius in mean edge lengths")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    app.add_option("--arap-iterations", options.arap.max_iterations,
                   "ARAP iterations with the inlet pinned (0 = no ARAP)")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str();
    app.add_option("--slim-iterations", options.injective.max_iterations,
                   "With --refine injective: symmetric Dirichlet (SLIM) iterations after "
                   "untangling (0 = none)")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str();
    app.add_option("--slim-momentum", options.injective.momentum,
                   "With --refine injective: heavy-ball momentum of the SLIM steps, in [0, 1) "
                   "(0 = plain SLIM)")
        ->check(CLI::Range(0.0, 0.999))
        ->capture_default_str();
    app.add_option("--scaffold-tolerance", options.injective.scaffold_tolerance,
                   "With --overlaps prevent/scaffold and --no-area-polish: SLIM stops once 3 "
                   "scaffold iterations in a row lower the energy by less than this fraction")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    app.add_option("--crossing-patience", options.injective.crossing_patience,
                   "With --overlaps prevent: SLIM iterations the map's boundary may stay crossed "
                   "before SLIM goes back to its last simple iterate and on with a scaffold")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    app.add_option("--polished-scaffold-tolerance", options.polished_scaffold_tolerance,
                   "As --scaffold-tolerance when the area polish follows SLIM (the default): "
                   "the polish's Newton steps do the rest faster")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    app.add_option("--refine", refine, "Refinement: injective (ARAP, then flipped triangles "
                                       "untangled, then SLIM; never flips), arap (the paper's "
                                       "plain ARAP) or none (the initial map)")
        ->check(CLI::IsMember({"injective", "arap", "none"}))
        ->capture_default_str();
    app.add_option("--overlaps", overlaps, "With --refine injective, when the map at the "
                                           "layout overlaps itself: prevent (restart from a "
                                           "Tutte map; if SLIM's map would overlap, a scaffold "
                                           "from its last one-to-one iterate: no overlaps), "
                                           "keep it, restart (Tutte map, fast, overlaps not "
                                           "excluded) or scaffold (restart with a scaffold "
                                           "throughout)")
        ->check(CLI::IsMember({"keep", "restart", "prevent", "scaffold"}))
        ->capture_default_str();
    app.add_flag("--keep-look", options.keep_layout_look,
                 "With --overlaps prevent, when the map at the layout overlaps itself, go on "
                 "from a one-to-one map with the layout's look (the map before ARAP, else the "
                 "fan start) instead of a Tutte circle; slower, not less distortion");
    app.add_option_function<std::string>(
           "--restart-circle",
           [&](const std::string& v) { options.restart_on_layout_circle = v == "layout"; },
           "Where the map restarts from a circle: layout (the inlet at the bottom, each outlet "
           "at its layout bearing; layout_circle.h) or tutte (constant speed)")
        ->check(CLI::IsMember({"layout", "tutte"}))
        ->default_str("layout");
    app.add_option("--look-pull", options.look_pull,
                   "When the map restarts, SLIM and the area polish also keep the start's look "
                   "(each outlet above the inlet and in walk order, or on its start ray: "
                   "--look-pull-form; centre_pull.h); the weight, 0 = off")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str();
    app.add_option_function<std::string>(
           "--look-pull-form",
           [&](const std::string& v) {
               options.look_pull_form =
                   v == "rays" ? vessel::LookPullForm::Rays : vessel::LookPullForm::Hinges;
           },
           "The look pull's outlet terms: hinges (zero cost while each outlet stays above the "
           "inlet and in walk order) or rays (each outlet held on its start ray)")
        ->check(CLI::IsMember({"hinges", "rays"}))
        ->default_str("hinges");
    app.add_option("--look-hold", options.look_hold,
                   "The look pull's inlet hold weight with hinges, if larger than --look-pull "
                   "(a rigid motion: costs no area)")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str();
    app.add_option("--look-margin", options.look_margin_deg,
                   "The look pull's hinge margin, degrees (between consecutive outlets' "
                   "bearings and above the inlet's line)")
        ->check(CLI::Range(0.0, 89.9))
        ->capture_default_str();
    app.add_option_function<std::string>(
           "--look-retry",
           [&](const std::string& v) {
               options.look_retry.mode = v == "off"     ? vessel::LookRetry::Off
                                         : v == "force" ? vessel::LookRetry::Force
                                                        : vessel::LookRetry::Auto;
           },
           "After a restarted map (--look-pull 0): auto redoes it with the hinge pull when its "
           "look is broken (an outlet below the inlet, or many walk inversions) and keeps that "
           "map if one-to-one and within the area bound (look_retry.h); force redoes it always; "
           "off never")
        ->check(CLI::IsMember({"auto", "off", "force"}))
        ->default_str("auto");
    app.add_option("--look-retry-pull", options.look_retry.pull,
                   "The look retry's hinge weight")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    app.add_option("--look-retry-inversions", options.look_retry.max_walk_inversion_fraction,
                   "The look is broken above this fraction of outlet pairs in walk inversion")
        ->check(CLI::Range(0.0, 1.0))
        ->capture_default_str();
    app.add_option("--look-retry-area", options.look_retry.max_area_over_keep,
                   "The pulled map is kept if its mean |log area| is at most this factor times "
                   "the --overlaps keep map's")
        ->check(CLI::Range(1.0, 1e9))
        ->capture_default_str();
    app.add_option("--area-polish", options.area_polish.area_weight,
                   "After SLIM, lower the area distortion at the cost of conformal distortion "
                   "(area_polish.h; on by default); the value is the area term's weight in "
                   "[0, 1). One-to-one maps stay one-to-one (except with --overlaps keep)")
        ->each([&](const std::string&) { options.polish_area = true; })
        ->capture_default_str();
    app.add_flag_callback("--no-area-polish", [&] { options.polish_area = false; },
                          "Skip the area polish (SLIM's map: less conformal distortion, more "
                          "area distortion)");
    app.add_option("--arap-solver", solver, "ARAP solver: local-global or ceres")
        ->check(CLI::IsMember({"ceres", "local-global"}))
        ->capture_default_str();
    app.add_option("--init", init, "Start of the map: layout-lscm (the paper) or spectral "
                                   "(free-boundary spectral conformal)")
        ->check(CLI::IsMember({"layout-lscm", "spectral", "tutte"}))
        ->capture_default_str();
    app.add_option("--direction-confidence", options.direction.confident_anisotropy,
                   "Curvature anisotropy (0-1) from which the cut direction is the pure "
                   "minimal curvature direction; below it the direction leans to the "
                   "vessel's harmonic longitudinal descent (0 = the paper's pure field; 0.6 "
                   "is the setting measured in docs/results.md)")
        ->check(CLI::Range(0.0, 1.0))
        ->capture_default_str();
    std::string cut_route = "aligned";
    app.add_option("--cut-route", cut_route,
                   "How a cut runs to its end: shortest (the paper's cheapest path), "
                   "streamline (the cheapest path in a band around a traced streamline of "
                   "--stream-field; cuts whose streamline does not arrive keep the cheapest "
                   "path) or aligned (per cut, whichever of the two follows --stream-field "
                   "better)")
        ->check(CLI::IsMember({"shortest", "streamline", "aligned"}))
        ->capture_default_str();
    std::string stream_field = "harmonic";
    app.add_option("--stream-field", stream_field,
                   "Field the streamline route traces: harmonic (descent of the harmonic "
                   "longitudinal coordinate) or direction (the cut cost's vessel direction z)")
        ->check(CLI::IsMember({"harmonic", "direction"}))
        ->capture_default_str();
    app.add_option("--band-rings", options.cuts.band_rings,
                   "Streamline route: edge rings around the streamline the cut may use")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str();
    app.add_option("--join-rings", options.cuts.join_rings,
                   "Streamline route: a later cut joins an earlier one once its streamline "
                   "comes within this many edge rings of it")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str();
    std::string join = "approach";
    app.add_option("--join", join,
                   "Where later cuts end on the cut tree: approach (the cheapest path, cut back "
                   "where it starts to run beside the tree, see --join-reach/--join-excess), "
                   "cheapest (wherever the cheapest path meets the tree; can run down the parent "
                   "beside a cut) or closest (a cut vertex nearest the outlet, within "
                   "--join-slack plus the outlet's perimeter)")
        ->check(CLI::IsMember({"closest", "cheapest", "approach"}))
        ->capture_default_str();
    app.add_option("--join-slack", options.cuts.join_slack,
                   "--join closest: later cuts may end on cut vertices up to (1 + this) x the "
                   "closest one's distance from the outlet, plus the outlet's perimeter")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str();
    app.add_option("--join-reach", options.cuts.join_reach,
                   "--join approach: a cut is cut back only at vertices within this many outlet "
                   "radii of the cut tree")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str();
    app.add_option("--join-excess", options.cuts.join_excess,
                   "--join approach: cut back only where the rest of the cut is longer than its "
                   "distance to the tree by more than this many outlet radii")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str();
    app.add_option("--tie-tolerance", options.cuts.tie_tolerance,
                   "Slack (fraction of the mean arc cost) within which cut routes tie; the "
                   "least winding one is taken (0 = plain Dijkstra)")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str();
    app.add_option("--relief-cuts", options.relief.max_cuts,
                   "At most this many relief cuts: slits from the most compressed point to the "
                   "seam, added while mean |log area| stays above --relief-target (0 = the "
                   "paper's cuts only)")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str();
    app.add_option("--relief-target", options.relief.target_mean_abs_log_area,
                   "Mean |log area ratio| above which relief cuts are tried")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str();
    app.add_flag("-q,--quiet", quiet, "No progress lines on stderr");
    try
    {
        app.parse(argc, argv);
    }
    catch (const CLI::ParseError& e)
    {
        // CLI11 prints the message (or the help); every usage error exits 1, as documented.
        return app.exit(e) == 0 ? 0 : 1;
    }

    if (input.empty() && batch.inputs.empty())
    {
        std::fprintf(stderr, "vessel-flatten: give an INPUT mesh, or --batch DIR_OR_LIST\n");
        return 1;
    }
    try
    {
        const std::string out_ext = std::filesystem::path(output).extension().string();
        if (batch.inputs.empty() && out_ext != ".obj" && out_ext != ".vtp" && out_ext != ".ply")
            throw vessel::InvalidInputError("the output must be .obj (seam form), .vtp or .ply, "
                                            "got " + output);
        surface_options.triangulate_polygons = !refuse_polygons;
        // Only the options given change the preset's values.
        if (app.count("--refine"))
            options.refinement = refine == "none"   ? vessel::Refinement::None
                                 : refine == "arap" ? vessel::Refinement::Arap
                                                    : vessel::Refinement::Injective;
        if (app.count("--overlaps"))
            options.overlaps = overlaps == "keep"       ? vessel::OverlapPolicy::Keep
                               : overlaps == "scaffold" ? vessel::OverlapPolicy::RestartWithScaffold
                               : overlaps == "restart"  ? vessel::OverlapPolicy::Restart
                                                        : vessel::OverlapPolicy::Prevent;
        if (app.count("--cost"))
            options.cost = cost == "geodesic" ? vessel::CostKind::Geodesic
                           : cost == "blend"  ? vessel::CostKind::Blend
                                              : vessel::CostKind::Curvature;
        if (app.count("--arap-solver"))
            options.arap.solver =
                solver == "ceres" ? vessel::ArapSolver::Ceres : vessel::ArapSolver::LocalGlobal;
        if (app.count("--cut-route"))
            options.cuts.route = cut_route == "streamline" ? vessel::CutRoute::Streamline
                                 : cut_route == "aligned"  ? vessel::CutRoute::Aligned
                                                           : vessel::CutRoute::ShortestPath;
        if (app.count("--join"))
            options.cuts.join = join == "cheapest"   ? vessel::CutJoin::Cheapest
                                : join == "approach" ? vessel::CutJoin::Approach
                                                     : vessel::CutJoin::Closest;
        if (app.count("--stream-field"))
            options.cuts.stream_field = stream_field == "direction"
                                            ? vessel::StreamField::Direction
                                            : vessel::StreamField::Harmonic;
        if (app.count("--init"))
            options.initialization = init == "spectral" ? vessel::Initialization::SpectralConformal
                                     : init == "tutte"  ? vessel::Initialization::Tutte
                                                        : vessel::Initialization::LayoutLscm;
        options.layout = vessel::make_layout(layout, options.alpha_deg);
        if (!viewpoint.empty())
        {
            options.cuts.endpoints = vessel::EndpointPolicy::NearestToPoint;
            options.cuts.viewpoint = {viewpoint[0], viewpoint[1], viewpoint[2]};
        }
        if (!batch.inputs.empty() && !split_at.empty())
            throw vessel::InvalidInputError("--split-at works on one INPUT, not with --batch");
        if (!batch.inputs.empty())
        {
            batch.output_dir = output;
            batch.quiet = quiet;
            return vessel::cli::run_batch(batch, options);
        }
        static const std::map<std::string, std::string> stage_names = {
            {"Z", "curvature, geodesic distance, alignment"},
            {"GC", "cut graph costs"},
            {"VC", "cut paths"},
            {"AC", "applying the cuts"},
            {"L", "layout"},
            {"F", "initial map + refinement"}};
        if (!quiet)
            options.on_stage = [](const std::string& stage, double s) {
                std::fprintf(stderr, "[%-2s] %-42s %8.3f s\n", stage.c_str(),
                             stage_names.at(stage).c_str(), s);
            };

        auto start = Clock::now();
        const vessel::cli::FieldInput field_input =
            vessel::cli::read_field_input(input, field_args);
        const vessel::cli::PreparedInput in =
            vessel::cli::prepare_input(field_input.data.mesh, surface_options, batch.repair);
        const vessel::TreeSurface& surface = in.surface;
        const std::vector<vessel::Field>& fields = field_input.fields;
        const vessel::TimeSeries& series = field_input.series;
        if (series.size() > 1 && out_ext != ".vtp")
            throw vessel::InvalidInputError(
                "--fields gives " + std::to_string(series.size()) +
                " time steps; write them with an OUT.vtp output (OUT.pvd series)");
        if (batch.repair && (!fields.empty() || series.size() > 0))
            throw vessel::InvalidInputError("--repair may merge or drop vertices and faces; "
                                            "fields cannot be carried through it (repair the "
                                            "mesh first, then compute the fields on it)");
        if (!split_at.empty() && (!fields.empty() || series.size() > 0))
            throw vessel::InvalidInputError("--split-at renumbers the vertices of each piece; "
                                            "fields cannot be carried to the pieces");
        const double read_s = seconds_since(start);
        if (!quiet)
        {
            std::fprintf(stderr, "[  ] read %zu vertices, %zu faces %24.3f s\n",
                         surface.mesh.n_vertices(), surface.mesh.n_faces(), read_s);
            for (const auto& note : surface.notes)
                std::fprintf(stderr, "note: %s\n", note.c_str());
        }
        if (surface.reoriented_faces > 0)  // shown even with --quiet: the input had a defect
            std::fprintf(stderr,
                         "warning: the input's faces were not wound consistently; %d %s "
                         "re-oriented to agree with their neighbours (fix the source if this "
                         "is unexpected)\n",
                         surface.reoriented_faces,
                         surface.reoriented_faces == 1 ? "face was" : "faces were");
        // One map per piece: the whole tree, or with --split-at each cut-off subtree and the rest.
        const auto flatten_piece = [&](const vessel::cli::PreparedInput& piece,
                                       const std::string& out, const std::string& report) {
            const vessel::FlattenResult result = vessel::flatten(piece.surface.mesh, options);
            if (!quiet)
                for (const auto& note : result.notes)
                    std::fprintf(stderr, "note: %s\n", note.c_str());

            start = Clock::now();
            const std::vector<vessel::Field> cut_fields =
                vessel::transfer_fields(fields, result.mesh);
            const vessel::TimeSeries cut_series = vessel::transfer_series(series, result.mesh);
            std::vector<vessel::Field> all_fields = cut_fields;
            if (cut_series.size() == 1)
                all_fields.insert(all_fields.end(), cut_series.steps[0].begin(),
                                  cut_series.steps[0].end());
            if (out_ext == ".vtp")
            {
                vessel::write_flat_vtp(out, result.mesh, result.uv, all_fields);
                if (cut_series.size() > 1)
                {
                    const std::string pvd =
                        std::filesystem::path(out).replace_extension(".pvd").string();
                    vessel::write_flat_series(pvd, result.mesh, result.uv, cut_fields, cut_series);
                    if (!quiet)
                        std::fprintf(stderr, "[  ] series: %d steps -> %s\n", cut_series.size(),
                                     pvd.c_str());
                }
            }
            else if (out_ext == ".ply")
                vessel::write_flat_ply(out, result.mesh, result.uv, all_fields);
            else
            {
                if (!all_fields.empty() && !quiet)
                    std::fprintf(stderr, "note: OBJ carries no data arrays (%zu not written); "
                                         "use an .vtp or .ply output to keep them\n",
                                 all_fields.size());
                vessel::write_flat_obj(out, piece.raw.points, result.mesh, result.uv);
            }
            if (!html.empty())
            {
                vessel::ViewerOptions view;
                view.title = std::filesystem::path(input).filename().string();
                view.flatten_command =
                    vessel::cli::command_without_viewpoint("vessel-flatten", argc, argv);
                view.view_command = vessel::cli::join_quoted({"vessel-view", input, "-o", html});
                view.viewpoint = options.cuts.endpoints == vessel::EndpointPolicy::NearestToPoint
                                     ? std::optional<Eigen::Vector3d>(options.cuts.viewpoint)
                                     : std::nullopt;
                std::vector<vessel::ViewerField> shown = {vessel::geodesic_field(result)};
                for (auto& f : vessel::cli::viewer_fields(cut_fields, cut_series))
                    shown.push_back(std::move(f));
                vessel::write_viewer_html(html, result, shown, view);
            }
            images.field = field_args.name;
            images.quiet = quiet;
            vessel::cli::render_images(images, result, cut_fields, cut_series);
            const double write_s = seconds_since(start);
            if (!report.empty())
            {
                const std::string tmp = report + ".tmp";
                std::ofstream(tmp) << vessel::cli::report_json(input, piece, result, read_s, write_s).dump(2)
                                   << "\n";
                std::filesystem::rename(tmp, report);
            }
            if (!quiet)
            {
                const auto& q = result.quality;
                std::fprintf(stderr,
                             "done: %d flipped, area ratio %.4f, mean |log area| %.4f, conformal "
                             "%.3f, total %.3f s -> %s\n",
                             q.flipped_triangles, q.area_ratio, q.mean_abs_log_area,
                             q.mean_conformal, result.timings.total(), out.c_str());
            }
        };
        if (split_at.empty())
        {
            flatten_piece(in, output, report_path);
            return 0;
        }
        if (!html.empty())
            throw vessel::InvalidInputError("--html shows one map; it cannot be used with --split-at");
        const auto pieces = vessel::split_tree(surface.mesh, split_at);
        for (std::size_t i = 0; i < pieces.size(); ++i)
        {
            const auto named = [&](const std::string& path) {
                if (path.empty())
                    return path;
                std::filesystem::path p(path);
                return (p.parent_path() / p.stem()).string() + ".piece" + std::to_string(i) +
                       p.extension().string();
            };
            if (!quiet)
                std::fprintf(stderr, "piece %zu: %zu faces\n", i, pieces[i].mesh.faces.size());
            vessel::cli::PreparedInput part;
            part.raw = pieces[i].mesh;
            part.surface = vessel::make_tree_surface(part.raw, surface_options);
            flatten_piece(part, named(output), named(report_path));
        }
        return 0;
    }
    catch (const std::exception& e)
    {
        std::fprintf(stderr, "vessel-flatten: %s\n", e.what());
        return 1;
    }
}
