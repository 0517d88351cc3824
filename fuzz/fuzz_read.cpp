// libFuzzer target: bytes -> a file with extension VESSEL_FUZZ_EXT -> read_raw_mesh() ->
// make_tree_surface(), as it is and with its flat caps removed. The documented errors (IoError,
// InvalidInputError, TopologyError) are the expected answers to bad bytes; anything else
// (another exception, a crash, a sanitizer report, a hang) is a bug.
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
        const vessel::RawMesh raw = vessel::read_raw_mesh(input_path());
        vessel::TreeSurfaceOptions caps;
        caps.remove_flat_caps = true;
        for (const auto& options : {vessel::TreeSurfaceOptions{}, caps})
            try
            {
                vessel::make_tree_surface(raw, options);
            }
            catch (const vessel::InvalidInputError&)
            {}
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
