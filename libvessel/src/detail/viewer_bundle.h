#pragma once

#include <string>

namespace vessel::detail {

//! The viewer's JavaScript (three.js and tools/viewer/src bundled by esbuild), or an empty string
//! when the library was built without node/npm. Defined in a source generated at build time.
std::string viewer_bundle();

}  // namespace vessel::detail
