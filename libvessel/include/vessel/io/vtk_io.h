#pragma once

#include "vessel/fields/fields.h"
#include "vessel/io/io.h"

#include <string>
#include <vector>

namespace vessel {

//! \file VTK PolyData files (`.vtp` XML, legacy `.vtk`) read and written through VTK 9; VTK
//! itself stays private to libvessel.

//! A surface with its data arrays, as stored in a VTK PolyData file.
struct PolyData
{
    //! Points and polygons (VTK "Polys"), in file order. Vertices, lines and strips are not
    //! part of a vessel wall and are refused when read.
    RawMesh mesh;
    std::vector<Field> point_data;  //!< rows = `mesh.points`
    std::vector<Field> cell_data;   //!< rows = `mesh.faces`
    //! Name of a 2-component point field written as the texture coordinates (empty: none).
    std::string tcoords;
};

//! How write_polydata() encodes a file.
enum class VtkEncoding
{
    Ascii,     //!< text (XML or legacy)
    Binary,    //!< XML: base64 inline data; legacy: binary
    Appended,  //!< XML only: raw binary block after the XML (ParaView's default)
};

//! Compression of a `.vtp`'s binary or appended data (VTK's `SetCompressorType`).
enum class VtkCompressor
{
    None,
    ZLib,  //!< VTK's and ParaView's default
    LZ4,   //!< fastest to read and write, larger files
    LZMA,  //!< smallest files, slowest to write
};

struct VtkWriteOptions
{
    VtkEncoding encoding = VtkEncoding::Appended;  //!< default: compact and fast
    //! XML binary/appended data only (ignored for ascii and legacy `.vtk`).
    VtkCompressor compressor = VtkCompressor::ZLib;
};

//! \brief Read a `.vtp` (ascii, binary or appended; uncompressed or zlib, lz4 or lzma) or legacy `.vtk`
//! POLYDATA file with all its point and cell data arrays (scalars, vectors, tensors; float,
//! double and integer types). Field data arrays are ignored. A `.vtu` is read with
//! read_unstructured_grid() and must be a surface (polygon cells only).
//! \throw IoError if the file is missing, unreadable, not PolyData, or holds vertex, line or
//! strip cells (the message says how to remove them); for a `.vtu`, if it holds volume cells.
PolyData read_polydata(const std::string& path);

//! A `.vtu` as read_unstructured_grid() returns it.
struct UnstructuredGrid
{
    //! Points and point arrays; if every cell is a polygon (triangle, quad, polygon: a surface
    //! stored as an unstructured grid), also the cells as `mesh.faces` with the cell arrays.
    PolyData data;
    //! With any other cell (tetrahedra: a volume mesh), `data` has no faces and no cell arrays;
    //! the names of the cell arrays left out.
    std::vector<std::string> volume_cell_arrays;
    bool is_volume() const { return data.mesh.faces.empty(); }
};

//! \brief Read a `.vtu` (VTK XML UnstructuredGrid, what svFSI and other CFD solvers write). A
//! volume's point values can be matched to a wall surface by an id array or by position
//! (read_field_series()); its cells cannot.
//! \throw IoError if the file is missing, unreadable or not an UnstructuredGrid.
UnstructuredGrid read_unstructured_grid(const std::string& path);

//! \brief Write \p data as `.vtp` (XML) or `.vtk` (legacy, by extension) with VTK's writers.
//! Written to a temporary name and renamed, so a failed run leaves no partial file.
//! \throw InvalidInputError if a field's row count does not match, or the extension is neither.
//! \throw IoError if writing fails.
void write_polydata(const std::string& path, const PolyData& data,
                    const VtkWriteOptions& options = {});

//! True if \p path ends in `.vtp`, `.vtk` or `.vtu` (any case): read_polydata() reads it.
bool is_vtk_path(const std::string& path);

//! \brief Let read_raw_mesh() (io.h) read `.vtp`, `.vtk` and `.vtu` files through read_polydata().
//! Idempotent. Called automatically in every program that includes this header (below), so a
//! program linking `vessel::vtk` never needs to call it; the core library itself does not link
//! VTK.
bool register_vtk_formats();

namespace detail {
//! Registers the VTK formats during static initialization of any program including this header.
inline const bool vtk_formats_registered = register_vtk_formats();
}  // namespace detail

}  // namespace vessel
