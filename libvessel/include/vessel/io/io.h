#pragma once

#include "vessel/core/mesh.h"

#include <functional>
#include <string>
#include <vector>

namespace vessel {

//! A mesh exactly as stored in a file: positions and polygon corner lists, nothing repaired.
struct RawMesh
{
    std::vector<Eigen::Vector3d> points;  //!< input vertex positions, in file order
    std::vector<std::vector<int>> faces;  //!< corner indices into `points`, in file order
};

//! \brief Read OBJ, PLY (ascii/binary) or STL (ascii/binary) through OpenMesh's readers, OFF
//! (every `[ST][C][N][4][n]OFF` header, ascii or binary; docs/bad-input.md) with our own reader,
//! or any format a module registered with register_mesh_reader(): VTK PolyData (`.vtp`, legacy
//! `.vtk`) once a program includes vtk_io.h and links `vessel::vtk` (the umbrella `vessel::vessel`
//! does; the data arrays are dropped here, read them with read_polydata()).
//! STL corners at identical positions are merged by OpenMesh's STL reader, so a segmentation
//! STL becomes a connected mesh. Faces are recorded before OpenMesh sees them, so non-manifold,
//! mis-oriented and degenerate faces reach the validation instead of being silently altered.
//! Safe to call from several threads: OpenMesh's readers (process-wide singletons) are used by
//! one thread at a time.
//! \throw IoError if the file is missing, unreadable, empty, of an unknown format, truncated or
//! corrupt (the message names the line, element or index and what was expected).
RawMesh read_raw_mesh(const std::string& path);

//! Reads one file format for read_raw_mesh() (see register_mesh_reader()).
using MeshReader = std::function<RawMesh(const std::string& path)>;

//! \brief Let read_raw_mesh() read files whose extension is \p extension (lower case, with the
//! dot, e.g. ".vtp") with \p reader: how a module with its own dependencies (`vessel::vtk`) adds
//! formats without the core library linking them. A later registration of the same extension
//! replaces the earlier one. Thread-safe.
//! \throw InvalidInputError if \p extension does not start with a dot or is one of the built-in
//! formats (.obj, .off, .ply, .stl).
void register_mesh_reader(const std::string& extension, MeshReader reader);

//! The corner lists and positions of \p mesh as a RawMesh (vertex i = `VertexHandle(i)`,
//! face j = `FaceHandle(j)`), e.g. to validate a generated mesh like a file.
RawMesh to_raw_mesh(const Mesh& mesh);

//! \brief Write a mesh with OpenMesh (format from the extension; PLY is written binary),
//! atomically as write_text_file().
//! \throw IoError if writing fails.
void write_mesh(const Mesh& mesh, const std::string& path);

//! \brief Write \p text to \p path atomically: into a new temporary file beside it (a unique
//! name created exclusively, so never through an existing file or link), flushed, synced and
//! closed with every result checked, then renamed onto \p path. On any failure \p path is left
//! as it was. Every writer of libvessel writes this way.
//! \throw IoError naming \p path and the system's reason (e.g. no space left, file too large).
void write_text_file(const std::string& path, const std::string& text);

}  // namespace vessel
