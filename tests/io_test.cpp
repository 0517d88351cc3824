#include <doctest/doctest.h>

#include "vessel/errors.h"
#include "vessel/io.h"
#include "vessel/phantom.h"

#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

using namespace vessel;

namespace {

std::string temp_path(const std::string& name)
{
    const auto dir = std::filesystem::temp_directory_path() / "vessel_io_test";
    std::filesystem::create_directories(dir);
    return (dir / name).string();
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
