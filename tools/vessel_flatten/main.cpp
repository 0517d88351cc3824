// vessel-flatten: cut a vessel tree surface open along natural vessel cuts and flatten it.
#include "../vessel_view/command.h"
#include "batch.h"
#include "common/error_text.h"
#include "common/restart.h"
#include "common/stage_status.h"
#include "field_input.h"
#include "images.h"
#include "json_config.h"
#include "output_plan.h"
#include "vessel/check/validation.h"
#include "vessel/core/errors.h"
#include "vessel/cut/split.h"
#include "vessel/fields/field_series.h"
#include "vessel/io/flat_io.h"
#include "vessel/io/flat_vtk.h"
#include "vessel/io/io.h"
#include "vessel/pipeline.h"
#include "vessel/render/viewer.h"
#include "viewer_fields.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <set>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start)
{
    return std::chrono::duration<double>(Clock::now() - start).count();
}

// CLI11 2.1's help has two blank lines between option groups; one keeps --help on one screen.
class HelpFormatter : public CLI::Formatter
{
public:
    //! The groups listed only by --help-all (the tuning options).
    std::set<std::string> hidden;

    std::string make_group(std::string group, bool is_positional,
                           std::vector<const CLI::Option*> opts) const override
    {
        if (hidden.count(group) > 0)
            return "";
        return CLI::Formatter::make_group(std::move(group), is_positional, std::move(opts));
    }

    std::string make_help(const CLI::App* app, std::string name,
                          CLI::AppFormatMode mode) const override
    {
        std::string help = CLI::Formatter::make_help(app, std::move(name), mode);
        for (std::size_t at = help.find("\n\n\n"); at != std::string::npos;
             at = help.find("\n\n\n"))
            help.erase(at, 1);
        return help;
    }
};

template <class T>
struct Same
{
    using type = T;
};

// An option whose words name the values of \p target (an enum or a bool). \p target changes only
// when the option is given, so a preset's value stands otherwise; the help shows the word of
// its value now (the default's) as the default.
template <class T>
CLI::Option* add_choice(CLI::App& app, const std::string& name, T& target,
                        const std::vector<std::pair<std::string, typename Same<T>::type>>& choices,
                        const std::string& help)
{
    std::vector<std::string> words;
    std::string current;
    for (const auto& [word, value] : choices)
    {
        words.push_back(word);
        if (value == target)
            current = word;
    }
    std::string shown;
    for (const auto& word : words)
        shown += (shown.empty() ? "" : "|") + word;
    return app
        .add_option_function<std::string>(
            name,
            [&target, choices](const std::string& word) {
                for (const auto& [w, value] : choices)
                    if (w == word)
                        target = value;
            },
            help)
        ->check(CLI::IsMember(words).description(""))
        ->type_name(shown)
        ->default_str(current);
}

// Runs \p run; a library refusal it throws is thrown again as "INPUT: CONTEXT message", its
// leading \p api ("function: ") dropped, unless the message names \p input already.
template <class Run>
auto naming_input(const std::string& input, const std::string& context, const std::string& api,
                  const Run& run) -> decltype(run())
{
    try
    {
        return run();
    }
    catch (const vessel::InvalidInputError& e)
    {
        std::string message = e.what();
        if (message.find(input) != std::string::npos)
            throw;
        if (!api.empty() && message.rfind(api, 0) == 0)
            message = message.substr(api.size());
        throw vessel::InvalidInputError(input + ": " + context + message);
    }
}

// What the command line sets: every option writes into one of these.
struct Args
{
    std::string input, output, report_path, html, layout = "fan", preset = "default";
    std::vector<std::string> viewpoint;
    std::vector<std::vector<int>> split_at;
    vessel::cli::ImageRequest images;
    bool quiet = false;
    vessel::FlattenOptions options;
    vessel::cli::BatchOptions batch;
    std::vector<std::string> batch_case;  // FILE NAME: one mesh of --batch (run_batch_case())
    vessel::cli::FieldArgs field_args;
    bool refuse_polygons = false;
};

// The groups of --help; the tuning groups are listed by --help-all only.
struct Groups
{
    std::string io, fields, cut, map;
    std::string input_tuning, image_tuning, cut_tuning, map_tuning;
};

// Input and output, and the input checks; returns --batch (which --fields excludes).
CLI::Option* add_io_options(CLI::App& app, Args& a, const Groups& g)
{
    std::string& input = a.input;
    std::string& output = a.output;
    std::string& report_path = a.report_path;
    std::string& html = a.html;
    bool& quiet = a.quiet;
    vessel::cli::BatchOptions& batch = a.batch;
    std::vector<std::string>& batch_case = a.batch_case;
    bool& refuse_polygons = a.refuse_polygons;
    vessel::TreeSurfaceOptions& surface_options = a.batch.surface;
    const std::string& io_group = g.io;
    const std::string& input_tuning = g.input_tuning;
    auto* input_option = app.add_option("input", input,
                                        "Vessel surface (.obj .off .ply .stl .vtp .vtk), open at "
                                        "inlet and outlets")
                             ->check(CLI::ExistingFile)
                             ->option_text("MESH");
    app.add_option("-o,--output", output,
                   "Flat map: .obj (seam form), .vtp or .ply; with "
                   "--batch a directory")
        ->required()
        ->option_text("OUT (required)")
        ->group(io_group);
    auto* batch_option = app.add_option("--batch", batch.inputs,
                                        "Flatten every mesh of a directory or list file "
                                        "into OUT (a directory)")
                             ->excludes(input_option)
                             ->option_text("DIR|LIST")
                             ->group(io_group);
    app.add_option("--batch-case", batch_case)->expected(2)->needs(batch_option)->group("");
    app.add_option("--jobs", batch.jobs, "With --batch: meshes flattened at the same time")
        ->check(CLI::PositiveNumber)
        ->option_text("N")
        ->group(io_group);
    app.add_option("--report", report_path, "Write a JSON report (timings, counts, quality)")
        ->option_text("FILE.json")
        ->group(io_group);
    app.add_option("--html", html, "Also write an interactive HTML viewer of the result")
        ->option_text("FILE.html")
        ->group(io_group);
    app.set_config("--config", "",
                   "Read options from a JSON file {\"long-name\": value}; "
                   "the command line wins")
        ->option_text("FILE.json")
        ->group(io_group);
    app.add_flag("-q,--quiet", quiet, "No progress or stage lines on stderr")->group(io_group);
    app.add_flag("--resume", batch.resume,
                 "With --batch: keep the inputs whose <stem>.obj and "
                 "<stem>.json already exist in OUTDIR")
        ->group(input_tuning);
    app.add_option("--batch-memory", batch.memory_mb,
                   "With --batch: memory the meshes running together may use; each is admitted "
                   "by an estimate from its triangles (32 MB + 3 KB each): one above it is "
                   "refused, large ones wait for room; one that uses more than the cap allows is "
                   "stopped (default: 80% of the machine's memory)")
        ->check(CLI::PositiveNumber)
        ->option_text("MB")
        ->group(input_tuning);
    app.add_flag("--largest-component", surface_options.keep_largest_component,
                 "Keep only the largest connected component of the input (noted) instead of "
                 "refusing a surface in several pieces")
        ->group(input_tuning);
    app.add_flag("--remove-caps", surface_options.remove_flat_caps,
                 "Remove the flat caps that close the vessel ends (a capped SimVascular model, "
                 "a segmentation closed by planes): planar patches meeting the wall at a sharp "
                 "rim; each is reported. Point and cell data still match")
        ->group(input_tuning);
    app.add_flag("--repair", batch.repair,
                 "Apply the safe repairs (CGAL): remove degenerate and duplicate faces, orient "
                 "the faces consistently, stitch coincident borders; each is reported")
        ->group(input_tuning);
    app.add_option("--fill-holes", batch.fill_holes,
                   "Fill the boundary loops of perimeter below MAX_PERIMETER (mesh units) with "
                   "CGAL's hole filling (triangulated, refined, faired; reported): holes in the "
                   "wall that would be refused as not vessel ends. With or without --repair")
        ->option_text("MAX_PERIMETER")
        ->check(CLI::PositiveNumber)
        ->group(input_tuning);
    app.add_option("--max-hole-edges", surface_options.hole_max_edges,
                   "Refuse boundary loops of at most this many edges and under half the largest "
                   "loop's perimeter as holes in the wall (not vessel ends); 0 takes every loop "
                   "for a vessel end")
        ->capture_default_str()
        ->check(CLI::NonNegativeNumber)
        ->group(input_tuning);
    app.add_flag("--refuse-polygons", refuse_polygons,
                 "Refuse faces with more than 3 corners instead of triangulating them (noted)")
        ->group(input_tuning);
    return batch_option;
}

// Fields and images.
void add_field_options(CLI::App& app, Args& a, const Groups& g, CLI::Option* batch_option)
{
    vessel::cli::ImageRequest& images = a.images;
    vessel::cli::FieldArgs& field_args = a.field_args;
    const std::string& fields_group = g.fields;
    const std::string& image_tuning = g.image_tuning;
    auto* fields_option = vessel::cli::add_field_options(app, field_args, "to carry to the output");
    fields_option
        ->description(
            "Fields to carry to the output: .vtp/.vtk, .pvd, numbered files "
            "or CSV (docs/fields.md)")
        ->excludes(batch_option)
        ->option_text("SPEC")
        ->group(fields_group);
    app.get_option("--field")
        ->description("Keep only this array of --fields; the one --image draws")
        ->option_text("NAME")
        ->group(fields_group);
    app.get_option("--time-step")->group(image_tuning);
    app.get_option("--match-by")->group(fields_group);
    app.get_option("--match-tolerance")->group(image_tuning);
    app.add_option("--image", images.images,
                   "Draw --field on the map: .png, .svg or .pdf (repeatable)")
        ->allow_extra_args(false)
        ->option_text("FILE")
        ->group(fields_group);
    app.add_option("--frames", images.frames,
                   "With a --fields series: PNG frames of --field over time in this directory")
        ->option_text("DIR")
        ->group(fields_group);
    app.add_option("--image-units", images.units, "With --image: units after the colorbar title")
        ->group(image_tuning);
    app.add_flag("--image-3d", images.view3d, "With --image: the 3D cut mesh beside the map")
        ->group(image_tuning);
    app.add_option("--image-arrows", images.arrows,
                   "With --image/--frames: arrows of this 3-component point array's direction "
                   "along the wall over the colours (e.g. WSS); --frames draws its time average")
        ->option_text("NAME")
        ->group(image_tuning);
    app.add_option("--image-range", images.range,
                   "With --image/--frames: the colour range LO HI (default: the field's, over "
                   "the whole series), so that figures of several runs compare")
        ->expected(2)
        ->option_text("LO HI")
        ->group(image_tuning);
    add_choice(app, "--colormap", images.colormap,
               {{"auto", vessel::Colormap::Auto},
                {"viridis", vessel::Colormap::Viridis},
                {"diverging", vessel::Colormap::Diverging}},
               "With --image/--frames: colour table (auto: diverging when the range straddles "
               "0, else viridis)")
        ->group(image_tuning);
    app.add_option("--image-size", images.size,
                   "With --image/--frames: width and height in pixels (points for SVG/PDF)")
        ->expected(2)
        ->option_text("W H")
        ->group(image_tuning);
    app.add_option("--fps", images.fps,
                   "With --frames: frames per second of series time (each frame shows its time)")
        ->capture_default_str()
        ->group(image_tuning);
    auto* image_step = app.add_option("--image-step", images.step,
                                      "With --image and a series: draw this step (0-based)")
                           ->check(CLI::NonNegativeNumber)
                           ->group(image_tuning);
    app.add_option("--image-time", images.time,
                   "With --image and a series: draw the field at "
                   "this time (s), interpolated between steps")
        ->excludes(image_step)
        ->group(image_tuning);
}

// Cut: cost, viewpoint, pieces, relief cuts, and the cut planner's tuning.
void add_cut_options(CLI::App& app, Args& a, const Groups& g)
{
    std::vector<std::string>& viewpoint = a.viewpoint;
    std::vector<std::vector<int>>& split_at = a.split_at;
    vessel::FlattenOptions& options = a.options;
    const std::string& cut_group = g.cut;
    const std::string& cut_tuning = g.cut_tuning;
    add_choice(app, "--cost", options.cost.kind,
               {{"curvature", vessel::CostKind::Curvature},
                {"geodesic", vessel::CostKind::Geodesic},
                {"blend", vessel::CostKind::Blend}},
               "Travel cost of the cuts (default curvature)")
        ->option_text("curvature|geodesic|blend")
        ->group(cut_group);
    app.add_option("--viewpoint", viewpoint,
                   "Put the cuts on the far side of the vessels from this "
                   "3D point X Y Z (e.g. the camera), or from face-on: the tree seen along "
                   "its axis of least spread (the same side of each vessel at any resolution)")
        ->expected(1, 3)
        ->option_text("X Y Z|face-on")
        ->group(cut_group);
    app.add_option("--split-at", split_at,
                   "Flatten the subtree of these outlets (e.g. 3,5) as "
                   "its own map; repeatable")
        ->delimiter(',')
        ->type_size(1, -1)
        ->allow_extra_args(false)
        ->option_text("I,J,...")
        ->group(cut_group);
    app.add_option("--relief-cuts", options.relief.max_cuts,
                   "At most this many relief cuts where the map is squeezed (default " +
                       std::to_string(vessel::FlattenOptions{}.relief.max_cuts) + ")")
        ->check(CLI::NonNegativeNumber)
        ->option_text("N")
        ->group(cut_group);
    app.add_option("--relief-target", options.relief.target_mean_abs_log_area,
                   "Mean |log area ratio| above which relief cuts are tried")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str()
        ->group(cut_tuning);
    app.add_option("--blend", options.cost.blend, "Weight a of E_c in E_cg = a E_c + (1 - a) E_g")
        ->check(CLI::Range(0.0, 1.0))
        ->capture_default_str()
        ->group(cut_tuning);
    app.add_option("--curvature-scale", options.curvature.scale,
                   "Curvature fitting radius in mean edge lengths")
        ->check(CLI::PositiveNumber)
        ->capture_default_str()
        ->group(cut_tuning);
    app.add_option("--direction-confidence", options.direction.confident_anisotropy,
                   "Curvature anisotropy (0-1) from which the cut direction is the pure "
                   "minimal curvature direction; below it the direction leans to the "
                   "vessel's harmonic longitudinal descent (0 = the paper's pure field)")
        ->check(CLI::Range(0.0, 1.0))
        ->capture_default_str()
        ->group(cut_tuning);
    add_choice(app, "--cut-route", options.cuts.route,
               {{"shortest", vessel::CutRoute::ShortestPath},
                {"streamline", vessel::CutRoute::Streamline},
                {"aligned", vessel::CutRoute::Aligned}},
               "How a cut runs to its end: shortest (the paper's cheapest path), "
               "streamline (the cheapest path in a band around a traced streamline "
               "of --stream-field; cuts whose streamline does not arrive keep the "
               "cheapest path) or aligned (per cut, whichever of the two follows "
               "--stream-field better)")
        ->group(cut_tuning);
    add_choice(app, "--stream-field", options.cuts.stream_field,
               {{"harmonic", vessel::StreamField::Harmonic},
                {"direction", vessel::StreamField::Direction}},
               "Field the streamline route traces: harmonic (descent of the "
               "harmonic longitudinal coordinate) or direction (the cut cost's "
               "vessel direction z)")
        ->group(cut_tuning);
    app.add_option("--band-rings", options.cuts.band_rings,
                   "Streamline route: edge rings around the streamline the cut may use")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str()
        ->group(cut_tuning);
    app.add_option("--join-rings", options.cuts.join_rings,
                   "Streamline route: a later cut joins an earlier one once its streamline "
                   "comes within this many edge rings of it")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str()
        ->group(cut_tuning);
    add_choice(app, "--join", options.cuts.join,
               {{"closest", vessel::CutJoin::Closest},
                {"cheapest", vessel::CutJoin::Cheapest},
                {"approach", vessel::CutJoin::Approach}},
               "Where later cuts end on the cut tree: approach (the cheapest path, "
               "cut back where it starts to run beside the tree, see --join-reach/"
               "--join-excess), cheapest (wherever the cheapest path meets the tree; "
               "can run down the parent beside a cut) or closest (a cut vertex "
               "nearest the outlet, within --join-slack plus the outlet's perimeter)")
        ->group(cut_tuning);
    app.add_option("--join-slack", options.cuts.join_slack,
                   "--join closest: later cuts may end on cut vertices up to (1 + this) x the "
                   "closest one's distance from the outlet, plus the outlet's perimeter")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str()
        ->group(cut_tuning);
    app.add_option("--join-reach", options.cuts.join_reach,
                   "--join approach: a cut is cut back only at vertices within this many outlet "
                   "radii of the cut tree")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str()
        ->group(cut_tuning);
    app.add_option("--join-excess", options.cuts.join_excess,
                   "--join approach: cut back only where the rest of the cut is longer than its "
                   "distance to the tree by more than this many outlet radii")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str()
        ->group(cut_tuning);
    app.add_flag("--natural-cuts,!--no-natural-cuts", options.cuts.natural_cuts,
                 "Hold every cut to 45 degrees around its vessel, end to end and in span, with a "
                 "winding-bounded route where needed (the default); --no-natural-cuts: the "
                 "aligned route alone, whose cuts may wind further around their vessels")
        ->group(cut_tuning);
    app.add_option("--tie-tolerance", options.cuts.tie_tolerance,
                   "Slack (fraction of the mean arc cost) within which cut routes tie; the "
                   "least winding one is taken (0 = plain Dijkstra)")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str()
        ->group(cut_tuning);
}

// Map: preset, layout, refinement, and the solvers' tuning.
void add_map_options(CLI::App& app, Args& a, const Groups& g)
{
    std::string& layout = a.layout;
    std::string& preset = a.preset;
    vessel::FlattenOptions& options = a.options;
    const std::string& map_group = g.map;
    const std::string& map_tuning = g.map_tuning;
    app.add_option("--preset", preset,
                   "Method to start from: default (one-to-one map) or paper "
                   "(the paper's LSCM + ARAP)")
        ->check(CLI::IsMember({"default", "paper"}))
        ->option_text("default|paper")
        ->group(map_group);
    app.add_option("--layout", layout,
                   "Loops' layout: fan (the paper) or sector (subtrees in "
                   "their own sectors)")
        ->check(CLI::IsMember({"fan", "sector"}))
        ->option_text("fan|sector")
        ->group(map_group);
    add_choice(app, "--refine", options.refinement,
               {{"injective", vessel::Refinement::Injective},
                {"arap", vessel::Refinement::Arap},
                {"none", vessel::Refinement::None}},
               "Refinement: injective (no flips; default), arap (the paper's) or none")
        ->option_text("injective|arap|none")
        ->group(map_group);
    add_choice(app, "--overlaps", options.overlaps,
               {{"prevent", vessel::OverlapPolicy::Prevent},
                {"keep", vessel::OverlapPolicy::Keep},
                {"restart", vessel::OverlapPolicy::Restart}},
               "With --refine injective, when the map at the layout overlaps "
               "itself: prevent (restart from a Tutte map; if SLIM's map would "
               "overlap, a scaffold from its last one-to-one iterate: no overlaps), "
               "keep it or restart (Tutte map, fast, overlaps not excluded)")
        ->group(map_tuning);
    app.add_option("--alpha", options.alpha_deg, "Branch angle of the fan layout, degrees")
        ->check(CLI::Range(0.0, 89.9))
        ->capture_default_str()
        ->group(map_tuning);
    add_choice(app, "--init", options.initialization,
               {{"layout-lscm", vessel::Initialization::LayoutLscm},
                {"spectral", vessel::Initialization::SpectralConformal},
                {"tutte", vessel::Initialization::Tutte}},
               "Start of the map: layout-lscm (the paper), spectral (free-boundary "
               "spectral conformal) or tutte")
        ->group(map_tuning);
    app.add_option("--arap-iterations", options.arap.max_iterations,
                   "ARAP iterations with the inlet pinned (0 = no ARAP)")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str()
        ->group(map_tuning);
    add_choice(
        app, "--arap-solver", options.arap.solver,
        {{"local-global", vessel::ArapSolver::LocalGlobal}, {"ceres", vessel::ArapSolver::Ceres}},
        "ARAP solver: local-global or ceres")
        ->group(map_tuning);
    app.add_option("--slim-iterations", options.injective.max_iterations,
                   "With --refine injective: symmetric Dirichlet (SLIM) iterations after "
                   "untangling (0 = none)")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str()
        ->group(map_tuning);
    app.add_option("--slim-momentum", options.injective.momentum,
                   "With --refine injective: heavy-ball momentum of the SLIM steps, in [0, 1) "
                   "(0 = plain SLIM)")
        ->check(CLI::Range(0.0, 0.999))
        ->capture_default_str()
        ->group(map_tuning);
    app.add_option("--scaffold-tolerance", options.injective.scaffold_tolerance,
                   "With --overlaps prevent: SLIM stops once 3 scaffold iterations in a row "
                   "lower the energy by less than this fraction (0 = 3e-4 before the area "
                   "polish, 2e-5 with --no-area-polish)")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str()
        ->group(map_tuning);
    app.add_option("--coarse-vertices", options.multilevel.coarse_vertices,
                   "With --refine injective: cut meshes with more than twice this many vertices "
                   "are mapped coarse-to-fine (solved on a decimated copy, then relaxed at full "
                   "resolution); 0 = every map at full resolution (slower on large meshes)")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str()
        ->group(map_tuning);
    app.add_option("--area-tolerance", options.multilevel.area_tolerance,
                   "Coarse-to-fine: the finest level's relaxation stops once the map's mean "
                   "|log area| is at most this (0 = its full schedule, for the last fraction "
                   "of a percent at several times the time on the largest meshes)")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str()
        ->group(map_tuning);
    app.add_option("--crossing-patience", options.injective.crossing_patience,
                   "With --overlaps prevent: SLIM iterations the map's boundary may stay crossed "
                   "before SLIM goes back to its last simple iterate and on with a scaffold")
        ->check(CLI::PositiveNumber)
        ->capture_default_str()
        ->group(map_tuning);
    app.add_option("--area-polish", options.area_polish.area_weight,
                   "After SLIM, lower the area distortion at the cost of conformal distortion "
                   "(area_polish.h; on by default); the value is the area term's weight in "
                   "[0, 1). One-to-one maps stay one-to-one (except with --overlaps keep)")
        ->each([&](const std::string&) { options.polish_area = true; })
        ->capture_default_str()
        ->group(map_tuning);
    app.add_flag_callback(
           "--no-area-polish", [&] { options.polish_area = false; },
           "Skip the area polish (SLIM's map: less conformal distortion, more "
           "area distortion)")
        ->group(map_tuning);
    add_choice(app, "--restart-circle", options.restart_on_layout_circle,
               {{"layout", true}, {"tutte", false}},
               "Where the map restarts from a circle: layout (the inlet at the "
               "bottom, each outlet at its layout bearing; layout_circle.h) or "
               "tutte (constant speed)")
        ->group(map_tuning);
    app.add_option("--look-pull", options.look_pull.weight,
                   "When the map restarts, SLIM, the area polish and the coarse-to-fine carry "
                   "also keep the start's look (each outlet above the inlet and in walk order, "
                   "or on its start ray: --look-pull-form; centre_pull.h); the weight, 0 = off")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str()
        ->group(map_tuning);
    add_choice(app, "--look-pull-form", options.look_pull.form,
               {{"hinges", vessel::LookPullForm::Hinges}, {"rays", vessel::LookPullForm::Rays}},
               "The look pull's outlet terms: hinges (zero cost while each outlet "
               "stays above the inlet and in walk order) or rays (each outlet held "
               "on its start ray)")
        ->group(map_tuning);
    app.add_option("--look-hold", options.look_pull.hold,
                   "The look pull's inlet hold weight with hinges, if larger than --look-pull "
                   "(a rigid motion: costs no area)")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str()
        ->group(map_tuning);
    app.add_option("--look-margin", options.look_pull.margin_deg,
                   "The look pull's hinge margin, degrees (between consecutive outlets' "
                   "bearings and above the inlet's line)")
        ->check(CLI::Range(0.0, 89.9))
        ->capture_default_str()
        ->group(map_tuning);
    add_choice(app, "--look-retry", options.look_retry.mode,
               {{"auto", vessel::LookRetry::Auto},
                {"off", vessel::LookRetry::Off},
                {"force", vessel::LookRetry::Force}},
               "After a restarted map (--look-pull 0): auto redoes it with the hinge "
               "pull when its look is broken (an outlet below the inlet, or many "
               "walk inversions) and keeps that map if one-to-one and within the "
               "area bound (look_retry.h); force redoes it always; off never")
        ->group(map_tuning);
    app.add_option("--look-retry-pull", options.look_retry.pull, "The look retry's hinge weight")
        ->check(CLI::PositiveNumber)
        ->capture_default_str()
        ->group(map_tuning);
    app.add_option("--look-retry-inversions", options.look_retry.max_walk_inversion_fraction,
                   "The look is broken above this fraction of outlet pairs in walk inversion")
        ->check(CLI::Range(0.0, 1.0))
        ->capture_default_str()
        ->group(map_tuning);
    app.add_option("--look-retry-area", options.look_retry.max_area_over_keep,
                   "The pulled map is kept if its mean |log area| is at most this factor times "
                   "the --overlaps keep map's")
        ->check(CLI::Range(1.0, 1e9))
        ->capture_default_str()
        ->group(map_tuning);
}

// One INPUT (not --batch): read and check it, flatten it (or each --split-at piece) and write
// every output. \p out_ext: the output's extension.
int flatten_input(Args& a, const std::string& out_ext, int argc, char** argv,
                  vessel::cli::LiveLine& live)
{
    std::string& input = a.input;
    std::string& output = a.output;
    std::string& report_path = a.report_path;
    std::string& html = a.html;
    std::vector<std::vector<int>>& split_at = a.split_at;
    vessel::cli::ImageRequest& images = a.images;
    bool& quiet = a.quiet;
    vessel::FlattenOptions& options = a.options;
    vessel::cli::BatchOptions& batch = a.batch;
    vessel::cli::FieldArgs& field_args = a.field_args;
    vessel::TreeSurfaceOptions& surface_options = a.batch.surface;
    // Every output checked before any work; all of them removed if the run fails.
    const vessel::cli::OutputPlan outputs(
        {output, report_path, html, images.images, images.frames,
         !field_args.spec.empty() && out_ext == ".vtp",
         split_at.empty() ? 0 : static_cast<int>(split_at.size()) + 1, {input, field_args.spec}});
    auto start = Clock::now();
    live.show("[  ] reading " + std::filesystem::path(input).filename().string());
    const vessel::cli::FieldInput field_input =
        vessel::cli::read_field_input(input, field_args);
    images.field = field_args.name;
    vessel::cli::check_images(images, field_input.fields, field_input.series);
    // The validation's messages name the defect, not the file: say which file it is.
    const vessel::cli::PreparedInput in = naming_input(input, "", "", [&] {
        return vessel::cli::prepare_input(field_input.data.mesh, surface_options,
                                          batch.repair_options());
    });
    const vessel::TreeSurface& surface = in.surface;
    const std::vector<vessel::Field>& fields = field_input.fields;
    const vessel::TimeSeries& series = field_input.series;
    if (series.size() > 1 && out_ext != ".vtp")
        throw vessel::InvalidInputError(
            "--fields gives " + std::to_string(series.size()) +
            " time steps; write them with an OUT.vtp output (OUT.case series)");
    if (batch.repair_options() && (!fields.empty() || series.size() > 0))
        throw vessel::InvalidInputError("--repair and --fill-holes may merge, drop or add "
                                        "vertices and faces; "
                                        "fields cannot be carried through it (repair the "
                                        "mesh first, then compute the fields on it)");
    if (!split_at.empty() && (!fields.empty() || series.size() > 0))
        throw vessel::InvalidInputError("--split-at renumbers the vertices of each piece; "
                                        "fields cannot be carried to the pieces");
    const double read_s = seconds_since(start);
    live.hide();
    if (!quiet)
    {
        std::fprintf(stderr, "[  ] read %zu vertices, %zu faces %24.3f s\n",
                     surface.mesh.n_vertices(), surface.mesh.n_faces(), read_s);
        for (const auto& note : surface.notes)
            std::fprintf(stderr, "note: %s\n", note.c_str());
        for (const auto& note : series.notes)
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
        // Shown even with --quiet, like the orientation warning: the map is of little use.
        const std::string distortion = vessel::distortion_warning(result.quality);
        if (!distortion.empty())
            std::fprintf(stderr, "warning: %s: %s\n", input.c_str(), distortion.c_str());

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
                const std::string series_case =
                    std::filesystem::path(out).replace_extension(".case").string();
                vessel::write_flat_series(series_case, result.mesh, result.uv, cut_fields,
                                          cut_series);
                if (!quiet)
                    std::fprintf(stderr, "[  ] series: %d steps -> %s\n", cut_series.size(),
                                 series_case.c_str());
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
            view.viewpoint = result.viewpoint;
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
            vessel::write_text_file(
                report,
                vessel::cli::report_json(input, piece, result, read_s, write_s)
                    .dump(2) +
                "\n");
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
    // split_tree()'s refusals name the library function; say which file and option instead.
    const auto pieces = naming_input(input, "--split-at: ", "split_tree: ",
                                     [&] { return vessel::split_tree(surface.mesh, split_at); });
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

// After parsing: the checks, then --batch or one INPUT; a refusal prints one line, exit 1.
int run(Args& a, int argc, char** argv)
{
    std::string& input = a.input;
    std::string& output = a.output;
    std::string& layout = a.layout;
    std::vector<std::string>& viewpoint = a.viewpoint;
    std::vector<std::vector<int>>& split_at = a.split_at;
    bool& quiet = a.quiet;
    vessel::FlattenOptions& options = a.options;
    vessel::cli::BatchOptions& batch = a.batch;
    std::vector<std::string>& batch_case = a.batch_case;
    bool& refuse_polygons = a.refuse_polygons;
    vessel::TreeSurfaceOptions& surface_options = a.batch.surface;
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
        options.layout = vessel::make_layout(layout, options.alpha_deg);
        vessel::cli::apply_viewpoint(viewpoint, options);
        if (!batch.inputs.empty() && !split_at.empty())
            throw vessel::InvalidInputError("--split-at works on one INPUT, not with --batch");
        if (!batch.inputs.empty())
        {
            batch.output_dir = output;
            batch.quiet = quiet;
            if (!batch_case.empty())
                return vessel::cli::run_batch_case(batch, options, batch_case[0], batch_case[1]);
            batch.command.assign(argv, argv + argc);
            return vessel::cli::run_batch(batch, options);
        }
        // A large mesh runs with huge pages, and every mesh with the BLAS kernels the maps are
        // made with everywhere: this process starts again with them if it must (before any
        // output, so nothing is printed twice).
        vessel::cli::restart_for_run(argv, input);
        // Destroyed before an error's message is printed: the status line is erased first.
        vessel::cli::LiveLine live = vessel::cli::LiveLine::on_terminal(quiet);
        if (!quiet)
            vessel::cli::show_stages(options, live, true);
        return flatten_input(a, out_ext, argc, argv, live);
    }
    catch (const std::exception& e)
    {
        std::fprintf(stderr, "vessel-flatten: %s\n",
                     vessel::cli::error_text(e, input.empty() ? batch.inputs : input).c_str());
        return 1;
    }
}

}  // namespace

int main(int argc, char** argv)
{
    CLI::App app{
        "Cut a vessel tree surface open along natural vessel cuts and flatten it into one "
        "2D map (README.md; every option: --help-all).",
        "vessel-flatten"};
    const auto formatter = std::make_shared<HelpFormatter>();
    app.formatter(formatter);
    app.get_formatter()->column_width(35);
    app.set_help_all_flag("--help-all", "Also list the tuning options");
    app.set_version_flag("--version", std::string("vessel-flatten ") + VESSEL_VERSION);
    // The tuning options are listed by --help-all only. (Not by putting them in CLI11's hidden
    // group "": its errors then name no option, ": jet not in {...}".)
    const bool help_all = std::any_of(
        argv + 1, argv + argc, [](const char* a) { return std::strcmp(a, "--help-all") == 0; });
    const auto tuning = [&](const std::string& group) {
        if (!help_all)
            formatter->hidden.insert(group);
        return group;
    };
    const Groups groups{"Input and output",
                        "Fields and images",
                        "Cut",
                        "Map",
                        tuning("Input checks"),
                        tuning("Fields and images, more"),
                        tuning("Cut, tuning"),
                        tuning("Map, tuning")};

    Args a;
    CLI::Option* batch_option = add_io_options(app, a, groups);
    add_field_options(app, a, groups, batch_option);
    add_cut_options(app, a, groups);
    add_map_options(app, a, groups);
    app.config_formatter(std::make_shared<vessel::cli::JsonConfig>());
    app.allow_config_extras(CLI::config_extras_mode::error);
    try
    {
        // Twice: the first parse finds the preset (on the command line or in --config), the
        // second writes the options given over it.
        app.parse(argc, argv);
        a.options =
            a.preset == "paper" ? vessel::FlattenOptions::paper() : vessel::FlattenOptions{};
        app.clear();
        app.parse(argc, argv);
    }
    catch (const CLI::ConfigError& e)
    {
        std::string what = e.what();
        const std::string unknown = "INI was not able to parse ";  // CLI11's words
        if (what.rfind(unknown, 0) == 0)
            what = "no option --" + what.substr(unknown.size()) +
                   "; the keys are long option names without the dashes (see --help-all)";
        std::fprintf(stderr, "vessel-flatten: --config: %s\n", what.c_str());
        return 1;
    }
    catch (const CLI::ParseError& e)
    {
        // CLI11 prints the message (or the help); every usage error exits 1, as documented.
        return app.exit(e) == 0 ? 0 : 1;
    }
    return run(a, argc, argv);
}
