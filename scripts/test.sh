#!/usr/bin/env bash
# Builds everything and runs the whole test suite (unit tests, CLI on ../shared real meshes).
# Without arguments (as .ci/run calls it) it then runs each reader's fuzzer briefly
# (scripts/fuzz.sh: 10 s per target from the seeds and findings in the repository, libFuzzer
# seed 1) and the bad-input tests under AddressSanitizer + UBSan (scripts/sanitize.sh
# --bad-input: its own -O0 build of the library, vessel-flatten and vessel-phantom;
# docs/bad-input.md, "In CI"). Arguments go to ctest and leave both out
# (e.g. scripts/test.sh -R cli).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh
ctest --test-dir build --output-on-failure -j2 -LE fuzz "$@"
if [ $# -eq 0 ]; then
  scripts/fuzz.sh 10
  scripts/sanitize.sh --bad-input
fi
