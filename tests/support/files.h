#pragma once

// Reading, writing and listing files in tests that check what a run wrote.

#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <string>

namespace vessel::test {

//! The bytes of the file \p path ("" if it cannot be read).
inline std::string read_bytes(const std::string& path)
{
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
}

//! Writes \p bytes to \p path (replacing it).
inline void write_bytes(const std::string& path, const std::string& bytes)
{
    std::ofstream(path, std::ios::binary) << bytes;
}

//! The names of the entries of the folder \p dir.
inline std::set<std::string> folder_names(const std::string& dir)
{
    std::set<std::string> names;
    for (const auto& e : std::filesystem::directory_iterator(dir))
        names.insert(e.path().filename().string());
    return names;
}

}  // namespace vessel::test
