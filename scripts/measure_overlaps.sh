#!/usr/bin/env bash
# Flattens every valid real tree and seeded tree phantoms (3, 10, 20, 30 outlets) with the given
# vessel-flatten options and prints one line per mesh: faces, flips, exact overlap figures (the
# report's quality), mean |log area ratio|, flatcheck.py's raster overlap fraction and smoothed
# seam alignment, the total seconds of the report, relief cuts kept, and how the map started.
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
printf "%-34s %7s %5s %7s %10s %10s %8s %9s %6s %7s %6s %s\n" mesh faces flips overlap area fraction \
  logarea flatcheck align total relief start
for input in "${inputs[@]}"; do
  stem=$(basename "${input%.*}")
  # SKIP: an extended regex of stems to leave out (e.g. the 277k-face mesh on a busy machine).
  if [ -n "${SKIP:-}" ] && [[ $stem =~ $SKIP ]]; then continue; fi
  if ! "$build/bin/vessel-flatten" "$input" -o "$out/$stem.obj" --report "$out/$stem.json" -q "$@" \
      2> "$out/$stem.err"; then
    printf "%-34s failed: %s\n" "$stem" "$(tail -1 "$out/$stem.err")"; continue
  fi
  /usr/bin/python3 "$tools/flatcheck.py" "$input" "$out/$stem.obj" --json > "$out/$stem.flatcheck.json" \
    2>/dev/null
  /usr/bin/python3 - "$out/$stem.json" "$stem" "$out/$stem.flatcheck.json" <<'PY'
import json, sys
j = json.load(open(sys.argv[1])); q = j["quality"]
try:
    f = json.load(open(sys.argv[3]))
    fc, align = f.get("overlap_fraction"), f.get("seam", {}).get("alignment_smoothed")
except (OSError, ValueError):
    fc = align = None
start = "Tutte" if any("Tutte" in n for n in j.get("notes", [])) else "layout"
print(f"{sys.argv[2]:34s} {j['counts']['faces']:7d} {q['flipped_triangles']:5d} "
      f"{q['overlapping_triangles']:7d} {q['overlap_area']:10.4g} {q['overlap_fraction']:10.3g} "
      f"{q['mean_abs_log_area_ratio']:8.4f} {fc if fc is None else round(fc, 4)!s:>9s} "
      f"{align if align is None else round(align, 3)!s:>6s} {j['timings']['total']:7.2f} "
      f"{len(j.get('relief_cuts', [])):6d} {start}")
PY
done
