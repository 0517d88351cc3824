// vessel-flatten on hand-made malformed files that crashed VTK's readers, made the readers
// allocate gigabytes, or were read into wrong results (docs/bad-input.md): each is refused with
// exit 1, one line on stderr naming the file, no output, and within a memory limit.
#include <doctest/doctest.h>

#include "support/checks.h"
#include "support/files.h"
#include "support/meshes.h"
#include "vessel/io/io.h"
#include "vessel/phantom/phantom.h"
#include "vessel/io/vtk_io.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

using vessel::test::folder_names;
using vessel::test::read_bytes;
using vessel::test::run;
using vessel::test::temp_dir;
using vessel::test::write_bytes;

namespace fs = std::filesystem;

namespace {

const std::string kFlatten = VESSEL_FLATTEN_EXE;

// Address space for one refusal: the executable with its libraries (VTK, CGAL, cairo) maps
// about 0.5 GB; the bombs asked for 3 to 8 GB.
const char* kMemoryLimit = "ulimit -v 1500000; ";

std::string le32(std::int32_t v)
{
    std::string s(4, '\0');
    std::memcpy(s.data(), &v, 4);
    return s;
}

std::string le_float(float v)
{
    std::string s(4, '\0');
    std::memcpy(s.data(), &v, 4);
    return s;
}

// A binary little-endian PLY: one triangle, whose corner count is \p count.
std::string ply_with_count(std::int32_t count)
{
    std::string s = "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
                    "property float y\nproperty float z\nelement face 1\n"
                    "property list int int vertex_indices\nend_header\n";
    for (float v : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f})
        s += le_float(v);
    s += le32(count) + le32(0) + le32(1) + le32(2);
    return s;
}

const std::string kLegacyHead = "# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\n"
                                "POINTS 3 float\n0 0 0 1 0 0 0 1 0\n";

std::string stl(const std::string& facets)
{
    return "solid t\n" + facets + "endsolid t\n";
}

const char kNulObj[] = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4\0 3\n";

const std::string kFacet = "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n"
                           "vertex 0 1 0\nendloop\nendfacet\n";

// A zlib-compressed appended .vtp of a tube whose first array's block count is \p blocks.
std::string vtp_with_blocks(const std::string& dir, std::uint64_t blocks)
{
    vessel::PolyData data;
    data.mesh = vessel::to_raw_mesh(vessel::open_cylinder(1.0, 4.0, 12, 6));
    vessel::VtkWriteOptions options;
    options.encoding = vessel::VtkEncoding::Appended;
    options.compressor = vessel::VtkCompressor::ZLib;
    const std::string path = dir + "/zlib_source.vtp";
    vessel::write_polydata(path, data, options);
    std::string s = read_bytes(path);
    fs::remove(path);
    const std::size_t at = s.find('_', s.find("<AppendedData")) + 1;
    const int header = s.find("header_type=\"UInt64\"") != std::string::npos ? 8 : 4;
    for (int b = 0; b < header; ++b)
        s[at + b] = static_cast<char>((blocks >> (8 * b)) & 0xff);
    return s;
}

struct BadFile
{
    BadFile(std::string name_, std::string bytes_, std::string message_, bool fields_ = false)
        : name(std::move(name_)), bytes(std::move(bytes_)), message(std::move(message_)),
          as_fields(fields_)
    {
    }
    std::string name;     // file name, its extension chooses the reader
    std::string bytes;    // contents
    std::string message;  // a part of the one line on stderr
    bool as_fields;       // given as --fields to a valid tube instead of as the input
};

}  // namespace

TEST_CASE("bad input: crashing, bomb and silently misread files are refused in one line, "
          "with no output and bounded memory")
{
    const std::string root = temp_dir("bad_input");
    const std::string dir = root + "/in";
    fs::create_directories(dir);
    const std::string tube = dir + "/tube.ply";
    vessel::write_mesh(vessel::open_cylinder(1.0, 4.0, 12, 6), tube);
    const std::vector<BadFile> files = {
        // VTK's readers crashed (SIGSEGV) on these.
        {"truncated_polygons.vtk", kLegacyHead + "POLYGONS 1 4\n3 0 1",
         "POLYGONS declares 4 values but the file ends after 3"},
        {"huge_polygon.vtk", kLegacyHead + "POLYGONS 1 4\n2000000000 0 1 2\n",
         "cell 0 of POLYGONS has 2000000000 corners but only 3 values are left"},
        {"huge_polygon_size.vtk", kLegacyHead + "POLYGONS 1 2000000001\n2000000000 0 1 2\n",
         "POLYGONS declares 2000000001 values but the file ends after 4"},
        {"point_index.vtk", kLegacyHead + "POLYGONS 1 4\n3 0 1 7\n",
         "cell 0 of POLYGONS refers to point 7 of 3"},
        {"zero_blocks.vtp", vtp_with_blocks(dir, 0), "declares 0 bytes (0 blocks)"},
        // Memory bombs: gigabytes from a few bytes.
        {"many_blocks.vtp", vtp_with_blocks(dir, 0x7FFFFFFF),
         "declares 2147483647 blocks, more than the"},
        {"count_minus_one.ply", ply_with_count(-1),
         "face 0 has the list vertex_indices of -1 entries"},
        {"count_2e31.ply", ply_with_count(0x7FFFFFFF),
         "face 0 has the list vertex_indices of 2147483647 entries, but only 12 bytes are left"},
        {"ascii_count.ply",
         "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
         "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
         "0 0 0\n1 0 0\n0 1 0\n-1 0 1 2\n",
         "face 0 has the list vertex_indices of '-1' entries"},
        // Read into wrong results, exit 0.
        {"nan.stl", stl("facet normal 0 0 1\nouter loop\nvertex nan 0 0\nvertex 1 0 0\n"
                        "vertex 0 1 0\nendloop\nendfacet\n"),
         "vertex 0 of " + dir + "/nan.stl has a NaN, infinite or unreadable coordinate ('nan')"},
        {"abc.stl", stl(kFacet + "facet normal 0 0 1\nouter loop\nvertex abc 0 0\nvertex 1 0 0\n"
                                 "vertex 0 1 0\nendloop\nendfacet\n"),
         "vertex 3 of " + dir + "/abc.stl has a NaN, infinite or unreadable coordinate ('abc')"},
        {"two_vertices.stl", stl(kFacet + "facet normal 0 0 1\nouter loop\nvertex 0 0 0\n"
                                          "vertex 1 0 0\nendloop\nendfacet\n"),
         "facet 1 of " + dir + "/two_vertices.stl has 2 vertices; an STL facet needs exactly 3"},
        {"no_vertices.stl", stl("facet normal 0 0 1\nouter loop\nendloop\nendfacet\n" + kFacet),
         "facet 0 of " + dir + "/no_vertices.stl has 0 vertices"},
        {"nul.obj", std::string(kNulObj, sizeof kNulObj - 1),
         "line 6 of " + dir + "/nul.obj contains a NUL byte"},
        {"bom.obj", "\xEF\xBB\xBFv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
         dir + "/bom.obj starts with a UTF-8 byte order mark"},
        {"nan_time.pvd",
         "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n<Collection>\n"
         "<DataSet timestep=\"nan\" part=\"0\" file=\"s.vtp\"/>\n</Collection>\n</VTKFile>\n",
         "DataSet entry 0 of " + dir + "/nan_time.pvd has timestep=\"nan\", not a finite number",
         true},
        {"nan.csv", "vertex,0\n0,nan\n",
         dir + "/nan.csv line 2, column 2 ('0'): 'nan' is not a number", true},
        {"inf.csv", "vertex,0\n0,1\n1,inf\n",
         dir + "/inf.csv line 3, column 2 ('0'): 'inf' is not a number", true},
    };
    for (const auto& f : files)
    {
        CAPTURE(f.name);
        const std::string path = dir + "/" + f.name;
        write_bytes(path, f.bytes);
        const std::string out = root + "/out";
        fs::create_directories(out);
        const std::string input = !f.as_fields ? path : tube + " --fields " + path;
        const std::string err = root + "/stderr.txt";
        const int status =
            run("sh -c '" + std::string(kMemoryLimit) + "exec " + kFlatten + " " + input +
                " -o " + out + "/flat.vtp --report " + out + "/r.json -q' 2> " + err);
        const std::string text = read_bytes(err);
        CHECK_MESSAGE(status == 1, text);
        CHECK_MESSAGE(std::count(text.begin(), text.end(), '\n') == 1, text);
        CHECK_MESSAGE(text.rfind("vessel-flatten: ", 0) == 0, text);
        CHECK_MESSAGE(text.find(path) != std::string::npos, text);
        CHECK_MESSAGE(text.find(f.message) != std::string::npos, text);
        CHECK(fs::is_empty(out));
        fs::remove_all(out);
    }
}
