#!/usr/bin/env bash
# Makes a small test cohort in DIR from ../shared/data/real (symbolic links, nothing copied):
# valid trees and refused meshes mixed, one case with a synthetic WSS-like pulse series
# (vessel-pulse; 12 steps, not a flow result).
#   workflows/cohort/make_test_cohort.sh DIR [BUILD_BIN]
set -euo pipefail
dir=${1:?usage: make_test_cohort.sh DIR [BUILD_BIN]}
here="$(cd "$(dirname "$0")/../.." && pwd)"
bin=${2:-$here/build/bin}
real="$(cd "$here/../shared/data/real" && pwd)"
mkdir -p "$dir"
case_of() {  # case name, mesh under ../shared/data/real
  mkdir -p "$dir/$1"
  ln -sfn "$real/$2" "$dir/$1/surface.${2##*.}"
}
case_of artery-coarse vampy/artery-coarse.ply
case_of artery vampy/artery.vtp
case_of coronary-branch x-ray-angio-data/coronary-clinical-branch-fine.ply
case_of aorta-open vmtk-test-data/aorta-surface-open-ends.ply
case_of demo-open simvascular-tests/demo-model-open.ply
case_of aorta-closed vmtk-test-data/aorta-surface.vtp
case_of aneurysm-duplicate-face openlb/aneurysm3d.stl
case_of aorta-split vmtk-test-data/aorta-surface-branch-split.ply
# A series over the coarse artery: 12 steps of a travelling pulse.
"$bin/vessel-pulse" "$real/vampy/artery-coarse.ply" "$dir/artery-coarse/pulse" \
  --name WSS --steps 12 > /dev/null
mv "$dir/artery-coarse/pulse.pvd" "$dir/artery-coarse/fields.pvd"
echo "cohort: $(ls "$dir" | wc -l) cases in $dir"
