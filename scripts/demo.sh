#!/usr/bin/env bash
# Builds libvessel, generates a carotid bifurcation phantom with a 50% ICA stenosis, flattens it
# and renders the cut and the map. Results in out/demo/.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh
mkdir -p out/demo
build/bin/vessel-phantom carotid --stenosis 0.5 -o out/demo/carotid.ply
build/bin/vessel-flatten out/demo/carotid.ply -o out/demo/carotid-flat.obj \
  --report out/demo/carotid-report.json
/usr/bin/python3 tools/render_flat.py out/demo/carotid.ply out/demo/carotid-flat.obj out/demo/carotid.png
echo "demo: out/demo/carotid-flat.obj, out/demo/carotid-report.json, out/demo/carotid.png"
