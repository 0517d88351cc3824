// vessel-view: flatten a vessel tree surface and write an interactive HTML viewer of the result.
#include "../vessel_flatten/field_input.h"
#include "../vessel_flatten/viewer_fields.h"
#include "command.h"
#include "common/restart.h"
#include "common/stage_status.h"
#include "vessel/check/validation.h"
#include "vessel/core/errors.h"
#include "vessel/pipeline.h"
#include "vessel/render/viewer.h"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <filesystem>

int main(int argc, char** argv)
{
    CLI::App app{
        "Flatten a vessel tree surface and write one self-contained HTML page with the "
        "3D surface and its flattened map in linked views (fields colormapped on both, "
        "animated over time)."};
    std::string input, output, cost = "curvature", title;
    vessel::cli::FieldArgs field_args;
    std::vector<std::string> viewpoint;
    bool demo_field = false, quiet = false;
    vessel::TreeSurfaceOptions surface_options;
    vessel::FlattenOptions options;
    vessel::PulseOptions pulse;
    app.add_option("input", input,
                   "Vessel surface (.obj, .off, .ply, .stl, .vtp, .vtk), open at inlet and "
                   "outlets; the point arrays of a .vtp/.vtk are shown")
        ->required()
        ->check(CLI::ExistingFile);
    app.add_option("-o,--output", output, "The HTML page to write")->required();
    app.add_option("--viewpoint", viewpoint,
                   "Put the cuts on the far side of the vessels from this "
                   "3D point X Y Z (the page shows the one of its camera) or from face-on "
                   "(the tree seen along its axis of least spread); "
                   "the 3D view starts looking from there")
        ->expected(1, 3)
        ->option_text("X Y Z|face-on");
    app.add_option("--cost", cost, "Travel cost of the cuts: curvature, geodesic or blend")
        ->check(CLI::IsMember({"curvature", "geodesic", "blend"}))
        ->capture_default_str();
    app.add_option("--alpha", options.alpha_deg, "Branch angle of the layout, degrees")
        ->check(CLI::Range(0.0, 89.9))
        ->capture_default_str();
    vessel::cli::add_field_options(app, field_args, "to show");
    app.add_flag("--demo-field", demo_field,
                 "Add a synthetic travelling pulse (90 steps over "
                 "1.8 s) to try the time controls");
    app.add_flag("--remove-caps", surface_options.remove_flat_caps,
                 "Remove the flat caps that close the vessel ends, as vessel-flatten "
                 "--remove-caps does");
    app.add_option("--title", title, "Page title (default: the input file name)");
    app.add_flag("-q,--quiet", quiet, "No progress lines on stderr");
    try
    {
        app.parse(argc, argv);
    }
    catch (const CLI::ParseError& e)
    {
        return app.exit(e) == 0 ? 0 : 1;
    }
    // The map is made as vessel-flatten makes it: with huge pages for a large input and the
    // same BLAS kernels (the process starts again with them if it must, before any output).
    vessel::cli::restart_for_run(argv, input);
    try
    {
        if (std::filesystem::path(output).extension() != ".html")
            throw vessel::InvalidInputError("the output must be an .html file, got " + output);
        options.cost.kind = cost == "geodesic" ? vessel::CostKind::Geodesic
                       : cost == "blend"  ? vessel::CostKind::Blend
                                          : vessel::CostKind::Curvature;
        vessel::ViewerOptions view;
        vessel::cli::apply_viewpoint(viewpoint, options);
        if (!vessel::viewer_available())
            throw vessel::IoError(
                "this build has no viewer bundle (node and npm were not found "
                "when libvessel was built); install nodejs and npm and rebuild");
        // On a terminal the step running is named on a status line, as by vessel-flatten;
        // destroyed before an error's message is printed, so that the line is erased first.
        vessel::cli::LiveLine live = vessel::cli::LiveLine::on_terminal(quiet);
        live.show("reading " + std::filesystem::path(input).filename().string());
        const vessel::cli::FieldInput in =
            vessel::cli::read_field_input(input, field_args);
        const vessel::TreeSurface surface =
            vessel::make_tree_surface(in.data.mesh, surface_options);
        if (!quiet)
        {
            live.print("read " + std::to_string(surface.mesh.n_vertices()) + " vertices, " +
                       std::to_string(surface.mesh.n_faces()) + " faces; flattening...");
            vessel::cli::show_stages(options, live, false);
        }
        const vessel::FlattenResult result = vessel::flatten(surface.mesh, options);

        std::vector<vessel::ViewerField> fields = {vessel::geodesic_field(result)};
        for (auto& f : vessel::cli::viewer_fields(vessel::transfer_fields(in.fields, result.mesh),
                                                  vessel::transfer_series(in.series, result.mesh)))
            fields.push_back(std::move(f));
        if (demo_field)
            fields.push_back(vessel::pulse_field(result, pulse));
        const std::filesystem::path path(input);
        view.viewpoint = result.viewpoint;
        view.title = title.empty() ? path.filename().string() : title;
        // A series of several steps is written as OUT.vtp + OUT.case; other fields fit any output.
        const bool series = in.series.size() > 1;
        std::vector<std::string> flatten = {"vessel-flatten", input, "-o",
                                            path.stem().string() + (series ? "-flat.vtp"
                                                                           : "-flat.obj")};
        if (!field_args.spec.empty())
            flatten.insert(flatten.end(), {"--fields", field_args.spec});
        if (!field_args.name.empty())
            flatten.insert(flatten.end(), {"--field", field_args.name});
        if (app.count("--time-step"))
            flatten.insert(flatten.end(),
                           {"--time-step", std::to_string(field_args.series.time_step)});
        if (!field_args.series.match_by.empty())
            flatten.insert(flatten.end(), {"--match-by", field_args.series.match_by});
        if (app.count("--match-tolerance"))
            flatten.insert(flatten.end(), {"--match-tolerance",
                                           std::to_string(field_args.series.position_tolerance)});
        if (surface_options.remove_flat_caps)
            flatten.push_back("--remove-caps");
        if (cost != "curvature")
            flatten.insert(flatten.end(), {"--cost", cost});
        if (app.count("--alpha"))
            flatten.insert(flatten.end(), {"--alpha", std::to_string(options.alpha_deg)});
        view.flatten_command = vessel::cli::join_quoted(flatten);
        view.view_command = vessel::cli::command_without_viewpoint("vessel-view", argc, argv);
        vessel::write_viewer_html(output, result, fields, view);
        if (!quiet)
            std::fprintf(stderr, "wrote %s (%zu cut-mesh vertices, %zu faces, %zu fields)\n",
                         output.c_str(), result.mesh.n_vertices(), result.mesh.n_faces(),
                         fields.size());
        return 0;
    }
    catch (const std::exception& e)
    {
        std::fprintf(stderr, "vessel-view: %s\n", e.what());
        return 1;
    }
}
