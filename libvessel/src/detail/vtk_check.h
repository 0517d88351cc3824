#pragma once

// Structure checks of VTK files before VTK's readers parse them. Debian's VTK 9 readers trust
// the counts in a file: a legacy .vtk cut short inside POLYGONS, a legacy cell that claims two
// billion corners, or a zlib-compressed .vtp whose block header claims 0 (or 2^31) blocks end
// in a segmentation fault or a multi-gigabyte allocation. These checks bound every count by the
// file's size and by the counts declared before it, and throw IoError instead.

#include <string>

namespace vessel::detail {

//! \brief A legacy `.vtk` POLYDATA file (VTK "File Formats", legacy format, versions 2 to 5.1,
//! ASCII or BINARY): POINTS has its 3 x N values, each cell section (VERTICES, LINES, POLYGONS,
//! TRIANGLE_STRIPS; legacy `n size` lists or 5.x OFFSETS/CONNECTIVITY) has all its values, the
//! cell sizes add up to the declared size and every point index is below the point count.
//! Sections after the cells (POINT_DATA, CELL_DATA) are bounded by the file size.
//! \throw IoError "read_polydata: PATH is truncated or corrupt: WHAT; ..." on the first defect.
void check_legacy_vtk(const std::string& path);

//! \brief A VTK XML `.vtp` file with appended raw data: every appended DataArray's offset lies in
//! the data, and for compressed data (`compressor=...`) the block header (number of blocks,
//! block sizes, compressed sizes) fits in the file, the compressed sizes fit in the data, the
//! uncompressed size is at most what the piece's counts need (points, cells) and not empty
//! when they need data.
//! \throw IoError as check_legacy_vtk().
void check_vtp(const std::string& path);

}  // namespace vessel::detail
