#!/usr/bin/env bash
# Builds the libFuzzer targets of the readers (fuzz/: clang, ASan + UBSan) into build-fuzz/ and
# runs each for SECONDS (default 10) from the seeds fuzz_seeds writes and the fuzzers' findings
# kept in tests/data/fuzz. The libFuzzer seed is fixed (VESSEL_FUZZ_SEED, default 1); a run
# bounded by time still need not meet the same inputs each time (docs/bad-input.md, "Fuzzing").
# Set VESSEL_FUZZ_SEED=0 for a random seed.
# Any crash, sanitizer report, leak or input over 10 s fails the run; its input is written to
# build-fuzz/fuzz/artifacts/.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-10}
"$(dirname "$0")/install-deps.sh"
export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$PWD}"
CXX=clang++ cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=Release -DVESSEL_BUILD_FUZZERS=ON \
  -DVESSEL_BUILD_TESTS=OFF -DVESSEL_BUILD_TOOLS=OFF -DVESSEL_BUILD_PYTHON=OFF \
  -DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DVESSEL_FUZZ_SECONDS="$seconds" > /dev/null
# The fuzz targets only: the library's own targets (solvers, tools) are configured too, but no
# fuzz target needs them.
nice cmake --build build-fuzz -j"$(nproc)" --target fuzz_seeds fuzz_read_obj fuzz_read_off \
  fuzz_read_ply fuzz_read_stl fuzz_read_vtp fuzz_read_vtk
VESSEL_FUZZ_SEED="${VESSEL_FUZZ_SEED:-1}" \
  ctest --test-dir build-fuzz --output-on-failure -j"$(nproc)" -L fuzz
