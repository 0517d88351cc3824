#include "field_input.h"

#include "vessel/core/errors.h"
#include "vessel/io/io.h"

namespace vessel::cli {

CLI::Option* add_field_options(CLI::App& app, FieldArgs& args, const std::string& purpose,
                               bool with_field)
{
    auto* fields = app.add_option(
        "--fields", args.spec,
        "Fields over the input mesh " + purpose + ": a .vtp/.vtk, a .pvd series, numbered "
        "files (wss_%03d.vtp or 'wss_*.vtp') or a CSV table (wide: vertex,t0,t1,...; long: "
        "vertex,time,NAME); see docs/fields.md");
    if (with_field)
        app.add_option("--field", args.name,
                       "Keep only this array of --fields (and check that it exists); also the "
                       "CSV field's name in wide form. NAME:magnitude|x|y|z: the value images "
                       "draw");
    app.add_option("--time-step", args.series.time_step,
                   "Seconds between numbered files (and CSV columns without times)")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    app.add_option("--match-by", args.series.match_by,
                   "Pair the points of --fields files with the mesh's: an integer id array "
                   "(default GlobalNodeID when both have it, else file order), 'position' "
                   "(nearest point within --match-tolerance) or 'order'")
        ->option_text("ID|position|order");
    app.add_option("--match-tolerance", args.series.position_tolerance,
                   "Largest distance of a paired --fields point from its mesh vertex, as a "
                   "fraction of the mesh's bounding-box diagonal")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str();
    return fields;
}

std::string FieldChoice::title(int components) const
{
    if (component >= 0)
        return name + "_" + "xyz"[component];
    return components == 1 ? name : "|" + name + "|";
}

FieldChoice parse_field_choice(const std::string& spec)
{
    FieldChoice choice;
    const auto colon = spec.rfind(':');
    choice.name = spec.substr(0, colon);
    if (colon == std::string::npos)
        return choice;
    const std::string which = spec.substr(colon + 1);
    if (which == "x" || which == "y" || which == "z")
        choice.component = which[0] - 'x';
    else if (which != "magnitude")
        throw InvalidInputError("--field " + spec + ": '" + which +
                                "' is not magnitude, x, y or z (e.g. --field WSS:x)");
    return choice;
}

FieldInput read_field_input(const std::string& input, const FieldArgs& args)
{
    const std::string& spec = args.spec;
    const std::string field_name = parse_field_choice(args.name).name;
    FieldSeriesOptions series_options = args.series;
    FieldInput in;
    if (is_vtk_path(input))
        in.data = read_polydata(input);
    else
        in.data.mesh = read_raw_mesh(input);
    in.fields = in.data.point_data;
    in.fields.insert(in.fields.end(), in.data.cell_data.begin(), in.data.cell_data.end());
    if (spec.empty())
    {
        if (!field_name.empty())
            find_field(in.fields, field_name);
        return in;
    }
    series_options.name = field_name;
    in.series = read_field_series(spec, in.data, series_options);
    if (!field_name.empty())
        for (auto& step : in.series.steps)
            step = {find_field(step, field_name)};
    return in;
}

}  // namespace vessel::cli
