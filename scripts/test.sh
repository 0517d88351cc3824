#!/usr/bin/env bash
# Builds everything and runs the whole test suite (unit tests, CLI on ../shared real meshes).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh
ctest --test-dir build --output-on-failure -j2 -LE fuzz "$@"
