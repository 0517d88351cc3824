#!/usr/bin/env bash
# Installs the build tree BUILD into a fresh prefix, builds tests/consumer against it with
# find_package(vessel CONFIG), runs it, and checks that linking vessel::core pulled in neither
# VTK nor cairo.  Usage: run.sh SOURCE_DIR BUILD_DIR WORK_DIR
set -euo pipefail
src=$1 build=$2 work=$3
rm -rf "$work" && mkdir -p "$work"
cmake --install "$build" --prefix "$work/prefix" > "$work/install.log"
cmake -S "$src/tests/consumer" -B "$work/build" -DCMAKE_BUILD_TYPE=Release \
      -DCMAKE_PREFIX_PATH="$work/prefix" > "$work/configure.log"
cmake --build "$work/build" > "$work/build.log"
"$work/build/consumer"
deps=$(ldd "$work/build/consumer")
if grep -Ei 'libvtk|libcairo' <<<"$deps"; then
  echo "run.sh: the consumer of vessel::core links VTK or cairo (above)" >&2
  exit 1
fi
echo "consumer of vessel::core: built against the installed package, no VTK, no cairo"
