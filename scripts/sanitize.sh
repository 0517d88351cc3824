#!/usr/bin/env bash
# Builds libvessel, its tools and the whole test suite with AddressSanitizer + UndefinedBehavior-
# Sanitizer (-DVESSEL_SANITIZE=ON, -O1, no recovery: the first report fails the test) into
# build-sanitize/ and runs every test (the `fuzz` label is not built here).
# Extra arguments go to ctest (e.g. -R cli).
#
# scripts/sanitize.sh --bad-input: builds only vessel-flatten, vessel-phantom and the bad-input
# tests (vessel_bad_input_tests: readers, fuzzer findings, outputs, atomic writes, the CLI's
# refusals) at -O0 into build-sanitize-bad-input/ and runs those; what scripts/test.sh runs in
# CI after the test suite and the fuzzers. -O0 halves the build from scratch (docs/bad-input.md,
# "In CI"); the tests' inputs are small enough for its slower numeric stages.
set -euo pipefail
cd "$(dirname "$0")/.."
"$(dirname "$0")/install-deps.sh"
export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$PWD}"
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:strict_string_checks=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:suppressions=$PWD/scripts/ubsan.supp"
export LSAN_OPTIONS="suppressions=$PWD/scripts/lsan.supp"
# configure DIR OPT: a VESSEL_SANITIZE build at optimization level OPT in DIR.
configure() {
  cmake -S . -B "$1" -DCMAKE_BUILD_TYPE=Release -DVESSEL_SANITIZE=ON -DVESSEL_SANITIZE_OPT="$2" \
    -DCMAKE_CXX_COMPILER_LAUNCHER="${CMAKE_CXX_COMPILER_LAUNCHER:-ccache}" > /dev/null
}
if [ "${1:-}" = "--bad-input" ]; then
  configure build-sanitize-bad-input -O0
  nice cmake --build build-sanitize-bad-input -j"$(nproc)" --target vessel_bad_input_tests
  exec build-sanitize-bad-input/bin/vessel_bad_input_tests
fi
configure build-sanitize -O1
nice cmake --build build-sanitize -j"$(nproc)"
# The batch over the real meshes (label `slow`) leaves out files over 1.1 MB here (the 207k and
# 277k trees, the 69k .ply; the 69k .vtp stays): under ASan they take many minutes each. The
# normal build (scripts/test.sh) runs it over every file.
export VESSEL_BATCH_MAX_BYTES=1100000
ctest --test-dir build-sanitize --output-on-failure -j2 -LE fuzz "$@"
