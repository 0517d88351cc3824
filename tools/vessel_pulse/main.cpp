// vessel-pulse: a synthetic travelling WSS-like pulse over an existing vessel surface (e.g. a real
// mesh), written as a time series that vessel-flatten --fields and vessel-view --fields read.
#include "../vessel_phantom/pulse_files.h"
#include "vessel/core/errors.h"
#include "vessel/io/io.h"
#include "vessel/core/properties.h"
#include "vessel/fields/pulse_series.h"
#include "vessel/check/validation.h"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>
#include <string>

namespace {

// The pulse of the surface (rows = its vertices) moved to the rows of the input file's points;
// points that no face uses keep the base value (a vector: zero).
vessel::TimeSeries on_input_points(const vessel::TimeSeries& pulse, const vessel::Mesh& mesh,
                                   int points, double base)
{
    OpenMesh::VPropHandleT<int> input_index;
    if (!mesh.get_property_handle(input_index, vessel::prop::input_index))
        throw vessel::InvalidInputError("the surface has no input vertex numbers");
    vessel::TimeSeries out = pulse;
    for (auto& step : out.steps)
        for (auto& field : step)
        {
            const Eigen::Index cols = field.values.cols();
            Eigen::MatrixXd values = Eigen::MatrixXd::Constant(points, cols, cols == 1 ? base : 0.0);
            for (auto v : mesh.vertices())
                values.row(mesh.property(input_index, v)) = field.values.row(v.idx());
            field.values = std::move(values);
        }
    return out;
}

}  // namespace

int main(int argc, char** argv)
{
    CLI::App app{"Write a synthetic travelling wall-shear-stress-like pulse over a vessel surface "
                 "(not a flow result): value = base + peak exp(-(s - c(t))^2 / (2 width^2)) Pa, "
                 "s = geodesic distance from the inlet over its maximum, the centre c sweeping "
                 "from the inlet to the outlets once per period. Writes PREFIX.pvd (+ "
                 "PREFIX/PREFIX_NNN.vtp), PREFIX.csv (wide) and PREFIX-long.csv, over the points "
                 "of INPUT in file order (docs/fields.md).",
                 "vessel-pulse"};
    std::string input, prefix;
    vessel::PulseSeriesOptions pulse;
    bool quiet = false;
    app.add_option("input", input, "Vessel surface (.obj, .off, .ply, .stl, .vtp, .vtk)")
        ->required()
        ->check(CLI::ExistingFile);
    app.add_option("prefix", prefix, "Output prefix")->required();
    app.add_option("--name", pulse.name, "Field name")->capture_default_str();
    app.add_option("--steps", pulse.steps, "Time steps")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    app.add_option("--duration", pulse.duration_s, "Length of the series (s)")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    app.add_option("--period", pulse.period_s, "One beat (s)")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    app.add_flag("--vector", pulse.vector,
                 "A 3-component array: the value times the direction away from the inlet along "
                 "the wall, as a wall shear stress vector points (drawn as arrows by "
                 "vessel-flatten --image-arrows); .pvd only, the CSV files hold scalars");
    app.add_flag("-q,--quiet", quiet, "No summary line");
    try
    {
        app.parse(argc, argv);
    }
    catch (const CLI::ParseError& e)
    {
        return app.exit(e) == 0 ? 0 : 1;
    }
    try
    {
        const vessel::RawMesh raw = vessel::read_raw_mesh(input);
        const vessel::TreeSurface surface = vessel::make_tree_surface(raw);
        const vessel::TimeSeries series =
            on_input_points(vessel::travelling_pulse(surface.mesh, pulse), surface.mesh,
                            static_cast<int>(raw.points.size()), pulse.base_pa);
        vessel::cli::write_pulse_files(prefix, raw, series, pulse.name, !pulse.vector);
        if (!quiet)
            std::printf("pulse %s: %d steps over %g s on %zu points -> %s.pvd%s\n",
                        pulse.name.c_str(), series.size(), pulse.duration_s, raw.points.size(),
                        prefix.c_str(), pulse.vector ? "" : ", .csv, -long.csv");
        return 0;
    }
    catch (const std::exception& e)
    {
        std::fprintf(stderr, "vessel-pulse: %s\n", e.what());
        return 1;
    }
}
