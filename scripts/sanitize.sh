#!/usr/bin/env bash
# Builds libvessel, its tools and the whole test suite with AddressSanitizer + UndefinedBehavior-
# Sanitizer (-DVESSEL_SANITIZE=ON, no recovery: the first report fails the test) into
# build-sanitize/ and runs every test (the `fuzz` label is not built here).
# Extra arguments go to ctest (e.g. -R cli).
#
# scripts/sanitize.sh --bad-input: builds only vessel-flatten, vessel-phantom and the bad-input
# tests (vessel_bad_input_tests: readers, fuzzer findings, outputs, atomic writes, the CLI's
# refusals) and runs those; what scripts/test.sh runs in CI.
set -euo pipefail
cd "$(dirname "$0")/.."
"$(dirname "$0")/install-deps.sh"
export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$PWD}"
cmake -S . -B build-sanitize -DCMAKE_BUILD_TYPE=Release -DVESSEL_SANITIZE=ON \
  -DCMAKE_CXX_COMPILER_LAUNCHER="${CMAKE_CXX_COMPILER_LAUNCHER:-ccache}" > /dev/null
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:strict_string_checks=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:suppressions=$PWD/scripts/ubsan.supp"
export LSAN_OPTIONS="suppressions=$PWD/scripts/lsan.supp"
if [ "${1:-}" = "--bad-input" ]; then
  nice cmake --build build-sanitize -j"$(nproc)" --target vessel_bad_input_tests
  exec build-sanitize/bin/vessel_bad_input_tests
fi
nice cmake --build build-sanitize -j"$(nproc)"
# The batch over the real meshes (label `slow`) leaves out files over 1.1 MB here (the 207k and
# 277k trees, the 69k .ply; the 69k .vtp stays): under ASan they take many minutes each. The
# normal build (scripts/test.sh) runs it over every file.
export VESSEL_BATCH_MAX_BYTES=1100000
ctest --test-dir build-sanitize --output-on-failure -j2 -LE fuzz "$@"
