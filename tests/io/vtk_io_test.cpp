#include <doctest/doctest.h>

#include "support/checks.h"
#include "support/files.h"
#include "support/io_refusal.h"
#include "support/meshes.h"
#include "vessel/core/errors.h"
#include "vessel/phantom/phantom.h"
#include "vessel/check/validation.h"
#include "vessel/io/vtk_io.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

using namespace vessel;
using vessel::test::run;
using vessel::test::temp_dir;

namespace {

// Exact unless \p digits > 0: then to that many significant digits (VTK's legacy ASCII writer
// prints doubles with 11 significant digits).
void check_same(const PolyData& a, const PolyData& b, int digits = 0)
{
    const double rel = digits > 0 ? std::pow(10.0, -digits) : 0.0;
    const auto close = [rel](const auto& x, const auto& y) {
        return (x - y).cwiseAbs().maxCoeff() <= rel * x.cwiseAbs().maxCoeff();
    };
    REQUIRE(a.mesh.points.size() == b.mesh.points.size());
    for (std::size_t i = 0; i < a.mesh.points.size(); ++i)
        CHECK(close(a.mesh.points[i], b.mesh.points[i]));
    CHECK(a.mesh.faces == b.mesh.faces);
    const auto same_fields = [&](const std::vector<Field>& x, const std::vector<Field>& y) {
        REQUIRE(x.size() == y.size());
        for (std::size_t k = 0; k < x.size(); ++k)
        {
            INFO("field " << x[k].name);
            CHECK(x[k].name == y[k].name);
            CHECK(x[k].location == y[k].location);
            CHECK(x[k].type == y[k].type);
            REQUIRE(x[k].values.rows() == y[k].values.rows());
            REQUIRE(x[k].values.cols() == y[k].values.cols());
            CHECK(close(x[k].values, y[k].values));
        }
    };
    same_fields(a.point_data, b.point_data);
    same_fields(a.cell_data, b.cell_data);
}

}  // namespace

TEST_CASE("vtk_io: every VTK encoding round-trips points, polygons and all arrays exactly")
{
    const PolyData d = vessel::test::tube_with_fields(10, 4);
    const std::string dir = temp_dir("vtk_io_roundtrip");
    struct Case
    {
        std::string name;
        VtkEncoding encoding;
        VtkCompressor compressor;
        int digits = 0;  // exact
    };
    using E = VtkEncoding;
    using C = VtkCompressor;
    const std::vector<Case> cases = {{"ascii.vtp", E::Ascii, C::None},
                                     {"binary.vtp", E::Binary, C::None},
                                     {"binary-zlib.vtp", E::Binary, C::ZLib},
                                     {"binary-lz4.vtp", E::Binary, C::LZ4},
                                     {"binary-lzma.vtp", E::Binary, C::LZMA},
                                     {"appended.vtp", E::Appended, C::None},
                                     {"appended-zlib.vtp", E::Appended, C::ZLib},
                                     {"appended-lz4.vtp", E::Appended, C::LZ4},
                                     {"appended-lzma.vtp", E::Appended, C::LZMA},
                                     {"ascii.vtk", E::Ascii, C::None, 10},
                                     {"binary.vtk", E::Binary, C::None}};
    for (const auto& c : cases)
    {
        INFO(c.name);
        const std::string path = dir + "/" + c.name;
        write_polydata(path, d, {c.encoding, c.compressor});
        CHECK_FALSE(std::filesystem::exists(path + ".tmp"));
        check_same(d, read_polydata(path), c.digits);
    }
    // The encodings really differ: ascii text, zlib header in the compressed file.
    std::ifstream ascii(dir + "/ascii.vtp");
    std::string text((std::istreambuf_iterator<char>(ascii)), {});
    CHECK(text.find("format=\"ascii\"") != std::string::npos);
    std::ifstream zlib(dir + "/appended-zlib.vtp");
    std::string packed((std::istreambuf_iterator<char>(zlib)), {});
    CHECK(packed.find("vtkZLibDataCompressor") != std::string::npos);
    CHECK(packed.find("format=\"appended\"") != std::string::npos);
    for (const auto& [name, header] : {std::pair<std::string, std::string>{"appended-lz4.vtp",
                                                                           "vtkLZ4DataCompressor"},
                                       {"binary-lzma.vtp", "vtkLZMADataCompressor"}})
    {
        std::ifstream in(dir + "/" + name);
        const std::string bytes((std::istreambuf_iterator<char>(in)), {});
        CHECK_MESSAGE(bytes.find(header) != std::string::npos, name);
    }
}

TEST_CASE("vtk_io: files written by python3-vtk9 (defaults, lz4, lzma) are read with their arrays")
{
    const std::string dir = temp_dir("vtk_io_python");
    const std::string script = dir + "/write.py";
    std::ofstream(script) << R"(import sys, vtk
src = vtk.vtkCylinderSource(); src.SetResolution(16); src.CappingOff(); src.Update()
poly = src.GetOutput()
s = vtk.vtkDoubleArray(); s.SetName("wss"); v = vtk.vtkFloatArray(); v.SetName("disp")
v.SetNumberOfComponents(3)
for i in range(poly.GetNumberOfPoints()):
    s.InsertNextValue(0.25 * i); v.InsertNextTuple3(i, -i, 0.5)
poly.GetPointData().AddArray(s); poly.GetPointData().AddArray(v)
c = vtk.vtkIntArray(); c.SetName("region")
for i in range(poly.GetNumberOfPolys()):
    c.InsertNextValue(i % 3)
poly.GetCellData().AddArray(c)
w = vtk.vtkXMLPolyDataWriter(); w.SetFileName(sys.argv[1]); w.SetInputData(poly); w.Write()
l = vtk.vtkPolyDataWriter(); l.SetFileName(sys.argv[2]); l.SetInputData(poly); l.Write()
for name, mode in (("lz4", "Appended"), ("lzma", "Binary")):
    c = vtk.vtkXMLPolyDataWriter(); c.SetFileName(sys.argv[1][:-4] + "-" + name + ".vtp")
    c.SetInputData(poly); getattr(c, "SetDataModeTo" + mode)()
    getattr(c, "SetCompressorTypeTo" + name.upper())(); c.Write()
print(poly.GetNumberOfPoints(), poly.GetNumberOfPolys())
)";
    REQUIRE(run("/usr/bin/python3 " + script + " " + dir + "/py.vtp " + dir + "/py.vtk > " + dir +
                "/counts.txt") == 0);
    int points = 0, polys = 0;
    std::ifstream(dir + "/counts.txt") >> points >> polys;
    // Python's defaults (appended, zlib), legacy, and the lz4 and lzma compressors.
    for (const std::string name : {"py.vtp", "py.vtk", "py-lz4.vtp", "py-lzma.vtp"})
    {
        INFO(name);
        const PolyData d = read_polydata(dir + "/" + name);
        REQUIRE(static_cast<int>(d.mesh.points.size()) == points);
        REQUIRE(static_cast<int>(d.mesh.faces.size()) == polys);
        const Field& wss = find_field(d.point_data, "wss");
        const Field& disp = find_field(d.point_data, "disp");
        const Field& region = find_field(d.cell_data, "region");
        CHECK(wss.type == FieldType::Float64);
        CHECK(disp.type == FieldType::Float32);
        CHECK(disp.components() == 3);
        CHECK(region.type == FieldType::Int32);
        for (int i = 0; i < points; ++i)
        {
            CHECK(wss.values(i, 0) == 0.25 * i);
            CHECK(disp.values(i, 1) == -i);
        }
        for (int f = 0; f < polys; ++f)
            CHECK(region.values(f, 0) == f % 3);
        // The quads of the cylinder reach validation with file indices, and are triangulated.
        const TreeSurface s = make_tree_surface(read_raw_mesh(dir + "/" + name));
        CHECK(static_cast<int>(s.mesh.n_faces()) == 2 * polys);
    }
}

TEST_CASE("vtk_io: legacy files with every attribute kind, ASCII and BINARY, 4.2 and 5.1, pass "
          "the structure check and are read")
{
    // python3-vtk9 writes each kind the check walks: SCALARS + LOOKUP_TABLE, VECTORS, NORMALS
    // (point and cell), TEXTURE_COORDINATES, GLOBAL_IDS, FIELD, and METADATA blocks
    // (INFORMATION after a ranged array, COMPONENT_NAMES).
    const std::string dir = temp_dir("vtk_io_legacy_kinds");
    const std::string script = dir + "/write.py";
    std::ofstream(script) << R"(import sys, vtk
src = vtk.vtkCylinderSource(); src.SetResolution(12); src.CappingOff()
tri = vtk.vtkTriangleFilter(); tri.SetInputConnection(src.GetOutputPort())
n = vtk.vtkPolyDataNormals(); n.SetInputConnection(tri.GetOutputPort()); n.ComputeCellNormalsOn()
n.SplittingOff(); n.Update()
p = n.GetOutput()
s = vtk.vtkFloatArray(); s.SetName("press")
v = vtk.vtkDoubleArray(); v.SetName("vel"); v.SetNumberOfComponents(3)
t = vtk.vtkFloatArray(); t.SetName("uv"); t.SetNumberOfComponents(2)
g = vtk.vtkIdTypeArray(); g.SetName("gid")
c = vtk.vtkIntArray(); c.SetName("pair"); c.SetNumberOfComponents(2)
c.SetComponentName(0, "a b"); c.SetComponentName(1, "c")
for i in range(p.GetNumberOfPoints()):
    s.InsertNextValue(0.5 * i); v.InsertNextTuple3(i, 1e-3, -2); t.InsertNextTuple2(0.1, 0.2)
    g.InsertNextValue(i); c.InsertNextTuple2(i, -i)
d = p.GetPointData(); d.SetScalars(s); d.SetVectors(v); d.SetTCoords(t); d.SetGlobalIds(g)
d.AddArray(c)
s.GetRange(); p.GetPoints().GetData().GetRange(-1)
for version in (42, 51):
    for binary in (False, True):
        w = vtk.vtkPolyDataWriter(); w.SetInputData(p); w.SetFileVersion(version)
        w.SetFileName("%s/k%d%s.vtk" % (sys.argv[1], version, "b" if binary else "a"))
        if binary:
            w.SetFileTypeToBinary()
        w.Write()
print(p.GetNumberOfPoints(), p.GetNumberOfPolys())
)";
    REQUIRE(run("/usr/bin/python3 " + script + " " + dir + " > " + dir + "/counts.txt") == 0);
    int points = 0, polys = 0;
    std::ifstream(dir + "/counts.txt") >> points >> polys;
    REQUIRE(points > 0);
    for (const std::string name : {"k42a.vtk", "k42b.vtk", "k51a.vtk", "k51b.vtk"})
    {
        INFO(name);
        const std::string bytes = vessel::test::read_bytes(dir + "/" + name);
        CHECK(bytes.find("METADATA") != std::string::npos);
        CHECK(bytes.find("COMPONENT_NAMES") != std::string::npos);
        const PolyData d = read_polydata(dir + "/" + name);
        CHECK(static_cast<int>(d.mesh.points.size()) == points);
        CHECK(static_cast<int>(d.mesh.faces.size()) == polys);
        const Field& vel = find_field(d.point_data, "vel");
        CHECK(vel.components() == 3);
        CHECK(vel.values(points - 1, 0) == points - 1);
        CHECK(find_field(d.point_data, "pair").values(2, 1) == -2);
    }
}

// Inputs found by the fuzzers (fuzz/, kept in tests/data/fuzz): each crashed (or, under ASan,
// asked for terabytes in) VTK's readers or the structure check before it; now each is refused.
TEST_CASE("vtk_io: fuzzer findings are refused with a clear IoError")
{
    const std::string dir = std::string(VESSEL_TEST_DATA) + "/fuzz/";
    const std::vector<std::pair<std::string, std::string>> cases = {
        // POINTS cut short: VTK read the next keyword as a coordinate and crashed in
        // vtkDataReader::ReadString.
        {"vtk_points_cut_short.vtk", "value 44 of POINTS is 'POLYGONS', not a number"},
        // "DATASET" followed by binary garbage: VTK matches the keyword by its first letters and
        // read on (a wild read in vtkCellArray::AppendLegacyFormat); non-ASCII bytes print as ?.
        {"vtk_dataset_keyword_garbled.vtk", "the fourth line starts with 'DATASET???"},
        // A <Piece> tag padded to hundreds of bytes: std::regex overflowed the stack.
        {"vtp_long_tag.vtp", "the XML tag <Piece> has a malformed attribute"},
        // Polys offsets ending at 2^38: vtkXMLPolyDataReader allocated 2 TB for connectivity.
        {"vtp_offset_bomb.vtp",
         "the last offset of <Polys> is 257698037760 but its connectivity holds 60 values"},
        // ASCII offsets running to the end of the file: the check read past it (its own
        // heap overflow); now VTK's XML parser refuses the broken tag after them.
        {"vtp_ascii_offsets_at_end.vtp", "VTK could not read"},
        // Points of one component: VTK refused them but leaked the array it had made.
        {"vtp_points_one_component.vtp",
         "the <Points> array 'Points' has NumberOfComponents=\"1\", not 3"},
        // A byte between <AppendedData> and its '_': VTK counted the offsets from that byte, the
        // check from the '_' after it, so VTK read a compression header of 2^30 blocks.
        {"vtp_byte_before_appended_underscore.vtp",
         "the data of <AppendedData> does not start with '_' after its tag"},
    };
    for (const auto& [file, message] : cases)
    {
        CAPTURE(file);
        const std::string what = vessel::test::io_refusal(dir + file);
        CHECK_MESSAGE(what.find(message) != std::string::npos, what);
        CHECK(what.find(dir + file) != std::string::npos);
    }
}

TEST_CASE("vtk_io: unreadable or unsuitable files are refused with a message")
{
    const std::string dir = temp_dir("vtk_io_bad");
    CHECK_THROWS_AS(read_polydata(dir + "/missing.vtp"), IoError);
    CHECK_THROWS_AS(read_polydata(dir + "/../vtk_io_bad"), IoError);
    std::ofstream(dir + "/grid.vtp")
        << "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\">"
           "<UnstructuredGrid></UnstructuredGrid></VTKFile>\n";
    CHECK_THROWS_AS(read_polydata(dir + "/grid.vtp"), IoError);
    std::ofstream(dir + "/grid.vtk") << "# vtk DataFile Version 4.2\nx\nASCII\nDATASET "
                                        "UNSTRUCTURED_GRID\nPOINTS 0 float\n";
    CHECK_THROWS_AS(read_polydata(dir + "/grid.vtk"), IoError);
    // Truncated appended data.
    write_polydata(dir + "/ok.vtp", vessel::test::tube_with_fields(10, 4),
                   {VtkEncoding::Appended, VtkCompressor::ZLib});
    const auto size = std::filesystem::file_size(dir + "/ok.vtp");
    std::filesystem::copy_file(dir + "/ok.vtp", dir + "/cut.vtp");
    std::filesystem::resize_file(dir + "/cut.vtp", size / 2);
    CHECK_THROWS_AS(read_polydata(dir + "/cut.vtp"), IoError);
    // Line cells are not a wall.
    std::ofstream(dir + "/lines.vtk") << "# vtk DataFile Version 4.2\nx\nASCII\nDATASET "
                                         "POLYDATA\nPOINTS 3 float\n0 0 0 1 0 0 0 1 0\n"
                                         "LINES 1 3\n2 0 1\nPOLYGONS 1 4\n3 0 1 2\n";
    try
    {
        read_polydata(dir + "/lines.vtk");
        FAIL("line cells were accepted");
    }
    catch (const IoError& e)
    {
        CHECK(std::string(e.what()).find("1 line cells") != std::string::npos);
    }
    PolyData bad = vessel::test::tube_with_fields(10, 4);
    bad.point_data[0].values.conservativeResize(3, 1);
    CHECK_THROWS_AS(write_polydata(dir + "/bad.vtp", bad), InvalidInputError);
    CHECK_THROWS_AS(write_polydata(dir + "/x.vtk", vessel::test::tube_with_fields(10, 4),
                                   {VtkEncoding::Appended, VtkCompressor::None}),
                    InvalidInputError);
    CHECK_THROWS_AS(write_polydata(dir + "/x.ply", vessel::test::tube_with_fields(10, 4)),
                    InvalidInputError);
    CHECK(is_vtk_path("a/B.VTP"));
    CHECK_FALSE(is_vtk_path("a.ply"));
}
