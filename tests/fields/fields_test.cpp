#include <doctest/doctest.h>

#include "support/checks.h"
#include "support/meshes.h"
#include "vessel/core/errors.h"
#include "vessel/fields/fields.h"
#include "vessel/fields/map_vectors.h"
#include "vessel/io/flat_vtk.h"
#include "vessel/pipeline.h"
#include "vessel/core/properties.h"
#include "vessel/check/validation.h"
#include "vessel/io/vtk_io.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

using namespace vessel;
using vessel::test::run;
using vessel::test::temp_dir;

namespace {

const std::string kData = VESSEL_SHARED_DATA;

std::vector<Field> all_fields(const PolyData& d)
{
    std::vector<Field> f = d.point_data;
    f.insert(f.end(), d.cell_data.begin(), d.cell_data.end());
    return f;
}

// Every cut vertex sits where its input vertex is and carries its row; every face's corners are
// corners of its input polygon and it carries the polygon's row. Returns the number of vertices
// that are seam copies (input vertex used more than once).
int check_carried(const PolyData& input, const Mesh& mesh, const std::vector<Field>& carried)
{
    const auto input_index = vessel::test::int_vertex_property(mesh, prop::input_index);
    const auto input_face = vessel::test::int_face_property(mesh, prop::input_face);
    const auto fields = all_fields(input);
    REQUIRE(carried.size() == fields.size());
    std::vector<int> uses(input.mesh.points.size(), 0);
    for (auto v : mesh.vertices())
    {
        const int i = input_index[v.idx()];
        ++uses[i];
        REQUIRE((to_eigen(mesh.point(v)) - input.mesh.points[i]).norm() == 0.0);
    }
    for (auto f : mesh.faces())
    {
        const auto& polygon = input.mesh.faces[input_face[f.idx()]];
        for (auto v : f.vertices())
            REQUIRE(std::count(polygon.begin(), polygon.end(), input_index[v.idx()]) == 1);
    }
    for (std::size_t k = 0; k < fields.size(); ++k)
    {
        INFO("field " << fields[k].name);
        const Field& in = fields[k];
        const Field& out = carried[k];
        CHECK(out.name == in.name);
        CHECK(out.type == in.type);
        if (in.location == FieldLocation::Point)
        {
            REQUIRE(out.rows() == static_cast<Eigen::Index>(mesh.n_vertices()));
            for (auto v : mesh.vertices())
                REQUIRE(out.values.row(v.idx()) == in.values.row(input_index[v.idx()]));
        }
        else
        {
            REQUIRE(out.rows() == static_cast<Eigen::Index>(mesh.n_faces()));
            for (auto f : mesh.faces())
                REQUIRE(out.values.row(f.idx()) == in.values.row(input_face[f.idx()]));
        }
    }
    int copies = 0;
    for (int u : uses)
        copies += std::max(0, u - 1);
    return copies;
}

// The written PolyData read back: same arrays at every point and cell, map at z = 0 on uv.
void check_written(const std::string& path, const FlattenResult& result,
                   const std::vector<Field>& carried)
{
    const PolyData solid = read_polydata(path);
    const PolyData map = read_polydata(map_path(path));
    REQUIRE(solid.mesh.points.size() == result.mesh.n_vertices());
    REQUIRE(map.mesh.points.size() == result.mesh.n_vertices());
    CHECK(solid.tcoords == uv_array);
    for (auto v : result.mesh.vertices())
    {
        REQUIRE(solid.mesh.points[v.idx()] == to_eigen(result.mesh.point(v)));
        REQUIRE(map.mesh.points[v.idx()] ==
                Eigen::Vector3d(result.uv(v.idx(), 0), result.uv(v.idx(), 1), 0.0));
    }
    // The map carries vectors as map vectors (map_fields()), everything else as it is.
    const std::vector<Field> on_map = map_fields(carried, result.mesh, result.uv);
    for (const PolyData* d : {&solid, &map})
    {
        CHECK(d->mesh.faces.size() == result.mesh.n_faces());
        CHECK(find_field(d->point_data, uv_array).values == Eigen::MatrixXd(result.uv));
        for (const auto& f : d == &map ? on_map : carried)
        {
            const auto& list = f.location == FieldLocation::Point ? d->point_data : d->cell_data;
            const Field& back = find_field(list, f.name);
            CHECK(back.type == f.type);
            // Float32 arrays are written as float: the values computed in double, rounded.
            CHECK(back.values == (f.type == FieldType::Float32
                                      ? Eigen::MatrixXd(f.values.cast<float>().cast<double>())
                                      : f.values));
        }
    }
}

}  // namespace

TEST_CASE("fields: seam copies get their original's values, faces keep their polygon's")
{
    const PolyData input = vessel::test::tube_with_fields(16, 10);
    const TreeSurface surface = make_tree_surface(input.mesh);
    FlattenOptions options;
    options.refinement = Refinement::None;  // the map's quality is not the point here
    const FlattenResult result = flatten(surface.mesh, options);
    REQUIRE(result.duplicated_vertices > 0);
    const auto carried = transfer_fields(all_fields(input), result.mesh);
    CHECK(check_carried(input, result.mesh, carried) == result.duplicated_vertices);

    const std::string dir = temp_dir("fields_tube");
    write_flat_vtp(dir + "/flat.vtp", result.mesh, result.uv, carried);
    check_written(dir + "/flat.vtp", result, carried);
    write_flat_ply(dir + "/flat.ply", result.mesh, result.uv, carried);
    // OpenMesh's PLY reader accepts it, and numpy's view of the binary PLY holds the same
    // values as VTK's Python reader sees in the .vtp.
    const RawMesh ply = read_raw_mesh(dir + "/flat.ply");
    CHECK(ply.points.size() == result.mesh.n_vertices());
    CHECK(ply.faces.size() == result.mesh.n_faces());
    std::ofstream(dir + "/ply.py") << R"(import sys, numpy as np, vtk
from vtk.util.numpy_support import vtk_to_numpy as np_of
data = open(sys.argv[1], "rb").read()
head, body = data.split(b"end_header\n", 1)
types = {"double": "<f8", "float": "<f4", "int": "<i4"}
elements, current = [], None
for line in head.decode().splitlines():
    w = line.split()
    if w[0] == "element":
        current = (w[1], int(w[2]), []); elements.append(current)
    elif w[0] == "property" and w[1] != "list":
        current[2].append((w[2], types[w[1]]))
(_, nv, vprops), (_, nf, fprops) = elements
vert = np.frombuffer(body, dtype=np.dtype(vprops), count=nv)
face = np.frombuffer(body, dtype=np.dtype([("n", "u1"), ("i", "<i4", 3)] + fprops), count=nf,
                     offset=vert.nbytes)
r = vtk.vtkXMLPolyDataReader(); r.SetFileName(sys.argv[2]); r.Update(); o = r.GetOutput()
pd, cd = o.GetPointData(), o.GetCellData()
xyz = np_of(o.GetPoints().GetData())
assert np.array_equal(np.stack([vert["x"], vert["y"], vert["z"]], 1), xyz)
assert np.array_equal(np.stack([vert["u"], vert["v"]], 1), np_of(pd.GetArray("uv")))
for name in ("InputVertex", "pressure", "GlobalNodeID"):
    assert np.array_equal(vert[name], np_of(pd.GetArray(name))), name
vel = np_of(pd.GetArray("velocity"))
for c in range(3):
    assert np.array_equal(vert["velocity_%d" % c], vel[:, c])
assert np.all(face["n"] == 3)
polys = np_of(o.GetPolys().GetConnectivityArray()).reshape(-1, 3)
assert np.array_equal(face["i"], polys)
# GlobalElementID is 64-bit (past 2^32 here): PLY has no such integer, it goes out as double.
for name in ("InputCell", "thickness", "GlobalElementID"):
    assert np.array_equal(face[name], np_of(cd.GetArray(name))), name
print("ok")
)";
    CHECK(run("/usr/bin/python3 " + dir + "/ply.py " + dir + "/flat.ply " + dir + "/flat.vtp") ==
          0);
}

TEST_CASE("fields: the pulmonary .vtp flattens with GlobalNodeID and GlobalElementID intact")
{
    const std::string path = kData + "/svfsi-tests/pulmonary-glenn-wall.vtp";
    REQUIRE_MESSAGE(std::filesystem::exists(path), "missing shared data: " << path);
    const PolyData input = read_polydata(path);
    REQUIRE(input.point_data.size() == 1);
    REQUIRE(input.cell_data.size() == 2);
    CHECK(input.point_data[0].name == "GlobalNodeID");
    CHECK(input.cell_data[0].name == "GlobalElementID");
    const TreeSurface surface = make_tree_surface(input.mesh);
    FlattenOptions options;
    options.refinement = Refinement::None;
    const FlattenResult result = flatten(surface.mesh, options);
    const auto carried = transfer_fields(all_fields(input), result.mesh);
    const int copies = check_carried(input, result.mesh, carried);
    CHECK(copies == result.duplicated_vertices);
    CHECK(copies > 0);
    MESSAGE("pulmonary: " << result.mesh.n_vertices() << " cut vertices (" << copies
                          << " seam copies), " << result.mesh.n_faces() << " faces");

    const std::string dir = temp_dir("fields_pulmonary");
    const std::string out = dir + "/pulmonary.vtp";
    write_flat_vtp(out, result.mesh, result.uv, carried);
    check_written(out, result, carried);
    // And ParaView's reader stack (python3-vtk9) sees the arrays and texture coordinates.
    const std::string script = dir + "/check.py";
    std::ofstream(script) << R"(import sys, vtk
for name, flat in ((sys.argv[1], False), (sys.argv[2], True)):
    r = vtk.vtkXMLPolyDataReader(); r.SetFileName(name); r.Update(); o = r.GetOutput()
    assert o.GetNumberOfPoints() == int(sys.argv[3]), o.GetNumberOfPoints()
    assert o.GetNumberOfPolys() == int(sys.argv[4])
    assert o.GetPointData().GetTCoords().GetName() == "uv"
    assert o.GetPointData().GetArray("GlobalNodeID").GetDataType() == vtk.VTK_INT
    assert o.GetCellData().GetArray("GlobalElementID").GetNumberOfTuples() == o.GetNumberOfPolys()
    if flat:
        b = o.GetBounds(); assert b[4] == 0 and b[5] == 0, b
)";
    CHECK(run("/usr/bin/python3 " + script + " " + out + " " + map_path(out) + " " +
              std::to_string(result.mesh.n_vertices()) + " " +
              std::to_string(result.mesh.n_faces())) == 0);
}

TEST_CASE("fields: mismatched fields and missing properties are refused with the counts")
{
    const PolyData input = vessel::test::tube_with_fields(16, 10);
    std::vector<Field> fields = all_fields(input);
    const int np = static_cast<int>(input.mesh.points.size());
    const int nf = static_cast<int>(input.mesh.faces.size());
    CHECK_NOTHROW(check_fields(fields, np, nf, "tube"));
    try
    {
        check_fields(fields, np + 1, nf, "tube");
        FAIL("a wrong point count passed");
    }
    catch (const InvalidInputError& e)
    {
        CHECK(std::string(e.what()) == "point field 'pressure' of tube has " + std::to_string(np) +
                                           " values but the mesh has " + std::to_string(np + 1) +
                                           " points; the field belongs to another mesh");
    }
    fields.push_back(fields[0]);
    CHECK_THROWS_AS(check_fields(fields, np, nf, "tube"), InvalidInputError);
    CHECK_THROWS_WITH_AS(find_field(fields, "wss"),
                         "no field named 'wss'; available: pressure, velocity, GlobalNodeID, "
                         "GlobalElementID, thickness, pressure",
                         InvalidInputError);
    Mesh bare;  // no input_index / input_face
    CHECK_THROWS_AS(transfer_fields(fields, bare), InvalidInputError);
    // Fields of a smaller mesh: an index past their rows.
    const TreeSurface surface = make_tree_surface(input.mesh);
    Field small{"s", FieldLocation::Point, FieldType::Float64, Eigen::MatrixXd::Zero(5, 1)};
    CHECK_THROWS_AS(transfer_fields({small}, surface.mesh), InvalidInputError);
}
