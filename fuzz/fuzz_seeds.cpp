// Writes the seed corpus of the reader fuzzers: small phantoms (a tube, a coarse carotid
// bifurcation, a closed sphere, a tube closed by flat caps) in every format and encoding OpenMesh
// writes, and as VTK PolyData (.vtp in each encoding and compressor, legacy .vtk ascii and
// binary, with a point and a cell field), plus a few short hand-made files, into DIR/<ext>/.
#include "vessel/cut/boundary.h"
#include "vessel/io/io.h"
#include "vessel/io/vtk_io.h"
#include "vessel/phantom/phantom.h"

#include <OpenMesh/Core/IO/MeshIO.hh>

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

// An open tube with each end closed by a fan round a vertex in the loop's plane: the flat caps
// make_tree_surface() removes with TreeSurfaceOptions::remove_flat_caps.
vessel::Mesh capped_tube()
{
    vessel::Mesh mesh = vessel::open_cylinder(1.0, 2.0, 8, 2);
    for (const vessel::BoundaryLoop& loop : vessel::boundary_loops(mesh))
    {
        const auto centre = mesh.add_vertex(vessel::to_openmesh(loop.centroid));
        for (const auto h : loop.halfedges)
            mesh.add_face(mesh.from_vertex_handle(h), mesh.to_vertex_handle(h), centre);
    }
    return mesh;
}

}  // namespace

int main(int argc, char** argv)
{
    if (argc != 2)
    {
        std::fprintf(stderr, "usage: fuzz_seeds DIR\n");
        return 2;
    }
    const fs::path dir = argv[1];
    vessel::CarotidPhantomOptions carotid;
    carotid.edge_length = 1.0;
    const std::vector<std::pair<std::string, vessel::Mesh>> meshes = {
        {"tube", vessel::open_cylinder(1.0, 2.0, 6, 2)},
        {"carotid", vessel::carotid_phantom(carotid)},
        {"sphere", vessel::icosphere(1.0, 0)},
        {"capped", capped_tube()}};
    omerr().disable();
    for (const std::string ext : {"obj", "off", "ply", "stl"})
    {
        fs::create_directories(dir / ext);
        for (const auto& [name, mesh] : meshes)
            for (const bool binary : {false, true})
            {
                if (binary && ext == "obj")
                    continue;  // OBJ has no binary form
                OpenMesh::IO::Options options;
                if (binary)
                    options += OpenMesh::IO::Options::Binary;
                const fs::path path =
                    dir / ext / (name + (binary ? "_binary." : "_ascii.") + ext);
                if (!OpenMesh::IO::write_mesh(mesh, path.string(), options))
                {
                    std::fprintf(stderr, "fuzz_seeds: cannot write %s\n", path.c_str());
                    return 1;
                }
            }
    }
    // VTK PolyData through libvessel's writer (VTK's own): every encoding of each format.
    const std::vector<std::pair<std::string, vessel::VtkWriteOptions>> vtk_variants = {
        {"ascii", {vessel::VtkEncoding::Ascii, vessel::VtkCompressor::None}},
        {"binary_zlib", {vessel::VtkEncoding::Binary, vessel::VtkCompressor::ZLib}},
        {"appended_raw", {vessel::VtkEncoding::Appended, vessel::VtkCompressor::None}},
        {"appended_lz4", {vessel::VtkEncoding::Appended, vessel::VtkCompressor::LZ4}}};
    for (const std::string ext : {"vtp", "vtk"})
    {
        fs::create_directories(dir / ext);
        for (const auto& [name, mesh] : meshes)
        {
            vessel::PolyData data;
            data.mesh = vessel::to_raw_mesh(mesh);
            const auto n_points = static_cast<Eigen::Index>(data.mesh.points.size());
            const auto n_faces = static_cast<Eigen::Index>(data.mesh.faces.size());
            vessel::Field pressure;
            pressure.name = "pressure";
            pressure.values = Eigen::VectorXd::LinSpaced(n_points, 0.0, 1.0);
            data.point_data.push_back(pressure);
            vessel::Field label;
            label.name = "label";
            label.location = vessel::FieldLocation::Cell;
            label.type = vessel::FieldType::Int32;
            label.values = Eigen::VectorXd::Ones(n_faces);
            data.cell_data.push_back(label);
            for (const auto& [encoding, options] : vtk_variants)
            {
                if (ext == "vtk" && encoding.rfind("appended", 0) == 0)
                    continue;  // legacy VTK has no appended form
                vessel::write_polydata((dir / ext / (name + "_" + encoding + "." + ext)).string(),
                                       data, options);
            }
        }
    }
    std::ofstream(dir / "obj" / "quad.obj") << "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";
    std::ofstream(dir / "obj" / "slashes.obj")
        << "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\nf 1/1/1 2/1/1 -1//1\n";
    std::ofstream(dir / "off" / "counts_apart.off") << "OFF\n# comment\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    // The header variants of libvessel's own OFF reader (off_reader.cpp), one small file each.
    const std::vector<std::pair<std::string, std::string>> variants = {
        {"coff", "COFF\n3 1 0\n0 0 0 1 0 0 1\n1 0 0 0 1 0 1\n0 1 0 0 0 1 1\n3 0 1 2 255 0 0\n"},
        {"noff", "NOFF 3 1 0\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n3 0 1 2\n"},
        {"stoff", "STOFF\n3 1\n0 0 0 0 0\n1 0 0 1 0\n0 1 0 0 1\n3 0 1 2\n"},
        {"4off", "4OFF\n3 1 0\n0 0 0 1\n2 0 0 2\n0 1 0 1\n3 0 1 2\n"},
        {"noff_dim", "nOFF\n3\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"},
        {"cnoff_comments", "# lead\nCNOFF # c\n\n3 1 0\n0 0 0 0 0 1 1 1 1 1 # v\n"
                           "1 0 0 0 0 1 1 1 1 1\n0 1 0 0 0 1 1 1 1 1\n3 0 1 2\n"}};
    for (const auto& [name, text] : variants)
        std::ofstream(dir / "off" / (name + ".off")) << text;
    // Geomview's binary OFF: big-endian, a colour count after each face's indices.
    {
        std::string bytes = "OFF BINARY\n";
        const auto put = [&](std::uint32_t word) {
            for (int shift = 24; shift >= 0; shift -= 8)
                bytes.push_back(static_cast<char>((word >> shift) & 0xff));
        };
        const auto put_float = [&](float x) {
            std::uint32_t word;
            std::memcpy(&word, &x, sizeof word);
            put(word);
        };
        for (const std::uint32_t count : {3u, 1u, 0u})
            put(count);
        for (const float x : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f})
            put_float(x);
        for (const std::uint32_t word : {3u, 0u, 1u, 2u, 0u})
            put(word);
        std::ofstream(dir / "off" / "geomview_big_endian.off", std::ios::binary) << bytes;
    }
    return 0;
}
