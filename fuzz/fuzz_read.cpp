// libFuzzer target: bytes -> a file with extension VESSEL_FUZZ_EXT -> read_raw_mesh() ->
// make_tree_surface(). The documented errors (IoError, InvalidInputError, TopologyError) are
// the expected answers to bad bytes; anything else (another exception, a crash, a sanitizer
// report, a hang) is a bug.
#include "vessel/core/errors.h"
#include "vessel/io/io.h"
#include "vessel/check/validation.h"
#include "vessel/io/vtk_io.h"  // inputs may be .vtp/.vtk

#include <OpenMesh/Core/System/omstream.hh>

#include <cstddef>
#include <cstdint>
#include <fstream>
#include <string>
#include <unistd.h>

namespace {

const std::string& input_path()
{
    static const std::string path =
        "/tmp/vessel_fuzz_" + std::to_string(::getpid()) + VESSEL_FUZZ_EXT;
    return path;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***)
{
    omerr().disable();
    omlog().disable();
    omout().disable();
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    {
        std::ofstream out(input_path(), std::ios::binary | std::ios::trunc);
        out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    }
    try
    {
        vessel::load_tree_surface(input_path());
    }
    catch (const vessel::IoError&)
    {
    }
    catch (const vessel::InvalidInputError&)
    {
    }
    catch (const vessel::TopologyError&)
    {
    }
    return 0;
}
