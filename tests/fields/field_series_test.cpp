#include <doctest/doctest.h>

#include "support/checks.h"
#include "support/ensight.h"
#include "vessel/cut/boundary.h"
#include "vessel/core/errors.h"
#include "vessel/fields/field_series.h"
#include "vessel/io/flat_vtk.h"
#include "vessel/phantom/phantom.h"
#include "vessel/pipeline.h"
#include "vessel/core/properties.h"
#include "vessel/fields/pulse_series.h"
#include "vessel/check/validation.h"

#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkPointData.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

using namespace vessel;
using vessel::test::temp_dir;
using vessel::test::contains;
using vessel::test::error_of;

namespace {

// A small carotid phantom and the 90-step pulse on it, written as .pvd and CSV.
struct PulseFiles
{
    Mesh mesh;
    PolyData base;
    TimeSeries series;
    std::string dir;
};

PulseFiles pulse_files(const std::string& name)
{
    PulseFiles p;
    CarotidPhantomOptions carotid;
    carotid.edge_length = 1.0;
    p.mesh = carotid_phantom(carotid);
    p.base.mesh = to_raw_mesh(p.mesh);
    p.series = travelling_pulse(p.mesh);
    p.dir = temp_dir(name);
    write_pvd_series(p.dir + "/pulse.pvd", p.base, p.series);
    write_csv_series(p.dir + "/pulse.csv", p.series, "WSS", CsvLayout::Wide);
    write_csv_series(p.dir + "/pulse-long.csv", p.series, "WSS", CsvLayout::Long);
    return p;
}

void check_same_series(const TimeSeries& a, const TimeSeries& b)
{
    REQUIRE(a.size() == b.size());
    for (int k = 0; k < a.size(); ++k)
    {
        INFO("step " << k);
        CHECK(a.times[k] == doctest::Approx(b.times[k]).epsilon(1e-14));
        REQUIRE(a.steps[k].size() == 1);
        REQUIRE(b.steps[k].size() == 1);
        CHECK(a.steps[k][0].name == b.steps[k][0].name);
        CHECK(a.steps[k][0].values == b.steps[k][0].values);
    }
}

}  // namespace

TEST_CASE("field_series: the 90-step pulse reads back the same from .pvd, numbered files and CSV")
{
    const PulseFiles p = pulse_files("series_pulse");
    REQUIRE(p.series.size() == 90);
    CHECK(p.series.times[89] == doctest::Approx(1.78));
    // The pulse travels: mid-beat its peak (0.5 + 2.5 Pa) is on the wall, and it is further from
    // the inlet at 0.7 s than at 0.4 s.
    const Eigen::Vector3d inlet = boundary_loops(p.mesh)[0].centroid;
    double reach[2];
    for (int i : {0, 1})
    {
        const Eigen::VectorXd wss = p.series.steps[i == 0 ? 20 : 35][0].values.col(0);
        Eigen::Index top = 0;
        CHECK(wss.maxCoeff(&top) > 2.9);
        CHECK(wss.minCoeff() >= 0.5);
        reach[i] = (to_eigen(p.mesh.point(VertexHandle(static_cast<int>(top)))) - inlet).norm();
    }
    CHECK(reach[1] > reach[0] + 5.0);  // mm

    const TimeSeries pvd = read_field_series(p.dir + "/pulse.pvd", p.base);
    check_same_series(pvd, p.series);
    // A wide table has no room for the field's name: it is the file's stem unless given.
    CHECK(read_field_series(p.dir + "/pulse.csv", p.base).steps[0][0].name == "pulse");
    FieldSeriesOptions named;
    named.name = "WSS";
    const TimeSeries wide = read_field_series(p.dir + "/pulse.csv", p.base, named);
    check_same_series(wide, p.series);
    const TimeSeries longer = read_field_series(p.dir + "/pulse-long.csv", p.base);
    check_same_series(longer, p.series);
    FieldSeriesOptions every_50ms;
    every_50ms.time_step = 0.02;
    const TimeSeries numbered =
        read_field_series(p.dir + "/pulse/pulse_%03d.vtp", p.base, every_50ms);
    check_same_series(numbered, p.series);
    const TimeSeries glob = read_field_series(p.dir + "/pulse/pulse_*.vtp", p.base, every_50ms);
    check_same_series(glob, p.series);
}

TEST_CASE("field_series: a series carried through the cut is written as two EnSight cases, the "
          "3D cut mesh and the map, each with its geometry once")
{
    const PulseFiles p = pulse_files("series_flat");
    const TreeSurface surface = make_tree_surface(p.base.mesh);
    FlattenOptions options;
    options.refinement = Refinement::None;
    const FlattenResult result = flatten(surface.mesh, options);
    const TimeSeries in = read_field_series(p.dir + "/pulse-long.csv", p.base);
    const TimeSeries cut = transfer_series(in, result.mesh);
    write_flat_series(p.dir + "/flat.case", result.mesh, result.uv, {}, cut);
    const auto input_index = vessel::test::int_vertex_property(result.mesh, prop::input_index);
    std::size_t geometry_files = 0;
    for (const auto& e : std::filesystem::directory_iterator(p.dir + "/flat"))
        geometry_files += e.path().extension() == ".geo";
    CHECK(geometry_files == 2);  // flat.geo and flat-map.geo, not one per step
    for (const std::string name : {"flat", "flat-map"})
    {
        CAPTURE(name);
        const vessel::test::EnSightCase read(p.dir + "/" + name + ".case");
        REQUIRE(read.times().size() == 90);
        for (int k : {0, 17, 44, 89})
        {
            CAPTURE(k);
            CHECK(read.times()[k] == doctest::Approx(in.times[k]).epsilon(1e-7));
            const auto grid = read.step(k);
            REQUIRE(grid->GetNumberOfPoints() == static_cast<vtkIdType>(result.mesh.n_vertices()));
            vtkDataArray* wss = grid->GetPointData()->GetArray("WSS");
            REQUIRE(wss != nullptr);
            for (auto v : result.mesh.vertices())
            {
                const double expected = in.steps[k][0].values(input_index[v.idx()], 0);
                REQUIRE(wss->GetComponent(v.idx(), 0) == static_cast<float>(expected));
                const double* x = grid->GetPoint(v.idx());
                if (name == "flat-map")
                {
                    REQUIRE(x[0] == static_cast<float>(result.uv(v.idx(), 0)));
                    REQUIRE(x[1] == static_cast<float>(result.uv(v.idx(), 1)));
                    REQUIRE(x[2] == 0.0);
                }
                else
                    REQUIRE(x[2] == static_cast<float>(result.mesh.point(v)[2]));
            }
            CHECK((grid->GetCellData()->GetArray("LogAreaRatio") != nullptr) ==
                  (name == "flat-map"));
        }
    }
}

TEST_CASE("field_series: a series that does not match the mesh says what differs")
{
    const PulseFiles p = pulse_files("series_bad");
    const int n = static_cast<int>(p.base.mesh.points.size());
    const auto write = [&](const std::string& name, const std::string& text) {
        std::ofstream(p.dir + "/" + name) << text;
        return p.dir + "/" + name;
    };
    // CSV: a vertex missing, twice, out of range; a bad number; a short row; unordered times.
    std::string header = "vertex,0,0.5\n";
    std::string rows;
    for (int v = 0; v < n; ++v)
        if (v != 5 && v != 17)
            rows += std::to_string(v) + ",1,2\n";
    auto e = error_of([&] { read_field_series(write("missing.csv", header + rows), p.base); });
    CHECK_MESSAGE(contains(e, "has no value for 2 of the mesh's " + std::to_string(n) +
                                  " vertices (ids 5, 17)"),
                  e);
    e = error_of([&] { read_field_series(write("twice.csv", header + rows + "3,1,1\n"), p.base); });
    CHECK_MESSAGE(contains(e, "vertex 3 appears twice"), e);
    e = error_of([&] {
        read_field_series(write("range.csv", header + std::to_string(n) + ",1,1\n"), p.base);
    });
    CHECK_MESSAGE(
        contains(e, "line 2: vertex id " + std::to_string(n) + " is not an index of the mesh's"),
        e);
    e = error_of([&] { read_field_series(write("nan.csv", header + "0,1,abc\n"), p.base); });
    CHECK_MESSAGE(contains(e, "line 2, column 3 ('0.5'): 'abc' is not a number"), e);
    e = error_of([&] { read_field_series(write("short.csv", header + "0,1\n"), p.base); });
    CHECK_MESSAGE(contains(e, "line 2 has 2 columns but the header has 3"), e);
    e = error_of([&] { read_field_series(write("order.csv", "vertex,1,0.5\n" + rows), p.base); });
    CHECK_MESSAGE(contains(e, "order the columns by time"), e);
    e = error_of(
        [&] { read_field_series(write("long.csv", "vertex,time,WSS\n0,0,1\n1,0,1\n"), p.base); });
    CHECK_MESSAGE(contains(e, "long.csv at time 0 has no value for " + std::to_string(n - 2)), e);

    // VTK steps: another mesh, a moved point, a different id numbering, other arrays.
    PolyData other;
    other.mesh = to_raw_mesh(open_cylinder(1.0, 2.0, 8, 3));
    write_pvd_series(p.dir + "/other.pvd", other,
                     travelling_pulse(open_cylinder(1.0, 2.0, 8, 3)));
    e = error_of([&] { read_field_series(p.dir + "/other.pvd", p.base); });
    CHECK_MESSAGE(contains(e, "step 0 of " + p.dir + "/other.pvd"), e);
    CHECK_MESSAGE(
        contains(e, "has 32 points and 48 polygons but the mesh has " + std::to_string(n)), e);
    PolyData moved = p.base;
    moved.mesh.points[7].x() += 1.0;
    write_polydata(p.dir + "/moved.vtp", moved);
    e = error_of([&] { read_field_series(p.dir + "/moved.vtp", p.base); });
    CHECK_MESSAGE(contains(e, ": point 7 is at ("), e);
    PolyData ids = p.base;
    Field id{"GlobalNodeID", FieldLocation::Point, FieldType::Int32, Eigen::MatrixXd(n, 1)};
    for (int v = 0; v < n; ++v)
        id.values(v, 0) = v + 1;
    ids.point_data = {id};
    PolyData shuffled = ids;
    std::swap(shuffled.point_data[0].values(3, 0), shuffled.point_data[0].values(4, 0));
    write_polydata(p.dir + "/shuffled.vtp", shuffled);
    FieldSeriesOptions in_order;
    in_order.match_by = "order";
    e = error_of([&] { read_field_series(p.dir + "/shuffled.vtp", ids, in_order); });
    CHECK_MESSAGE(contains(e, "id array 'GlobalNodeID' has 5 at point 3 where the mesh has 4"), e);
    // Paired by GlobalNodeID (the default when both have it), vertex 3 meets the point at 4.
    e = error_of([&] { read_field_series(p.dir + "/shuffled.vtp", ids); });
    CHECK_MESSAGE(contains(e, "mesh vertex 3 at ("), e);
    CHECK_MESSAGE(contains(e, "is paired with point 4 at ("), e);
    e = error_of([&] { read_field_series(p.dir + "/pulse/pulse_%s.vtp", p.base); });
    CHECK_MESSAGE(contains(e, "must hold exactly one %d"), e);
    CHECK_THROWS_AS(read_field_series(p.dir + "/nothing_*.vtp", p.base), IoError);
    CHECK_THROWS_AS(read_field_series(p.dir + "/pulse.txt", p.base), InvalidInputError);
    FieldSeriesOptions bad;
    bad.time_step = 0;
    CHECK_THROWS_AS(read_field_series(p.dir + "/pulse.csv", p.base, bad), InvalidInputError);
    PulseSeriesOptions no_steps;
    no_steps.steps = 0;
    CHECK_THROWS_AS(travelling_pulse(p.mesh, no_steps), InvalidInputError);
}
