#pragma once

// The one line a tool prints for an exception. Our exceptions say what to fix; the standard
// library's std::bad_alloc ("std::bad_alloc") and std::filesystem::filesystem_error
// ("filesystem error: ...") name neither the input nor a remedy, so they are said again here.

#include <exception>
#include <filesystem>
#include <new>
#include <string>

namespace vessel::cli {

//! The message of \p e for a user working on \p input (a mesh file).
inline std::string error_text(const std::exception& e, const std::string& input)
{
    if (dynamic_cast<const std::bad_alloc*>(&e))
        return input + ": out of memory (std::bad_alloc): flattening it needs more memory than "
                       "this process may use; free memory, raise the limit (ulimit -v) or "
                       "flatten a coarser mesh";
    if (const auto* fs = dynamic_cast<const std::filesystem::filesystem_error*>(&e))
    {
        std::string paths = fs->path1().string();
        if (!fs->path2().empty())
            paths += " or " + fs->path2().string();
        return "cannot access " + (paths.empty() ? std::string("a file") : paths) + ": " +
               fs->code().message() + "; check that it exists and that its folders and it have "
               "the permissions needed";
    }
    return e.what();
}

}  // namespace vessel::cli
