#pragma once

// Writing a file so that a failed run never leaves a partial one: write to PATH.tmp, then rename.

#include <cstdio>
#include <functional>
#include <string>

namespace vessel::detail {

//! Opens `path + ".tmp"` ("wb"), calls \p write with it, checks for write errors and renames it
//! to \p path. \p who names the caller in the IoError thrown on any failure.
void write_atomically(const std::string& path, const std::string& who,
                      const std::function<void(FILE*)>& write);

//! Renames `path + ".tmp"` (written by someone else, e.g. VTK) to \p path; IoError on failure.
void commit_tmp(const std::string& path, const std::string& who);

}  // namespace vessel::detail
