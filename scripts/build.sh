#!/usr/bin/env bash
# Configures and builds libvessel, its tools, tests, benchmarks and Python package into build/
# (Release), then installs the Python package into Debian's python3 (docs/python.md).
set -euo pipefail
cd "$(dirname "$0")/.."
"$(dirname "$0")/install-deps.sh"
# ccache with paths relative to the checkout: a rebuild, or a build of the same sources in another
# clone on this machine, compiles only what changed.
export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$PWD}"
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DVESSEL_BUILD_BENCHMARKS=ON \
      -DCMAKE_CXX_COMPILER_LAUNCHER=ccache "$@"
cmake --build build -j"$(nproc)"
# `import vessel` from any folder: the package copied into /usr/bin/python3's site-packages
# (the python component; as root or through sudo, like the Debian packages).
if grep -q '^VESSEL_BUILD_PYTHON:BOOL=ON' build/CMakeCache.txt; then
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  $SUDO cmake --install build --component python
fi
