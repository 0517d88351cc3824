#include <doctest/doctest.h>

#include "support/checks.h"
#include "support/ensight.h"
#include "vessel/core/errors.h"
#include "vessel/io/ensight.h"

#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkPointData.h>

#include <filesystem>
#include <set>
#include <string>
#include <vector>

using namespace vessel;
using vessel::test::temp_dir;

namespace {

namespace fs = std::filesystem;

// A strip of 2 x n triangles over n + 1 columns of 2 points each.
PolyData strip(int n)
{
    PolyData data;
    for (int i = 0; i <= n; ++i)
        for (int j = 0; j < 2; ++j)
            data.mesh.points.emplace_back(0.5 * i, j, 0.1 * i * i);
    for (int i = 0; i < n; ++i)
    {
        data.mesh.faces.push_back({2 * i, 2 * i + 2, 2 * i + 1});
        data.mesh.faces.push_back({2 * i + 1, 2 * i + 2, 2 * i + 3});
    }
    return data;
}

Field field(const std::string& name, FieldLocation where, Eigen::MatrixXd values)
{
    return {name, where, FieldType::Float64, std::move(values)};
}

// Step k's fields at time t: a point vector and a cell scalar that depend on both.
std::vector<Field> step_fields(const PolyData& data, double t)
{
    const auto np = static_cast<Eigen::Index>(data.mesh.points.size());
    const auto nf = static_cast<Eigen::Index>(data.mesh.faces.size());
    Eigen::MatrixXd wss(np, 3), q(nf, 1);
    for (Eigen::Index i = 0; i < np; ++i)
        wss.row(i) << t, 0.25 * i, -1.0 / (1.0 + i);
    for (Eigen::Index f = 0; f < nf; ++f)
        q(f, 0) = t * f;
    return {field("wall shear", FieldLocation::Point, wss), field("Q", FieldLocation::Cell, q)};
}

std::vector<std::string> names(vtkFieldData* data)
{
    std::vector<std::string> out;
    for (int i = 0; i < data->GetNumberOfArrays(); ++i)
        out.emplace_back(data->GetArrayName(i));
    return out;
}

}  // namespace

TEST_CASE("ensight: a series is written with its geometry once and read back by VTK with its "
          "times and values")
{
    const std::string dir = temp_dir("ensight_series");
    PolyData data = strip(5);
    const auto np = static_cast<Eigen::Index>(data.mesh.points.size());
    const auto nf = static_cast<Eigen::Index>(data.mesh.faces.size());
    Eigen::MatrixXd id(np, 1), uv(np, 2), tensor(np, 4), cell(nf, 1);
    for (Eigen::Index i = 0; i < np; ++i)
    {
        id(i, 0) = 1000 + i;
        uv.row(i) << 2.0 * i, -3.0 * i;
        tensor.row(i) << i, i + 0.5, i + 0.25, i + 0.125;
    }
    for (Eigen::Index f = 0; f < nf; ++f)
        cell(f, 0) = 7 * f;
    data.point_data = {field("2d id", FieldLocation::Point, id),
                       field("uv", FieldLocation::Point, uv),
                       field("T", FieldLocation::Point, tensor)};
    data.cell_data = {field("InputCell", FieldLocation::Cell, cell)};
    TimeSeries series;
    series.times = {1.8, 1.85, 1.9};
    for (double t : series.times)
        series.steps.push_back(step_fields(data, t));

    write_ensight_series(dir + "/run.case", data, series);

    // One geometry file, one file per static variable (T: 4 scalars), one per step variable
    // and step; names without spaces or a leading digit.
    std::set<std::string> files;
    for (const auto& e : fs::directory_iterator(dir + "/run"))
        files.insert(e.path().filename().string());
    CHECK(files == std::set<std::string>{"run.geo", "run._2d_id", "run.uv", "run.T_0", "run.T_1",
                                         "run.T_2", "run.T_3", "run.InputCell",
                                         "run.wall_shear.0000", "run.wall_shear.0001",
                                         "run.wall_shear.0002", "run.Q.0000", "run.Q.0001",
                                         "run.Q.0002"});

    const vessel::test::EnSightCase read(dir + "/run.case");
    REQUIRE(read.times().size() == 3);
    for (int k = 0; k < 3; ++k)  // VTK's reader parses the case file's times as floats
        CHECK(read.times()[k] == doctest::Approx(series.times[k]).epsilon(1e-7));

    for (int k = 0; k < 3; ++k)
    {
        CAPTURE(k);
        const auto grid = read.step(k);
        REQUIRE(grid->GetNumberOfPoints() == np);
        REQUIRE(grid->GetNumberOfCells() == nf);
        for (Eigen::Index i = 0; i < np; ++i)
            for (int c = 0; c < 3; ++c)
                CHECK(grid->GetPoint(i)[c] == static_cast<float>(data.mesh.points[i][c]));
        for (Eigen::Index f = 0; f < nf; ++f)
        {
            vtkIdType n = 0;
            const vtkIdType* corners = nullptr;
            grid->GetCellPoints(f, n, corners);
            REQUIRE(n == 3);
            for (int c = 0; c < 3; ++c)
                CHECK(corners[c] == data.mesh.faces[f][c]);
        }
        vtkPointData* pd = grid->GetPointData();
        const std::vector<std::string> point_names = names(pd);
        CHECK(std::set<std::string>(point_names.begin(), point_names.end()) ==
              std::set<std::string>{"_2d_id", "uv", "T_0", "T_1", "T_2", "T_3", "wall_shear"});
        const std::vector<Field> expected = step_fields(data, series.times[k]);
        vtkDataArray* wss = pd->GetArray("wall_shear");
        REQUIRE(wss->GetNumberOfComponents() == 3);
        vtkDataArray* got_uv = pd->GetArray("uv");
        REQUIRE(got_uv->GetNumberOfComponents() == 3);
        for (Eigen::Index i = 0; i < np; ++i)
        {
            CHECK(pd->GetArray("_2d_id")->GetComponent(i, 0) == id(i, 0));
            for (int c = 0; c < 3; ++c)
                CHECK(wss->GetComponent(i, c) == static_cast<float>(expected[0].values(i, c)));
            CHECK(got_uv->GetComponent(i, 0) == uv(i, 0));
            CHECK(got_uv->GetComponent(i, 1) == uv(i, 1));
            CHECK(got_uv->GetComponent(i, 2) == 0.0);
            for (int c = 0; c < 4; ++c)
                CHECK(pd->GetArray(("T_" + std::to_string(c)).c_str())->GetComponent(i, 0) ==
                      tensor(i, c));
        }
        vtkCellData* cd = grid->GetCellData();
        for (Eigen::Index f = 0; f < nf; ++f)
        {
            CHECK(cd->GetArray("InputCell")->GetComponent(f, 0) == cell(f, 0));
            CHECK(cd->GetArray("Q")->GetComponent(f, 0) ==
                  static_cast<float>(expected[1].values(f, 0)));
        }
    }
}

TEST_CASE("ensight: what does not fit is refused before the case file is written")
{
    const std::string dir = temp_dir("ensight_refused");
    const PolyData data = strip(3);
    TimeSeries series;
    series.times = {0.0, 0.5};
    series.steps = {step_fields(data, 0.0), step_fields(data, 0.5)};
    const auto refused = [&](const PolyData& d, const TimeSeries& s, const std::string& what) {
        CAPTURE(what);
        try
        {
            write_ensight_series(dir + "/bad.case", d, s);
            FAIL("not refused");
        }
        catch (const InvalidInputError& e)
        {
            CHECK_MESSAGE(std::string(e.what()).find(what) != std::string::npos, e.what());
        }
        CHECK(!fs::exists(dir + "/bad.case"));
    };
    PolyData quad = data;
    quad.mesh.faces[1].push_back(0);
    refused(quad, series, "polygon 1 has 4 vertices");
    refused(data, TimeSeries{}, "the series has no steps");
    TimeSeries renamed = series;
    renamed.steps[1][0].name = "WSS";
    refused(data, renamed, "step 1 has other fields than step 0");
    TimeSeries short_rows = series;
    short_rows.steps[1][1].values.conservativeResize(2, 1);
    refused(data, short_rows, "field 'Q' of step 1 has 2 rows but the mesh has 6 triangles");
    TimeSeries one_time_short = series;
    one_time_short.times.pop_back();
    refused(data, one_time_short, "the series has 1 times but 2 steps");
    EnSightOptions spaced;
    spaced.folder = "my data";
    try
    {
        write_ensight_series(dir + "/bad.case", data, series, spaced);
        FAIL("not refused");
    }
    catch (const InvalidInputError& e)
    {
        CHECK_MESSAGE(std::string(e.what()).find("has white space") != std::string::npos, e.what());
    }
    CHECK(!fs::exists(dir + "/my data"));
}
