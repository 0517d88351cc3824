#!/usr/bin/env bash
# Flattens every valid real tree and seeded tree phantoms (3, 10, 20, 30 outlets) with the given
# vessel-flatten options and prints one line per mesh: faces, flips, exact overlap figures (the
# report's quality), mean |log area ratio|, and flatcheck.py's raster overlap fraction.
#   scripts/measure_overlaps.sh BUILD_DIR OUT_DIR [vessel-flatten options...]
set -uo pipefail
build=$1; out=$2; shift 2
mkdir -p "$out"
data=$(cd "$(dirname "$0")/../../shared/data/real" && pwd)
tools=$(cd "$(dirname "$0")/../../shared/tools" && pwd)
meshes=(
  vmtk-test-data/aorta-surface-open-ends.ply vampy/artery.ply vampy/artery-coarse.ply
  vmtk-old-website/aneurisk-id1-lateral-aneurysm.ply svfsi-tests/pulmonary-glenn-wall.ply
  svfsi-tests/pulmonary-glenn-wall-split4.ply x-ray-angio-data/coronary-phantom-tri3-coarse.ply
  x-ray-angio-data/coronary-clinical-branch-fine.ply simvascular-tests/demo-model-open.ply
)
inputs=()
for m in "${meshes[@]}"; do inputs+=("$data/$m"); done
for n in 3 10 20 30; do
  p="$out/tree$n.ply"
  [ -f "$p" ] || "$build/bin/vessel-phantom" tree --outlets "$n" --seed "$n" -o "$p"
  inputs+=("$p")
done
printf "%-34s %7s %5s %7s %10s %10s %8s %9s\n" mesh faces flips overlap area fraction logarea flatcheck
for input in "${inputs[@]}"; do
  stem=$(basename "${input%.*}")
  # SKIP: an extended regex of stems to leave out (e.g. the 277k-face mesh on a busy machine).
  if [ -n "${SKIP:-}" ] && [[ $stem =~ $SKIP ]]; then continue; fi
  if ! "$build/bin/vessel-flatten" "$input" -o "$out/$stem.obj" --report "$out/$stem.json" -q "$@" \
      2> "$out/$stem.err"; then
    printf "%-34s failed: %s\n" "$stem" "$(tail -1 "$out/$stem.err")"; continue
  fi
  fc=$(/usr/bin/python3 "$tools/flatcheck.py" "$input" "$out/$stem.obj" --json 2>/dev/null |
       /usr/bin/python3 -c "import json,sys; print(json.load(sys.stdin).get('overlap_fraction'))")
  /usr/bin/python3 - "$out/$stem.json" "$stem" "$fc" <<'PY'
import json, sys
j = json.load(open(sys.argv[1])); q = j["quality"]
print(f"{sys.argv[2]:34s} {j['counts']['faces']:7d} {q['flipped_triangles']:5d} "
      f"{q['overlapping_triangles']:7d} {q['overlap_area']:10.4g} {q['overlap_fraction']:10.3g} "
      f"{q['mean_abs_log_area_ratio']:8.4f} {sys.argv[3]:>9s}")
PY
done
