#include <doctest/doctest.h>

#include "support/checks.h"
#include "support/io_refusal.h"
#include "vessel/core/errors.h"
#include "vessel/io/io.h"
#include "vessel/phantom/phantom.h"

#include <cstdint>
#include <filesystem>
#include <functional>
#include <sstream>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

using namespace vessel;
using vessel::test::io_refusal;

namespace {

std::string temp_path(const std::string& name)
{
    static const std::string dir = vessel::test::temp_dir("io");
    return dir + "/" + name;
}

}  // namespace

TEST_CASE("io: every supported format round-trips positions and faces")
{
    const Mesh mesh = open_cylinder(1.0, 3.0, 12, 6);
    for (const char* ext : {".obj", ".off", ".ply", ".stl"})
    {
        CAPTURE(ext);
        const std::string path = temp_path(std::string("cylinder") + ext);
        write_mesh(mesh, path);
        const RawMesh raw = read_raw_mesh(path);
        CHECK(raw.faces.size() == mesh.n_faces());
        // STL stores corners per face; OpenMesh's reader merges coincident ones again.
        CHECK(raw.points.size() == mesh.n_vertices());
        double max_error = 0;
        for (std::size_t f = 0; f < raw.faces.size(); ++f)
        {
            REQUIRE(raw.faces[f].size() == 3);
            int k = 0;
            for (auto v : mesh.fv_range(FaceHandle(static_cast<int>(f))))
            {
                const Eigen::Vector3d a = raw.points[raw.faces[f][k++]];
                max_error = std::max(max_error, (a - to_eigen(mesh.point(v))).norm());
            }
        }
        CHECK(max_error < 1e-5);  // STL and PLY store float32
    }
}

TEST_CASE("io: missing, empty and unknown files are refused with IoError")
{
    CHECK_THROWS_AS(read_raw_mesh(temp_path("does-not-exist.obj")), IoError);
    const std::string empty = temp_path("empty.obj");
    std::ofstream(empty).close();
    CHECK_THROWS_AS(read_raw_mesh(empty), IoError);
    const std::string unknown = temp_path("mesh.xyz");
    std::ofstream(unknown) << "1 2 3\n";
    CHECK_THROWS_AS(read_raw_mesh(unknown), IoError);
    const std::string no_faces = temp_path("points.obj");
    std::ofstream(no_faces) << "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
    CHECK_THROWS_AS(read_raw_mesh(no_faces), IoError);
}

TEST_CASE("io: faces OpenMesh cannot add are still recorded in file indices")
{
    // Face 2 is non-manifold (third face on edge 0-1): OpenMesh's importer would have
    // duplicated its vertices; the raw mesh keeps the file's indices, for the validation to
    // name.
    const std::string path = temp_path("nonmanifold.obj");
    std::ofstream(path) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\n"
                           "f 1 2 3\nf 2 1 4\nf 1 2 5\nf 4 1 3\n";
    const RawMesh raw = read_raw_mesh(path);
    REQUIRE(raw.faces.size() == 4);
    CHECK(raw.points.size() == 5);
    CHECK(raw.faces[2] == std::vector<int>{0, 1, 4});
    CHECK(raw.faces[3] == std::vector<int>{3, 0, 2});
}

// Inputs found by the fuzzers (fuzz/), kept as files in tests/data/fuzz: each crashed or hung
// OpenMesh's readers before read_raw_mesh() checked them; now each is refused with IoError.
TEST_CASE("io: fuzzer findings are refused with a clear IoError")
{
    const std::string dir = std::string(VESSEL_TEST_DATA) + "/fuzz/";
    const std::vector<std::pair<std::string, std::string>> cases = {
        // OpenMesh's PLY reader dereferenced a missing element (SEGV).
        {"ply_property_before_element.ply",
         "PLY header line 3: the control byte 0x00 in 'elem????ent vgrtex 18'"},
        // OpenMesh's OBJ reader failed an assertion on the corner "/1/1".
        {"obj_bad_face_index.obj", "face 0 of " + dir + "obj_bad_face_index.obj refers to vertex '/1/1'"},
        // OpenMesh's OFF reader read the count "3OFF" and looped for minutes.
        {"off_unreadable_face_count.off", "is malformed ('3850651 0'): an OFF face is a corner count"},
        // A header "OFFSt9tyBINARY...": OpenMesh read garbage counts and allocated 13 GB.
        {"off_bad_header.off", "the first line 'OFFSt9tyBINARYm"},
        // "element vertet x" (no count) and a property type "floty": OpenMesh's PLY reader hung.
        {"ply_unreadable_element_count.ply",
         "PLY header line 3: element count must be a decimal integer from 0 to 2147483648, got "
         "'x'"},
        // A form feed inside "property float z": OpenMesh's PLY reader split the line there and
        // looped (a 10 s timeout of the CI's fuzz run).
        {"ply_form_feed_in_property.ply",
         "PLY header line 6: the control byte 0x0C in 'property float z?element f????20'"},
        // "format binary_little_endian ty float z": OpenMesh's PLY reader looped.
        {"ply_format_line_extra_words.ply",
         "PLY header line 2: expected 'format ascii 1.0' (or binary_little_endian, "
         "binary_big_endian), got 'format binary_little_endian ty float z'"},
        // "format binary_little_endian \x061.0": OpenMesh's PLY reader read no version and looped.
        {"ply_control_byte_in_format_version.ply",
         "PLY header line 2: the control byte 0x06 in 'format binary_little_endian ?1.0'"},
        // The corner "1-4" in an ASCII face: OpenMesh read "1", then "-4" as the next face's
        // corner count (2^32-4) and added corners until the fuzzer's 10 s timeout.
        {"ply_ascii_corner_read_in_part.ply",
         "face 14 has the corner '1-4' in its list vertex_indices, which is no vertex index (a "
         "decimal integer)"},
        // Garbage after "OFF" on the first line; its counts "-1 1" were read as unsigned and
        // OpenMesh tried to allocate them (out of memory).
        {"off_negative_vertex_count.off", "the first line 'OFF????omm2' is not an OFF header"},
    };
    // The negative count itself, behind a valid header line.
    std::ofstream(temp_path("negative.off")) << "OFF\n-1 1 0\n0 0 0\n3 0 0 0\n";
    CHECK_THROWS_WITH_AS(read_raw_mesh(temp_path("negative.off")),
                         doctest::Contains("the OFF header declares -1 vertices and 1 faces"),
                         IoError);
    for (const auto& [file, message] : cases)
    {
        CAPTURE(file);
        std::string what;
        try
        {
            read_raw_mesh(dir + file);
        }
        catch (const IoError& e)
        {
            what = e.what();
        }
        CHECK_MESSAGE(what.find(message) != std::string::npos, what);
    }
}

namespace {

// The bytes of a binary little-endian PLY triangle: \p before_vertex lines after the format line,
// then the vertex and face elements, \p before_end lines, end_header and the data. Each line
// ends with \p eol.
std::string ply_triangle(const std::string& format_line, const std::string& before_vertex,
                         const std::string& before_end, const std::string& eol = "\n")
{
    std::string head = "ply" + eol + format_line + eol + before_vertex +
                       "element vertex 3" + eol + "property float x" + eol + "property float y" +
                       eol + "property float z" + eol + "element face 1" + eol +
                       "property list uchar int vertex_indices" + eol + before_end;
    head += "end_header" + eol;
    if (format_line.find("ascii") != std::string::npos)
        return head + "0 0 0" + eol + "1 0 0" + eol + "0 1 0" + eol + "3 0 1 2" + eol;
    const float points[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const std::int32_t corners[3] = {0, 1, 2};
    head.append(reinterpret_cast<const char*>(points), sizeof points);
    head.push_back(3);
    head.append(reinterpret_cast<const char*>(corners), sizeof corners);
    return head;
}

std::string write_bytes(const std::string& name, const std::string& bytes)
{
    const std::string path = temp_path(name);
    std::ofstream(path, std::ios::binary) << bytes;
    return path;
}

const std::string kBinary = "format binary_little_endian 1.0";

}  // namespace

// OpenMesh's PLY reader reads the header word by word and loops forever where its stream fails
// (fuzz findings above), or misreads binary data after a comment: read_raw_mesh() lets only the
// PLY grammar through and names the line and what to fix.
TEST_CASE("io: a PLY header outside the PLY grammar is refused with its line and what to fix")
{
    const std::vector<std::pair<std::string, std::string>> cases = {
        {ply_triangle("format binary_little_endian \x06" "1.0", "", ""),
         "PLY header line 2: the control byte 0x06 in 'format binary_little_endian ?1.0'; "
         "header lines are text"},
        {ply_triangle("format ascii 2.0", "", ""),
         "PLY header line 2: format version must be 1.0, got '2.0'"},
        {ply_triangle("format ascii 1", "", ""),
         "PLY header line 2: format version must be 1.0, got '1'"},
        {ply_triangle("format binary 1.0", "", ""),
         "PLY header line 2: format must be ascii, binary_little_endian or binary_big_endian, "
         "got 'binary'"},
        {ply_triangle("comment first", "format ascii 1.0\n", ""),
         "PLY header line 2: expected 'format ascii 1.0' (or binary_little_endian, "
         "binary_big_endian), got 'comment first'"},
        {ply_triangle(kBinary, "format ascii 1.0\n", ""),
         "PLY header line 3: unknown line 'format ascii 1.0'; a PLY header line is comment, "
         "obj_info, element, property or end_header (format only as line 2)"},
        {ply_triangle(kBinary, "element edge -1\n", ""),
         "PLY header line 3: element count must be a decimal integer from 0 to 2147483648, got "
         "'-1'"},
        {ply_triangle(kBinary, "element edge +1\n", ""),
         "element count must be a decimal integer from 0 to 2147483648, got '+1'"},
        {ply_triangle(kBinary, "element edge 2147483649\n", ""),
         "element count must be a decimal integer from 0 to 2147483648, got '2147483649'"},
        {ply_triangle(kBinary, "element edge 3x\n", ""),
         "element count must be a decimal integer from 0 to 2147483648, got '3x'"},
        {ply_triangle(kBinary, "element edge\n", ""),
         "PLY header line 3: an element line is 'element NAME COUNT', got 'element edge'"},
        {ply_triangle(kBinary, "property float w\n", ""),
         "PLY header line 3: the property 'property float w' comes before any element line"},
        {ply_triangle(kBinary, "", "property float\n"),
         "PLY header line 9: a property line is 'property TYPE NAME' or 'property list "
         "COUNT_TYPE TYPE NAME', got 'property float'"},
        {ply_triangle(kBinary, "", "property list uchar int\n"),
         "PLY header line 9: a property line is"},
        {ply_triangle(kBinary, "", "property float32 quality extra\n"),
         "PLY header line 9: a property line is"},
        {ply_triangle(kBinary, "", "property floaty quality\n"),
         "PLY header line 9: unknown property type 'floaty' in 'property floaty quality'"},
        {ply_triangle(kBinary, "", "property list uchar integer neighbours\n"),
         "PLY header line 9: unknown property type 'integer'"},
        {ply_triangle(kBinary, "", "property list ushort int neighbours\n"),
         "PLY header line 9: list count type must be uchar, uint8, uint16 or int (the ones "
         "OpenMesh reads), got 'ushort'"},
        {ply_triangle(kBinary, "", "property list uchar float texcoord\n"),
         "PLY header line 9: the property 'texcoord' of the element 'face' is a list; OpenMesh "
         "reads only one list, the face's vertex_indices (or vertex_index), and misreads the "
         "rest of the file after any other; remove it"},
        {ply_triangle(kBinary, "element edge 1\nproperty list uchar int vertex_indices\n", ""),
         "PLY header line 4: the property 'vertex_indices' of the element 'edge' is a list"},
        {"ply\nformat ascii 1.0\nelement face 1\nproperty list uchar float vertex_indices\n"
         "end_header\n3 0 1 2\n",
         "PLY header line 4: the face's corner indices must be of an integer type, got 'float'"},
        {"ply\n" + kBinary + "\nelement vertex 1\nproperty int x\nend_header\n",
         "PLY header line 4: OpenMesh reads the property 'x' of the element 'vertex' of a binary "
         "PLY only as float, float32, double or float64, got 'int'; write it as float"},
        {ply_triangle(kBinary, "", "property uchar double\n"),
         "PLY header line 9: the property name 'double' in 'property uchar double' is a type "
         "name, which PLY readers can take for the type; rename the property"},
        {ply_triangle(kBinary, "", "property double red\n"),
         "PLY header line 9: OpenMesh reads the property 'red' of the element 'face' of a binary "
         "PLY only as an integer type, float or float32, got 'double'; write it as uchar or "
         "float"},
        {ply_triangle(kBinary, "element v\xc3\xa9rtex 0\n", ""),
         "PLY header line 3: the byte 0xC3 in 'element v??rtex 0'; only comment and obj_info "
         "lines may hold text beyond ASCII"},
        {ply_triangle(kBinary, "obj_info element 3\n", ""),
         "PLY header line 3: the obj_info line 'obj_info element 3' holds the word 'element', "
         "which PLY readers can take for a header keyword; make it a comment line"},
        {ply_triangle(kBinary, "\n", ""), "PLY header line 3: an empty line; remove it"},
        {ply_triangle(kBinary, "element edge 2147483648\n", ""),
         "PLY header line 3: the element 'edge' has 2147483648 rows but no property line "
         "follows it; give it its properties or a count of 0"},
        {ply_triangle(kBinary, "", "element edge 5\n"),
         "PLY header line 9: the element 'edge' has 5 rows but no property line follows it"},
        {ply_triangle(kBinary, "vertex 3\n", ""), "PLY header line 3: unknown line 'vertex 3'"},
        {ply_triangle(kBinary, "", "end_header now\n"),
         "PLY header line 9: end_header must be alone on its line, got 'end_header now'"},
        // OpenMesh reads on from 12 bytes after the last word before end_header: after a
        // comment or trailing blanks it read the triangle's coordinates one byte late, with
        // exit 0 and no faces.
        {ply_triangle(kBinary, "", "comment last line\n"),
         "PLY header line 10: OpenMesh would read the binary data from byte 188, but they start "
         "at byte 187; put end_header right after the previous line's last word and one line "
         "break (no comment or trailing blanks before it)"},
        {ply_triangle(kBinary, "", "property float quality \n"),
         "PLY header line 10: OpenMesh would read the binary data from byte 192, but they start "
         "at byte 193"},
        {"PLY\nformat ascii 1.0\nend_header\n", "is not a PLY file (its first line is 'PLY', not 'ply')"},
        {"ply\nformat ascii 1.0\nelement vertex 3\n", "the PLY header has no 'end_header' line"},
        {"ply\nformat ascii 1.0\n" + std::string(70000, 'c') + "\nend_header\n",
         "the PLY header has no 'end_header' line in its first 65536 bytes"},
    };
    for (const auto& [bytes, message] : cases)
    {
        CAPTURE(bytes.substr(0, 200));
        const std::string what = io_refusal(write_bytes("header.ply", bytes));
        CHECK_MESSAGE(what.find(message) != std::string::npos, what);
    }
}

// OpenMesh reads ASCII PLY data word by word across lines: a word read in part or one too many
// shifts every later value, and a shifted corner count can ask for billions of corners.
TEST_CASE("io: ASCII PLY rows that OpenMesh would read shifted are refused")
{
    const std::string head = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                             "property float y\nproperty float z\nproperty uchar red\n"
                             "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"0 0 0 9\n1 0 0 9\n0 1 0 9\n3 0 1 2 4000000000\n",
         "face 0 has 5 values on its line '3 0 1 2 4000000000', but its properties take 4; each "
         "row is one line of exactly its values"},
        {"0 0 0 9\n1 0 0\n9 0 1 0 9\n3 0 1 2\n",
         "vertex 1 has 3 values on its line '1 0 0', but its properties take 4"},
        {"0 0 0 9\n# a comment\n1 0 0 9\n0 1 0 9\n3 0 1 2\n",
         "vertex 1 has 3 values on its line '# a comment', but its properties take 4"},
        {"0 0 0 9\n\n1 0 0 9\n0 1 0 9\n3 0 1 2\n",
         "vertex 1 has 0 values on its line '', but its properties take 4"},
        {"0 0 0 9\n1 0 0x10 9\n0 1 0 9\n3 0 1 2\n",
         "vertex 1 has the value '0x10' for z, which is no number C++ streams read in full "
         "(OpenMesh would read on from inside it)"},
        // A number beyond float's range is said to be one (it was "no number C++ streams read").
        {"0 0 1e39 9\n1 0 0 9\n0 1 0 9\n3 0 1 2\n",
         "vertex 0 of " + temp_path("rows.ply") + " has the value '1e39' for z, beyond the range "
         "of float (3.4e38)"},
        {"0 0 0 9\n1 0 0 0.5\n0 1 0 9\n3 0 1 2\n", "vertex 1 has the value '0.5' for red"},
        {"0 0 0 9\n1 0 0 9\n0 1 0 9\n3 0 1 -2\n",
         "face 0 has the corner '-2' in its list vertex_indices, which is no vertex index"},
        {"0 0 0 9\n1 0 0 9\n0 1 0 9\n3 0 1 2.0\n", "face 0 has the corner '2.0'"},
        {"0 0 0 9\n1 0 0 9\n0 1 0 9\n+3 0 1 2\n",
         "face 0 has the list vertex_indices of '+3' entries, but its line has 3 values after "
         "the count"},
        // The coordinates strtod cannot read keep their own message.
        {"0 0 0 9\n1 nan 0 9\n0 1 0 9\n3 0 1 2\n",
         "vertex 1 of " + temp_path("rows.ply") + " has a NaN, infinite or unreadable coordinate "
         "('nan')"},
    };
    for (const auto& [rows, message] : cases)
    {
        CAPTURE(rows);
        const std::string what = io_refusal(write_bytes("rows.ply", head + rows));
        CHECK_MESSAGE(what.find(message) != std::string::npos, what);
    }
    // The same rows written well (any blanks between the values) are read.
    const RawMesh raw = read_raw_mesh(
        write_bytes("rows.ply", head + "0 0 0 9\n1 0 0\t9\n 0 1.0e0 0 9 \r\n3 0 1 2\n\n"));
    CHECK(raw.points[2] == Eigen::Vector3d(0, 1, 0));
    CHECK(raw.faces == std::vector<std::vector<int>>{{0, 1, 2}});
}

TEST_CASE("io: PLY headers within the grammar are read: comments, obj_info, UTF-8 text, CRLF")
{
    const std::vector<std::string> headers = {
        ply_triangle(kBinary, "comment made by caf\xc3\xa9 \tscanner\nobj_info mm units\n",
                     "property float quality\n"),
        ply_triangle(kBinary, "comment made by x\r\nobj_info mm\r\n", "", "\r\n"),
        ply_triangle("format ascii 1.0", "comment \xc3\xa9\n", "comment last\n"),
        ply_triangle("format ascii 1.0", "obj_info a\r\n", "comment last\r\n", "\r\n"),
        ply_triangle("format binary_little_endian\t1.0", "element edge 0\n", ""),
    };
    for (std::size_t i = 0; i < headers.size(); ++i)
    {
        CAPTURE(i);
        std::string bytes = headers[i];
        // The face's quality property of the first header: one more float after its corners.
        if (i == 0)
        {
            const float quality = 7;
            bytes.append(reinterpret_cast<const char*>(&quality), sizeof quality);
        }
        const RawMesh raw = read_raw_mesh(write_bytes("good.ply", bytes));
        REQUIRE(raw.points.size() == 3);
        CHECK(raw.points[1] == Eigen::Vector3d(1, 0, 0));
        CHECK(raw.points[2] == Eigen::Vector3d(0, 1, 0));
        CHECK(raw.faces == std::vector<std::vector<int>>{{0, 1, 2}});
    }
}

namespace {

// A tube written as OBJ with one `vt` and one `vn` per vertex and faces whose corners are
// spelled by \p corner(index 1-based, vertex count).
std::string write_obj_corners(const std::string& name,
                              const std::function<std::string(int, int)>& corner)
{
    const RawMesh raw = to_raw_mesh(open_cylinder(1.0, 4.0, 12, 6));
    const int n = static_cast<int>(raw.points.size());
    std::ostringstream out;
    out.precision(17);
    for (const auto& p : raw.points)
        out << "v " << p.x() << " " << p.y() << " " << p.z() << "\nvt 0.5 0.5\nvn 0 0 1\n";
    for (const auto& f : raw.faces)
        out << "f " << corner(f[0] + 1, n) << " " << corner(f[1] + 1, n) << " "
            << corner(f[2] + 1, n) << "\n";
    const std::string path = temp_path(name);
    std::ofstream(path) << out.str();
    return path;
}

}  // namespace

TEST_CASE("io: OBJ corners with texture and normal indices, or counted back, are read")
{
    const std::vector<std::vector<int>> faces =
        to_raw_mesh(open_cylinder(1.0, 4.0, 12, 6)).faces;
    const std::vector<std::pair<std::string, std::function<std::string(int, int)>>> spellings = {
        {"v/vt/vn", [](int i, int) { return std::to_string(i) + "/" + std::to_string(i) + "/" +
                                            std::to_string(i); }},
        {"v//vn", [](int i, int) { return std::to_string(i) + "//" + std::to_string(i); }},
        {"v/vt", [](int i, int) { return std::to_string(i) + "/" + std::to_string(i); }},
        // -1 is the last vertex (and texture coordinate, normal) before the face line.
        {"negative", [](int i, int n) { return std::to_string(i - n - 1) + "/" +
                                               std::to_string(i - n - 1) + "/-1"; }},
    };
    for (const auto& [name, corner] : spellings)
    {
        CAPTURE(name);
        const RawMesh raw = read_raw_mesh(write_obj_corners("corners.obj", corner));
        CHECK(raw.faces == faces);
    }
}

TEST_CASE("io: OBJ corners referring to no texture coordinate, normal or vertex are refused")
{
    SUBCASE("texture index past the last vt")
    {
        const auto path = write_obj_corners("vt_range.obj", [](int i, int n) {
            return std::to_string(i) + "/" + std::to_string(i == 1 ? n + 1 : i);
        });
        const std::string what = io_refusal(path);
        CHECK(what.find("read_raw_mesh: face ") == 0);
        CHECK(what.find(" of " + path + " refers to texture coordinate '85' (corner '1/85'), "
                        "which is not one of the 84 'vt' lines before it; the file is corrupt") !=
              std::string::npos);
    }
    SUBCASE("normal index 0")
    {
        const auto path = write_obj_corners(
            "vn_zero.obj", [](int i, int) { return std::to_string(i) + "//" + (i == 2 ? "0" : "1"); });
        CHECK(io_refusal(path).find("refers to normal '0' (corner '2//0'), which is not one of "
                                    "the 84 'vn' lines before it") != std::string::npos);
    }
    SUBCASE("negative vertex index counting back past the first vertex")
    {
        const auto path = write_obj_corners(
            "negative_range.obj", [](int i, int n) { return std::to_string(i == 3 ? -n - 1 : i); });
        CHECK(io_refusal(path).find("refers to vertex '-85', which is not one of the 84 vertices "
                                    "before it; the file is corrupt") != std::string::npos);
    }
    SUBCASE("malformed corners and too few corners")
    {
        const auto path = temp_path("corner_syntax.obj");
        for (const std::string face : {"f 1/1/1/1 2 3", "f 1/ 2 3", "f 1/1/ 2 3"})
        {
            std::ofstream(path) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\n" << face << "\n";
            CAPTURE(face);
            CHECK(io_refusal(path).find("which is not v, v/vt, v/vt/vn or v//vn; the file is "
                                        "corrupt") != std::string::npos);
        }
        std::ofstream(path) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n";
        CHECK(io_refusal(path) == "read_raw_mesh: face 0 of " + path +
                                      " has 2 corners; a face needs at least 3; the file is corrupt");
    }
}

TEST_CASE("io: a registered reader reads its extension, and built-in formats stay the library's")
{
    CHECK_THROWS_AS(vessel::register_mesh_reader("vtp", {}), vessel::InvalidInputError);
    CHECK_THROWS_AS(vessel::register_mesh_reader(".ply", {}), vessel::InvalidInputError);

    const auto dir = std::filesystem::temp_directory_path() / "vessel_io_registry";
    std::filesystem::create_directories(dir);
    const std::string path = (dir / "tri.xyzmesh").string();
    std::ofstream(path) << "one triangle\n";
    CHECK_THROWS_AS(vessel::read_raw_mesh(path), vessel::IoError);  // unknown until registered

    std::string seen;
    vessel::register_mesh_reader(".xyzmesh", [&seen](const std::string& p) {
        seen = p;
        vessel::RawMesh raw;
        raw.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
        raw.faces = {{0, 1, 2}};
        return raw;
    });
    const vessel::RawMesh raw = vessel::read_raw_mesh(path);
    CHECK(seen == path);
    CHECK(raw.faces.size() == 1);
    std::filesystem::remove_all(dir);
}
