#!/usr/bin/env bash
# Installs the Debian packages libvessel needs to build, test and render (idempotent).
# python3-dev, pybind11-dev: the Python package (docs/python.md); python3-pytest runs its tests;
# snakemake runs the cohort workflow (docs/cohort.md).
# chromium: the viewer's end-to-end test (headless). nodejs and npm: the viewer bundle (npm ci,
# esbuild) and that test's driver; Debian's are installed unless a node and an npm are already on
# the PATH (e.g. NodeSource's nodejs, which bundles its own npm and conflicts with Debian's).
# libopenblas0-pthread: becomes the libblas.so.3 alternative, so CHOLMOD's supernodal factorizations
# run on OpenBLAS instead of ATLAS or the reference BLAS (1.3-1.5x less CPU for a whole run,
# docs/design.md); libvessel holds it at one thread (solve/serial_openmp.h).
# clang, libclang-rt-14-dev: the libFuzzer targets of the readers (fuzz/, scripts/fuzz.sh).
set -euo pipefail
packages=(
  build-essential cmake pkg-config ccache clang libclang-rt-14-dev
  libopenmesh-dev libeigen3-dev libspectra-dev libceres-dev libsuitesparse-dev
  doctest-dev libcli11-dev nlohmann-json3-dev libbenchmark-dev libcgal-dev libboost-dev
  libopenblas0-pthread
  libcairo2-dev
  libvtk9-dev
  python3 python3-numpy python3-matplotlib python3-vtk9
  python3-dev pybind11-dev python3-pytest snakemake
  chromium
)
if ! command -v node > /dev/null || ! command -v npm > /dev/null; then
  packages+=(nodejs npm)
fi
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "installing: ${missing[*]}"
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
