#pragma once

#include "vessel/core/errors.h"
#include "vessel/io/io.h"

#include <string>

namespace vessel::test {

//! The IoError message read_raw_mesh() refuses \p path with, or "(read without an error)".
inline std::string io_refusal(const std::string& path)
{
    try
    {
        read_raw_mesh(path);
    }
    catch (const IoError& e)
    {
        return e.what();
    }
    return "(read without an error)";
}

}  // namespace vessel::test
