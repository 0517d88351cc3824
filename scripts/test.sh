#!/usr/bin/env bash
# Builds everything and runs the whole test suite (unit tests, CLI on ../shared real meshes).
# Arguments go to ctest (e.g. scripts/test.sh -R cli). The readers' fuzzers run apart
# (scripts/fuzz.sh, docs/bad-input.md): short runs still find hangs of OpenMesh's PLY reader.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh
ctest --test-dir build --output-on-failure -j2 -LE fuzz "$@"
