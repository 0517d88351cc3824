#!/usr/bin/env bash
# Configures and builds libvessel, its tools, tests and benchmarks into build/ (Release).
set -euo pipefail
cd "$(dirname "$0")/.."
"$(dirname "$0")/install-deps.sh"
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DVESSEL_BUILD_BENCHMARKS=ON "$@"
cmake --build build -j"$(nproc)"
