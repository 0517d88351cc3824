// The OFF variants read_raw_mesh() reads (detail/off_reader.h) and those it refuses
// (docs/bad-input.md, "OFF variants").
#include <doctest/doctest.h>

#include "support/checks.h"
#include "support/io_refusal.h"
#include "support/meshes.h"
#include "vessel/core/errors.h"
#include "vessel/io/io.h"
#include "vessel/phantom/phantom.h"

#include <OpenMesh/Core/IO/MeshIO.hh>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <utility>

using namespace vessel;
using vessel::test::io_refusal;

namespace {

std::string temp_path(const std::string& name)
{
    static const std::string dir = vessel::test::temp_dir("off_reader");
    return dir + "/" + name;
}

const RawMesh& tube()
{
    static const RawMesh raw = to_raw_mesh(open_cylinder(1.0, 4.0, 12, 6));
    return raw;
}

// Writes tube() as ASCII OFF: \p header (the keyword line), \p counts (the counts line, or
// empty when the header holds them), each vertex line from \p vertex and each face line from
// \p face, with a comment and a blank line between the sections.
std::string write_ascii(const std::string& name, const std::string& header,
                        const std::string& counts,
                        const std::function<std::string(const Eigen::Vector3d&)>& vertex,
                        const std::string& face_suffix = "")
{
    const RawMesh& t = tube();
    std::ostringstream out;
    out.precision(17);
    out << header << "\n# written by off_reader_test\n";
    if (!counts.empty())
        out << counts << "\n";
    out << "\n";
    for (const auto& p : t.points)
        out << vertex(p) << "\n";
    out << "# faces\n\n";
    for (const auto& f : t.faces)
        out << "3 " << f[0] << " " << f[1] << " " << f[2] << face_suffix << "  # a face\n";
    const std::string path = temp_path(name);
    std::ofstream(path, std::ios::binary) << out.str();
    return path;
}

std::string xyz(const Eigen::Vector3d& p)
{
    std::ostringstream out;
    out.precision(17);
    out << p.x() << " " << p.y() << " " << p.z();
    return out.str();
}

std::string counts()
{
    return std::to_string(tube().points.size()) + " " + std::to_string(tube().faces.size());
}

// Largest distance between a point read and tube()'s; faces must be tube()'s exactly.
double read_error(const std::string& path)
{
    const RawMesh raw = read_raw_mesh(path);
    REQUIRE(raw.points.size() == tube().points.size());
    CHECK(raw.faces == tube().faces);
    double error = 0;
    for (std::size_t i = 0; i < raw.points.size(); ++i)
        error = std::max(error, (raw.points[i] - tube().points[i]).norm());
    return error;
}

// Binary OFF of tube(): 32-bit words in the given byte order, float coordinates (with
// \p extra_floats zeros after each vertex) and, if \p color_count, a colour count 0 per face.
std::string write_binary(const std::string& name, const std::string& header, bool big_endian,
                         bool color_count, int extra_floats = 0)
{
    const RawMesh& t = tube();
    std::string data = header + "\n";
    auto word = [&](std::uint32_t u) {
        for (int k = 0; k < 4; ++k)
            data.push_back(static_cast<char>(big_endian ? (u >> (24 - 8 * k)) & 0xff
                                                        : (u >> (8 * k)) & 0xff));
    };
    auto real = [&](float f) {
        std::uint32_t u = 0;
        std::memcpy(&u, &f, 4);
        word(u);
    };
    word(static_cast<std::uint32_t>(t.points.size()));
    word(static_cast<std::uint32_t>(t.faces.size()));
    word(0);
    for (const auto& p : t.points)
    {
        real(static_cast<float>(p.x()));
        real(static_cast<float>(p.y()));
        real(static_cast<float>(p.z()));
        for (int k = 0; k < extra_floats; ++k)
            real(0.5f);
    }
    for (const auto& f : t.faces)
    {
        word(3);
        for (int v : f)
            word(static_cast<std::uint32_t>(v));
        if (color_count)
            word(0);
    }
    const std::string path = temp_path(name);
    std::ofstream(path, std::ios::binary) << data;
    return path;
}

}  // namespace

TEST_CASE("off: every ASCII header variant is read, comments and blank lines skipped")
{
    SUBCASE("OFF, counts line V F E")
    {
        CHECK(read_error(write_ascii("plain.off", "OFF", counts() + " 0", xyz)) < 1e-12);
    }
    SUBCASE("OFF, counts line V F (no edge count)")
    {
        CHECK(read_error(write_ascii("no_edges.off", "OFF", counts(), xyz)) < 1e-12);
    }
    SUBCASE("OFF, counts on the header line")
    {
        CHECK(read_error(write_ascii("same_line.off", "OFF " + counts() + " 0", "", xyz)) < 1e-12);
    }
    SUBCASE("COFF, NOFF, CNOFF, STOFF: colours, normals, texture coordinates ignored")
    {
        // Header, what follows x y z on each vertex line (face lines end with a colour).
        const std::pair<const char*, const char*> variants[] = {
            {"COFF", " 255 128 0 255"},
            {"NOFF", " 0 0 1"},
            {"CNOFF", " 0 0 1 0.1 0.2 0.3 1"},
            {"STOFF", " 0.25 0.75"},
        };
        for (const auto& [header, rest] : variants)
        {
            CAPTURE(header);
            const std::string tail = rest;
            const auto path = write_ascii(std::string(header) + ".off", header, counts() + " 0",
                                          [&](const auto& p) { return xyz(p) + tail; },
                                          " 0.5 0.5 0.5 1");
            CHECK(read_error(path) < 1e-12);
        }
    }
    SUBCASE("4OFF: homogeneous coordinates are divided by w")
    {
        const auto path = write_ascii("homogeneous.off", "4OFF", counts() + " 0",
                                      [](const auto& p) { return xyz(2.0 * p) + " 2"; });
        CHECK(read_error(path) < 1e-12);
    }
    SUBCASE("nOFF of dimension 3, dimension and counts on their own lines")
    {
        CHECK(read_error(write_ascii("ndim.off", "nOFF\n3", counts() + " 0", xyz)) < 1e-12);
    }
    SUBCASE("4nOFF of dimension 3")
    {
        const auto path = write_ascii("4n.off", "4nOFF 3", counts() + " 0",
                                      [](const auto& p) { return xyz(4.0 * p) + " 4"; });
        CHECK(read_error(path) < 1e-12);
    }
}

TEST_CASE("off: binary OFF is read big-endian (Geomview) or little-endian (OpenMesh)")
{
    SUBCASE("OFF BINARY, big-endian with a colour count per face (Geomview)")
    {
        CHECK(read_error(write_binary("geomview.off", "OFF BINARY", true, true)) < 1e-6);
    }
    SUBCASE("OFF BINARY, little-endian without colour counts")
    {
        CHECK(read_error(write_binary("little.off", "OFF BINARY", false, false)) < 1e-6);
    }
    SUBCASE("NOFF BINARY, big-endian: normals skipped")
    {
        CHECK(read_error(write_binary("normals_bin.off", "NOFF BINARY", true, true, 3)) < 1e-6);
    }
    SUBCASE("as OpenMesh's writer writes it")
    {
        const Mesh mesh = open_cylinder(1.0, 4.0, 12, 6);
        const std::string path = temp_path("openmesh_binary.off");
        REQUIRE(OpenMesh::IO::write_mesh(mesh, path, OpenMesh::IO::Options::Binary));
        CHECK(read_error(path) < 1e-6);
    }
}

TEST_CASE("off: variants that are not a 3D surface and corrupt OFF files are refused")
{
    const std::string c = counts() + " 0";
    const std::string n = std::to_string(tube().points.size());
    // Written by write_ascii(): header, vertex line, the refusal after "read_raw_mesh: ".
    struct Case
    {
        const char *header, *w, *message;
    };
    for (const Case& k : {Case{"nOFF 4", " 1", "PATH is an nOFF file of dimension 4; only "
                                               "3-dimensional surfaces (x, y, z) can be flattened"},
                          Case{"4OFF", " 0", "vertex 0 of PATH has the homogeneous coordinate w = 0 "
                                             "(a point at infinity); fix or remove it in the source"}})
    {
        CAPTURE(k.header);
        const std::string w = k.w;
        const auto path = write_ascii("refused.off", k.header, c,
                                      [&](const auto& p) { return xyz(p) + w; });
        std::string message = k.message;
        message.replace(message.find("PATH"), 4, path);
        CHECK(io_refusal(path) == "read_raw_mesh: " + message);
    }
    SUBCASE("counts line that is not integers")
    {
        const auto path = write_ascii("bad_counts.off", "OFF", n + " x 0", xyz);
        CHECK(io_refusal(path) == "read_raw_mesh: " + path + " is truncated or corrupt: the OFF "
                                   "counts line '" + n + " x 0' is not 'V F' or 'V F E' "
                                   "(integers); re-export or re-download the file");
    }
    SUBCASE("vertex line with two coordinates")
    {
        const auto path = write_ascii("short_vertex.off", "OFF", c, [](const auto& p) {
            return std::to_string(p.x()) + " " + std::to_string(p.y());
        });
        CHECK(io_refusal(path) == "read_raw_mesh: vertex 0 of " + path +
                                   " has a NaN, infinite or unreadable coordinate (''); fix or "
                                   "remove it in the source");
    }
    SUBCASE("face index out of range and face of two corners")
    {
        const auto path = temp_path("bad_face.off");
        std::ofstream(path) << "OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n3 0 2 4\n";
        CHECK(io_refusal(path) == "read_raw_mesh: face 1 of " + path +
                                   " is malformed ('3 0 2 4'): an OFF face is a corner count (3 or "
                                   "more) and that many vertex indices below 4; the file is corrupt");
        std::ofstream(path) << "OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n2 0 2\n";
        CHECK(io_refusal(path).find("is malformed ('2 0 2')") != std::string::npos);
    }
    SUBCASE("binary OFF cut short")
    {
        const auto path = write_binary("cut.off", "OFF BINARY", true, true);
        std::filesystem::resize_file(path, std::filesystem::file_size(path) - 6);
        const std::string what = io_refusal(path);
        CHECK(what.find("is truncated or corrupt: the binary OFF data fit none of the layouts "
                        "it can have (big-endian with face colour counts: ") != std::string::npos);
    }
    SUBCASE("unknown keyword")
    {
        const auto path = temp_path("keyword.off");
        std::ofstream(path) << "XOFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
        CHECK(io_refusal(path) == "read_raw_mesh: " + path + " is truncated or corrupt: the first "
                                   "line 'XOFF' is not an OFF header ([ST][C][N][4][n]OFF "
                                   "[BINARY]); re-export or re-download the file");
    }
}
