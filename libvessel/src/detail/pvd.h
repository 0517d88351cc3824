#pragma once

// ParaView collection (.pvd) index files: the list of (time, part, file) entries. Kept apart from
// the series logic so that only pvd.cpp and vtk_io.cpp see VTK.

#include <string>
#include <vector>

namespace vessel::detail {

struct PvdEntry
{
    double time = 0.0;
    int part = 0;
    std::string file;  //!< as written in the .pvd (relative to its directory, or absolute)
};

//! Entries in file order. Throws IoError if the file is not a VTKFile of type Collection.
std::vector<PvdEntry> read_pvd(const std::string& path);

//! Writes the index (temporary file + rename). Throws IoError on failure.
void write_pvd(const std::string& path, const std::vector<PvdEntry>& entries);

}  // namespace vessel::detail
