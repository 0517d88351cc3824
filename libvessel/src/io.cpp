#include "vessel/io.h"

#include "vessel/errors.h"

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>

namespace vessel {

namespace {

using ScratchMesh = OpenMesh::PolyMesh_ArrayKernelT<>;

// Records every vertex and face the reader emits before OpenMesh's importer sees them; the
// importer duplicates vertices of faces it cannot add (non-manifold, mis-oriented) and drops
// faces with repeated corners, which would hide exactly the defects we must report.
class RecordingImporter : public OpenMesh::IO::ImporterT<ScratchMesh>
{
public:
    RecordingImporter(ScratchMesh& scratch, RawMesh& raw) : ImporterT(scratch), raw_(raw) {}

    VertexHandle add_vertex(const OpenMesh::Vec3f& p) override
    {
        return record(ImporterT::add_vertex(p), {p[0], p[1], p[2]});
    }
    VertexHandle add_vertex(const OpenMesh::Vec3d& p) override
    {
        return record(ImporterT::add_vertex(p), {p[0], p[1], p[2]});
    }
    VertexHandle add_vertex() override
    {
        return record(ImporterT::add_vertex(), Eigen::Vector3d::Zero());
    }
    void set_point(VertexHandle v, const OpenMesh::Vec3f& p) override
    {
        if (v.is_valid() && static_cast<std::size_t>(v.idx()) < raw_index_.size())
            raw_.points[raw_index_[v.idx()]] = {p[0], p[1], p[2]};
        ImporterT::set_point(v, p);
    }
    FaceHandle add_face(const VHandles& corners) override
    {
        std::vector<int>& face = raw_.faces.emplace_back();
        face.reserve(corners.size());
        for (auto v : corners)
            face.push_back(v.is_valid() && static_cast<std::size_t>(v.idx()) < raw_index_.size()
                               ? raw_index_[v.idx()]
                               : -1);
        return ImporterT::add_face(corners);
    }

private:
    // The importer adds scratch vertices of its own for faces it cannot add, so scratch handles
    // and file indices diverge after the first bad face; faces are recorded in file indices.
    VertexHandle record(VertexHandle scratch, const Eigen::Vector3d& p)
    {
        if (static_cast<std::size_t>(scratch.idx()) >= raw_index_.size())
            raw_index_.resize(scratch.idx() + 1, -1);
        raw_index_[scratch.idx()] = static_cast<int>(raw_.points.size());
        raw_.points.push_back(p);
        return scratch;
    }

    RawMesh& raw_;
    std::vector<int> raw_index_;
};

}  // namespace

RawMesh read_raw_mesh(const std::string& path)
{
    if (!std::filesystem::exists(path))
        throw IoError("read_raw_mesh: file not found: " + path);
    if (std::filesystem::file_size(path) == 0)
        throw IoError("read_raw_mesh: file is empty: " + path);
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
    if (ext != ".obj" && ext != ".off" && ext != ".ply" && ext != ".stl")
        throw IoError("read_raw_mesh: unknown file format '" + ext + "' (" + path +
                      "); use .obj, .off, .ply or .stl");
    RawMesh raw;
    ScratchMesh scratch;
    RecordingImporter importer(scratch, raw);
    OpenMesh::IO::Options options;
    // OpenMesh prints warnings for the defects we report ourselves; keep stderr for our messages.
    const bool was_enabled = omerr().is_enabled();
    omerr().disable();
    const bool ok = OpenMesh::IO::IOManager().read(path, importer, options);
    if (was_enabled)
        omerr().enable();
    if (!ok)
        throw IoError("read_raw_mesh: OpenMesh could not read " + path +
                      " (truncated or malformed file?)");
    if (raw.faces.empty())
        throw IoError("read_raw_mesh: no faces in " + path + "; expected a triangulated surface");
    return raw;
}

void write_mesh(const Mesh& mesh, const std::string& path)
{
    OpenMesh::IO::Options options;
    const std::string ext = std::filesystem::path(path).extension().string();
    if (ext == ".ply" || ext == ".stl")
        options += OpenMesh::IO::Options::Binary;
    if (!OpenMesh::IO::write_mesh(mesh, path, options))
        throw IoError("write_mesh: could not write " + path);
}

}  // namespace vessel
