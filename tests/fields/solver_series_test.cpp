// Series written the way a CFD solver (svFSI) writes them: .vtu volume files whose points come in
// another order than the wall's, with WSS (3 components), Pressure and GlobalNodeID; built here
// with VTK's C++ writers, read with read_field_series() and checked against the function that
// generated the values.
#include <doctest/doctest.h>

#include "support/checks.h"
#include "support/ensight.h"
#include "support/files.h"
#include "vessel/check/validation.h"
#include "vessel/core/errors.h"
#include "vessel/fields/field_series.h"
#include "vessel/io/flat_vtk.h"
#include "vessel/phantom/phantom.h"
#include "vessel/pipeline.h"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLPolyDataWriter.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <random>
#include <string>

using namespace vessel;
using vessel::test::temp_dir;
using vessel::test::contains;
using vessel::test::error_of;

namespace {

// The generating functions of the solver's arrays at point p and time t.
Eigen::Vector3d wss_at(const Eigen::Vector3d& p, double t)
{
    return {std::sin(0.3 * p.y()) + t, std::cos(0.2 * p.z()) - t, 0.1 * p.x() * t};
}

double pressure_at(const Eigen::Vector3d& p, double t)
{
    return 0.5 * p.x() - 0.25 * p.y() + 0.1 * p.z() + 10.0 * t;
}

// The wall's ids: not 0..n-1, so that pairing by row number would be caught.
int wall_id(int v) { return 7 * v + 100; }
int face_model_id(int f) { return 1 + f % 3; }

struct Wall
{
    Mesh mesh;
    PolyData data;  // with GlobalNodeID
};

Wall make_wall()
{
    Wall w;
    CarotidPhantomOptions carotid;
    carotid.edge_length = 1.0;
    w.mesh = carotid_phantom(carotid);
    w.data.mesh = to_raw_mesh(w.mesh);
    const auto n = static_cast<Eigen::Index>(w.data.mesh.points.size());
    Field id{"GlobalNodeID", FieldLocation::Point, FieldType::Int32, Eigen::MatrixXd(n, 1)};
    for (Eigen::Index v = 0; v < n; ++v)
        id.values(v, 0) = wall_id(static_cast<int>(v));
    w.data.point_data = {id};
    return w;
}

// How a step file deviates from a faithful solver output.
struct StepFaults
{
    std::vector<int> foreign_ids;  // wall vertices written with an id the wall does not have
    std::vector<int> moved;        // wall vertices written 1 mm away from where they are
};

// Point arrays of a step: the wall's points in order \p order, then \p extra points.
void add_point_arrays(vtkPointData* pd, const std::vector<Eigen::Vector3d>& points,
                      const std::vector<int>& ids, double t)
{
    vtkNew<vtkDoubleArray> wss, pressure;
    vtkNew<vtkIntArray> gid;
    wss->SetName("WSS");
    wss->SetNumberOfComponents(3);
    pressure->SetName("Pressure");
    gid->SetName("GlobalNodeID");
    for (std::size_t i = 0; i < points.size(); ++i)
    {
        const Eigen::Vector3d w = wss_at(points[i], t);
        wss->InsertNextTuple(w.data());
        pressure->InsertNextValue(pressure_at(points[i], t));
        gid->InsertNextValue(ids[i]);
    }
    pd->AddArray(wss);
    pd->AddArray(pressure);
    pd->AddArray(gid);
}

// The wall's points in a shuffled order (file row r holds wall vertex order[r]), then, for a
// volume, interior points on the vessel's axis region with ids the wall does not use.
struct StepPoints
{
    std::vector<int> order;
    std::vector<Eigen::Vector3d> points;
    std::vector<int> ids;
    std::vector<int> row_of;  // file row of each wall vertex
};

StepPoints step_points(const Wall& w, unsigned seed, int interior, const StepFaults& faults)
{
    StepPoints s;
    const int n = static_cast<int>(w.data.mesh.points.size());
    s.order.resize(n);
    std::iota(s.order.begin(), s.order.end(), 0);
    std::shuffle(s.order.begin(), s.order.end(), std::mt19937(seed));
    s.row_of.resize(n);
    for (int r = 0; r < n; ++r)
    {
        const int v = s.order[r];
        s.row_of[v] = r;
        Eigen::Vector3d p = w.data.mesh.points[v];
        if (std::find(faults.moved.begin(), faults.moved.end(), v) != faults.moved.end())
            p.x() += 1.0;
        s.points.push_back(p);
        const bool foreign = std::find(faults.foreign_ids.begin(), faults.foreign_ids.end(), v) !=
                             faults.foreign_ids.end();
        s.ids.push_back(foreign ? 5000000 + v : wall_id(v));
    }
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    for (const auto& p : w.data.mesh.points)
        centre += p / n;
    for (int j = 0; j < interior; ++j)
    {
        s.points.push_back(centre + Eigen::Vector3d(0.1 * j, 0.05 * j, -0.02 * j));
        s.ids.push_back(9000000 + j);
    }
    return s;
}

vtkSmartPointer<vtkPoints> vtk_points(const std::vector<Eigen::Vector3d>& from)
{
    auto points = vtkSmartPointer<vtkPoints>::New();
    points->SetDataTypeToDouble();
    for (const auto& p : from)
        points->InsertNextPoint(p.data());
    return points;
}

template <class Writer>
void write_with(vtkDataObject* data, const std::string& path)
{
    vtkNew<Writer> writer;
    writer->SetInputData(data);
    writer->SetFileName(path.c_str());
    REQUIRE(writer->Write() == 1);
}

// A volume step as svFSI writes it: one tetrahedron on each wall triangle and an interior point.
void write_vtu(const std::string& path, const Wall& w, double t, unsigned seed,
               const StepFaults& faults = {})
{
    const int interior = 40;
    const StepPoints s = step_points(w, seed, interior, faults);
    const int n = static_cast<int>(w.data.mesh.points.size());
    const auto points = vtk_points(s.points);
    vtkNew<vtkUnstructuredGrid> grid;
    grid->SetPoints(points);
    vtkNew<vtkIntArray> model;
    model->SetName("ModelFaceID");
    for (std::size_t f = 0; f < w.data.mesh.faces.size(); ++f)
    {
        const auto& face = w.data.mesh.faces[f];
        const vtkIdType tet[4] = {s.row_of[face[0]], s.row_of[face[1]], s.row_of[face[2]],
                                  n + static_cast<vtkIdType>(f % interior)};
        grid->InsertNextCell(VTK_TETRA, 4, tet);
        model->InsertNextValue(face_model_id(static_cast<int>(f)));
    }
    grid->GetCellData()->AddArray(model);
    add_point_arrays(grid->GetPointData(), s.points, s.ids, t);
    write_with<vtkXMLUnstructuredGridWriter>(grid, path);
}

// The wall alone with its points and its triangles both shuffled, cell array ModelFaceID.
void write_shuffled_vtp(const std::string& path, const Wall& w, double t, unsigned seed)
{
    const StepPoints s = step_points(w, seed, 0, {});
    const auto points = vtk_points(s.points);
    std::vector<int> faces(w.data.mesh.faces.size());
    std::iota(faces.begin(), faces.end(), 0);
    std::shuffle(faces.begin(), faces.end(), std::mt19937(seed + 1));
    vtkNew<vtkCellArray> polys;
    vtkNew<vtkIntArray> model;
    model->SetName("ModelFaceID");
    for (int f : faces)
    {
        const auto& face = w.data.mesh.faces[f];
        // Each triangle starts at another corner than the wall's: only the corner set matches.
        const vtkIdType tri[3] = {s.row_of[face[1]], s.row_of[face[2]], s.row_of[face[0]]};
        polys->InsertNextCell(3, tri);
        model->InsertNextValue(face_model_id(f));
    }
    vtkNew<vtkPolyData> poly;
    poly->SetPoints(points);
    poly->SetPolys(polys);
    poly->GetCellData()->AddArray(model);
    add_point_arrays(poly->GetPointData(), s.points, s.ids, t);
    write_with<vtkXMLPolyDataWriter>(poly, path);
}

// run.pvd with run/run_000.vtu, run/run_001.vtu at \p times, as svFSI's series.
std::string write_run(const std::string& dir, const Wall& w, const std::vector<double>& times)
{
    std::filesystem::create_directories(dir + "/run");
    std::string xml = "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n"
                      "<Collection>\n";
    for (std::size_t k = 0; k < times.size(); ++k)
    {
        const std::string name = "run/run_00" + std::to_string(k) + ".vtu";
        write_vtu(dir + "/" + name, w, times[k], 11u + static_cast<unsigned>(k));
        xml += "<DataSet timestep=\"" + std::to_string(times[k]) + "\" part=\"0\" file=\"" +
               name + "\"/>\n";
    }
    xml += "</Collection>\n</VTKFile>\n";
    std::ofstream(dir + "/run.pvd") << xml;
    return dir + "/run.pvd";
}

// Every vertex of \p points carries the generated WSS and Pressure at time \p t.
void check_values(const std::vector<Field>& step, const std::vector<Eigen::Vector3d>& points,
                  double t, double tolerance = 1e-12)
{
    const Field& wss = find_field(step, "WSS");
    const Field& pressure = find_field(step, "Pressure");
    REQUIRE(wss.components() == 3);
    REQUIRE(wss.rows() == static_cast<Eigen::Index>(points.size()));
    double worst = 0;
    for (std::size_t v = 0; v < points.size(); ++v)
    {
        const auto i = static_cast<Eigen::Index>(v);
        worst = std::max(worst, (wss.values.row(i).transpose() - wss_at(points[v], t)).norm());
        worst = std::max(worst, std::abs(pressure.values(i, 0) - pressure_at(points[v], t)));
    }
    CHECK(worst <= tolerance);
}

// Point array \p name of an EnSight step as a Field.
Field point_field(vtkUnstructuredGrid* grid, const std::string& name)
{
    vtkDataArray* a = grid->GetPointData()->GetArray(name.c_str());
    REQUIRE_MESSAGE(a != nullptr, name);
    Field f{name, FieldLocation::Point, FieldType::Float64,
            Eigen::MatrixXd(a->GetNumberOfTuples(), a->GetNumberOfComponents())};
    for (vtkIdType i = 0; i < a->GetNumberOfTuples(); ++i)
        for (int c = 0; c < a->GetNumberOfComponents(); ++c)
            f.values(i, c) = a->GetComponent(i, c);
    return f;
}

}  // namespace

TEST_CASE("solver series: .vtu volumes in another point order are paired by GlobalNodeID")
{
    const std::string dir = temp_dir("solver_vtu");
    const Wall w = make_wall();
    const std::string pvd = write_run(dir, w, {1.8, 1.85});
    const TimeSeries series = read_field_series(pvd, w.data);
    REQUIRE(series.size() == 2);
    CHECK(series.times[0] == doctest::Approx(1.8));
    CHECK(series.times[1] == doctest::Approx(1.85));
    for (int k = 0; k < 2; ++k)
    {
        INFO("step " << k);
        check_values(series.steps[k], w.data.mesh.points, series.times[k]);
        // Paired by it, GlobalNodeID equals the wall's own and is not repeated in the steps.
        CHECK_THROWS_AS(find_field(series.steps[k], "GlobalNodeID"), InvalidInputError);
    }
    // The tetrahedra's ModelFaceID cannot be placed on the wall: left out, and said so.
    CHECK_THROWS_AS(find_field(series.steps[0], "ModelFaceID"), InvalidInputError);
    REQUIRE(series.notes.size() == 1);
    CHECK_MESSAGE(contains(series.notes[0], "ModelFaceID"), series.notes[0]);

    // Through the cut: every cut vertex (seam copies too) carries the values of its 3D point.
    FlattenOptions options;
    options.refinement = Refinement::None;
    const FlattenResult result = flatten(make_tree_surface(w.data.mesh).mesh, options);
    const TimeSeries cut = transfer_series(series, result.mesh);
    std::vector<Eigen::Vector3d> cut_points;
    for (auto v : result.mesh.vertices())
        cut_points.push_back(to_eigen(result.mesh.point(v)));
    REQUIRE(cut_points.size() > w.data.mesh.points.size());  // the seam's copies
    check_values(cut.steps[1], cut_points, 1.85);

    // The same files paired by position, for a wall that has no ids.
    PolyData bare = w.data;
    bare.point_data.clear();
    FieldSeriesOptions by_position;
    by_position.match_by = "position";
    const TimeSeries positioned = read_field_series(pvd, bare, by_position);
    for (int k = 0; k < 2; ++k)
        check_values(positioned.steps[k], w.data.mesh.points, positioned.times[k]);
    // Without ids on both sides and without --match-by, the file order is taken and refused.
    const std::string e = error_of([&] { read_field_series(pvd, bare); });
    CHECK_MESSAGE(contains(e, "--match-by GlobalNodeID or position"), e);

    // A volume is no wall: refused as the input mesh, with what to give instead.
    const std::string volume = error_of([&] { read_polydata(dir + "/run/run_000.vtu"); });
    CHECK_MESSAGE(contains(volume, "holds volume cells"), volume);
}

TEST_CASE("solver series: a shuffled .vtp carries its point and cell arrays to the right places")
{
    const std::string dir = temp_dir("solver_vtp");
    const Wall w = make_wall();
    write_shuffled_vtp(dir + "/wall-result.vtp", w, 0.5, 3);
    const TimeSeries series = read_field_series(dir + "/wall-result.vtp", w.data);
    REQUIRE(series.size() == 1);
    check_values(series.steps[0], w.data.mesh.points, 0.5);
    CHECK(series.notes.empty());
    const Field& model = find_field(series.steps[0], "ModelFaceID");
    CHECK(model.location == FieldLocation::Cell);
    REQUIRE(model.rows() == static_cast<Eigen::Index>(w.data.mesh.faces.size()));
    int wrong = 0;
    for (Eigen::Index f = 0; f < model.rows(); ++f)
        wrong += model.values(f, 0) != face_model_id(static_cast<int>(f));
    CHECK(wrong == 0);
}

TEST_CASE("solver series: unpaired points are refused with their count, never guessed")
{
    const std::string dir = temp_dir("solver_unpaired");
    const Wall w = make_wall();
    const int n = static_cast<int>(w.data.mesh.points.size());

    StepFaults foreign;
    foreign.foreign_ids = {4, 50, 51};
    write_vtu(dir + "/foreign.vtu", w, 0.0, 5, foreign);
    std::string e = error_of([&] { read_field_series(dir + "/foreign.vtu", w.data); });
    CHECK_MESSAGE(contains(e, "3 of the mesh's " + std::to_string(n) +
                                  " vertices have a GlobalNodeID the step does not hold"),
                  e);
    CHECK_MESSAGE(contains(e, "vertex 4: " + std::to_string(wall_id(4))), e);

    StepFaults moved;
    moved.moved = {1, 2, 30, 31};
    write_vtu(dir + "/moved.vtu", w, 0.0, 6, moved);
    FieldSeriesOptions by_position;
    by_position.match_by = "position";
    e = error_of([&] { read_field_series(dir + "/moved.vtu", w.data, by_position); });
    CHECK_MESSAGE(contains(e, "4 of the mesh's " + std::to_string(n) +
                                  " vertices have no step point within"),
                  e);
    // Paired by id, the moved points are found, and refused for being elsewhere.
    e = error_of([&] { read_field_series(dir + "/moved.vtu", w.data); });
    CHECK_MESSAGE(contains(e, "is paired with point"), e);
    // An id array that one side lacks.
    FieldSeriesOptions by_other;
    by_other.match_by = "NodeLabel";
    e = error_of([&] { read_field_series(dir + "/moved.vtu", w.data, by_other); });
    CHECK_MESSAGE(contains(e, "needs the point array 'NodeLabel'"), e);
}

TEST_CASE("solver series: vessel-flatten takes an svFSI-style .pvd of .vtu files")
{
    const std::string kFlatten = VESSEL_FLATTEN_EXE;
    const std::string dir = temp_dir("solver_cli");
    const Wall w = make_wall();
    write_polydata(dir + "/wall.vtp", w.data);
    const std::string pvd = write_run(dir, w, {1.8, 1.85});
    REQUIRE(vessel::test::run(kFlatten + " " + dir + "/wall.vtp -o " + dir +
                              "/flat.vtp --refine none --fields " + pvd + " 2> " + dir +
                              "/stderr.txt") == 0);
    const std::string log = vessel::test::read_bytes(dir + "/stderr.txt");
    CHECK_MESSAGE(contains(log, "note: " + pvd + ": the cell arrays ModelFaceID"), log);
    // The series as EnSight cases (32-bit floats): the values at each cut vertex's input point.
    const vessel::test::EnSightCase wall(dir + "/flat.case"), map(dir + "/flat-map.case");
    REQUIRE(wall.times().size() == 2);
    REQUIRE(map.times().size() == 2);
    for (int k = 0; k < 2; ++k)
    {
        const double t = k == 0 ? 1.8 : 1.85;
        CHECK(wall.times()[k] == doctest::Approx(t).epsilon(1e-7));
        const auto grid = wall.step(k);
        const Field input = point_field(grid, "InputVertex");
        std::vector<Eigen::Vector3d> points;
        for (Eigen::Index i = 0; i < input.rows(); ++i)
            points.push_back(w.data.mesh.points[static_cast<std::size_t>(input.values(i, 0))]);
        check_values({point_field(grid, "WSS"), point_field(grid, "Pressure")}, points, t, 1e-5);
        // The map's step: WSS as map vectors (in its plane), in its own case.
        const auto flat = map.step(k);
        const Field wss = point_field(flat, "WSS");
        CHECK(wss.values.col(2).cwiseAbs().maxCoeff() == 0.0);
        CHECK(wss.values.leftCols(2).rowwise().norm().maxCoeff() > 0.1);
        CHECK(flat->GetCellData()->GetArray("LogAreaRatio") != nullptr);
        CHECK(grid->GetCellData()->GetArray("LogAreaRatio") == nullptr);
    }

    // --field NAME:x draws a component; a component the array lacks is refused before any work.
    REQUIRE(vessel::test::run(kFlatten + " " + dir + "/wall.vtp -o " + dir +
                              "/x.vtp --refine none -q --fields " + pvd +
                              " --field WSS:x --image " + dir + "/x.png 2> " + dir +
                              "/stderr.txt") == 0);
    CHECK(std::filesystem::file_size(dir + "/x.png") > 1000);
    for (const std::string& bad : {"Pressure:y", "WSS:w"})
    {
        INFO(bad);
        CHECK(vessel::test::run(kFlatten + " " + dir + "/wall.vtp -o " + dir +
                                "/bad.vtp --refine none -q --fields " + pvd + " --field " + bad +
                                " --image " + dir + "/bad.png 2> " + dir + "/stderr.txt") == 1);
        CHECK_FALSE(std::filesystem::exists(dir + "/bad.vtp"));
    }
    CHECK(contains(vessel::test::read_bytes(dir + "/stderr.txt"), "'w' is not magnitude, x, y or z"));

    // One wall id missing from the solver's files: exit 1, the count, and no output left.
    StepFaults foreign;
    foreign.foreign_ids = {9};
    write_vtu(dir + "/run/run_001.vtu", w, 1.85, 12, foreign);
    REQUIRE(vessel::test::run(kFlatten + " " + dir + "/wall.vtp -o " + dir +
                              "/again.vtp --refine none -q --fields " + pvd + " 2> " + dir +
                              "/stderr.txt") == 1);
    const std::string refusal = vessel::test::read_bytes(dir + "/stderr.txt");
    CHECK_MESSAGE(contains(refusal, "step 1 of " + pvd), refusal);
    CHECK_MESSAGE(contains(refusal, "1 of the mesh's"), refusal);
    CHECK_FALSE(std::filesystem::exists(dir + "/again.vtp"));
    CHECK_FALSE(std::filesystem::exists(dir + "/again.pvd"));
}

TEST_CASE("solver series: --match-tolerance sets how far a paired point may lie from its vertex")
{
    // Four points of the solver's file written 1 mm from their wall vertices: paired by
    // GlobalNodeID, they are refused at the default tolerance (1e-5 of the wall's bounding-box
    // diagonal) and taken at a tolerance above 1 mm.
    const std::string kFlatten = VESSEL_FLATTEN_EXE;
    const std::string dir = temp_dir("solver_match_tolerance");
    const Wall w = make_wall();
    write_polydata(dir + "/wall.vtp", w.data);
    StepFaults moved;
    moved.moved = {1, 2, 30, 31};
    write_vtu(dir + "/moved.vtu", w, 0.0, 6, moved);
    Eigen::Vector3d lo = w.data.mesh.points.front(), hi = lo;
    for (const Eigen::Vector3d& p : w.data.mesh.points)
    {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
    }
    const double diagonal = (hi - lo).norm();
    const std::string flatten = kFlatten + " " + dir + "/wall.vtp --refine none -q --fields " +
                                dir + "/moved.vtu -o " + dir;
    CHECK(vessel::test::run(flatten + "/strict.vtp 2> " + dir + "/stderr.txt") == 1);
    const std::string refusal = vessel::test::read_bytes(dir + "/stderr.txt");
    CHECK_MESSAGE(contains(refusal, "is paired with point"), refusal);
    CHECK_FALSE(std::filesystem::exists(dir + "/strict.vtp"));
    const std::string tolerance = std::to_string(2.0 / diagonal);  // 2 mm
    CHECK(vessel::test::run(flatten + "/loose.vtp --match-tolerance " + tolerance + " 2> " + dir +
                            "/stderr.txt") == 0);
    CHECK(std::filesystem::exists(dir + "/loose.vtp"));
}
