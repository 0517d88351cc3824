#pragma once

// Structure checks of VTK files before VTK's readers parse them. Debian's VTK 9 readers trust
// the counts in a file: a legacy .vtk cut short inside POLYGONS, a legacy cell that claims two
// billion corners, or a zlib-compressed .vtp whose block header claims 0 (or 2^31) blocks end
// in a segmentation fault or a multi-gigabyte allocation. These checks bound every count by the
// file's size and by the counts declared before it, and throw IoError instead.

#include <string>

namespace vessel::detail {

//! \brief A legacy `.vtk` file (VTK "File Formats", legacy format, versions 2 to 5.1, ASCII or
//! BINARY), walked the way vtkDataReader and vtkPolyDataReader read it, so that they meet no
//! error path (several end in a null stream or a wild read): whole keywords only; POINTS has its
//! 3 x N values; each cell section (VERTICES, LINES, POLYGONS, TRIANGLE_STRIPS; legacy `n size`
//! lists or 5.x OFFSETS/CONNECTIVITY) has all its values, the cell sizes add up to the declared
//! size and every point index is below the point count; POINT_DATA and CELL_DATA match the point
//! and cell counts and hold FIELD, SCALARS (with LOOKUP_TABLE), COLOR_SCALARS, LOOKUP_TABLE,
//! VECTORS, NORMALS, TEXTURE_COORDINATES, TENSORS, GLOBAL_IDS or PEDIGREE_IDS arrays of numeric
//! types, each with all its values; an array may be followed by a METADATA block. Every count
//! is bounded by the file's size. ASCII values must be numbers that C++ stream extraction reads
//! in full (no `nan`, `inf`, hexadecimal or values beyond the type's range, e.g. 1e39 as float).
//! \return false if the file is a legacy VTK file of another data set (not POLYDATA).
//! \throw IoError "read_polydata: PATH is truncated or corrupt: WHAT; ..." on the first defect,
//! or "read_polydata: PATH uses WHAT, which this reader does not accept ..." for keywords and
//! types outside that list (string arrays, bit arrays).
bool check_legacy_vtk(const std::string& path);

//! \brief A VTK XML `.vtp` file ("VTK File Formats", XML): every binary DataArray, inline (base64
//! in the element) or appended (raw or base64 after <AppendedData>), has a size header that fits
//! in the data; for compressed data (`compressor=...`) the block header (number of blocks, block
//! sizes, compressed sizes) fits, the compressed sizes fit in the data, the uncompressed size is
//! what the piece's counts need (points, cells) and the expansion is below 2048-fold. The
//! piece's counts are bounded by the file's size; each cell section's offsets rise from 0 to at
//! most its connectivity's length (vtkXMLPolyDataReader allocates the connectivity from the
//! last offset before reading it). Tags are scanned by hand: std::regex recurses once per
//! character and overflows the stack on a long tag.
//! \throw IoError as check_legacy_vtk().
void check_vtp(const std::string& path);

}  // namespace vessel::detail
