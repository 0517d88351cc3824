#include <doctest/doctest.h>

#include "support/checks.h"
#include "support/io_refusal.h"
#include "vessel/core/errors.h"
#include "vessel/io/io.h"
#include "vessel/phantom/phantom.h"

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
    // Face 2 is non-manifold (third face on edge 0-1): OpenMesh's importer duplicates its
    // vertices, but the raw mesh must keep the file's indices.
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
        {"ply_property_before_element.ply", "the PLY header has an unknown line 'elem????ent"},
        // OpenMesh's OBJ reader failed an assertion on the corner "/1/1".
        {"obj_bad_face_index.obj", "face 0 of " + dir + "obj_bad_face_index.obj refers to vertex '/1/1'"},
        // OpenMesh's OFF reader read the count "3OFF" and looped for minutes.
        {"off_unreadable_face_count.off", "is malformed ('3850651 0'): an OFF face is a corner count"},
        // A header "OFFSt9tyBINARY...": OpenMesh read garbage counts and allocated 13 GB.
        {"off_bad_header.off", "the first line 'OFFSt9tyBINARYm"},
        // "element vertet x" (no count) and a property type "floty": OpenMesh's PLY reader hung.
        {"ply_unreadable_element_count.ply",
         "the PLY header line 'element vertet x' does not declare a valid element count"},
        // A form feed inside "property float z": OpenMesh's PLY reader split the line there and
        // looped (a 10 s timeout of the CI's fuzz run).
        {"ply_form_feed_in_property.ply",
         "the PLY header line 'property float z?element f????20' does not have the words"},
        // "format binary_little_endian ty float z": OpenMesh's PLY reader looped.
        {"ply_format_line_extra_words.ply",
         "the PLY header line 'format binary_little_endian ty float z' does not have the words"},
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
