#!/usr/bin/env bash
# Builds libvessel, generates a carotid bifurcation phantom with a 50% ICA stenosis, flattens it
# and renders the cut and the map. When ../shared/data/real is beside the checkout, also flattens
# a real internal carotid artery with an aneurysm (VaMPy's artery.vtp) with a synthetic
# travelling WSS-like pulse on it (vessel-pulse; not a flow result) and draws the map at
# t = 0.31 s as PNG (with the 3D view), SVG and PDF. Results in out/demo/.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh
mkdir -p out/demo
build/bin/vessel-phantom carotid --stenosis 0.5 -o out/demo/carotid.ply
build/bin/vessel-flatten out/demo/carotid.ply -o out/demo/carotid-flat.obj \
  --report out/demo/carotid-report.json
/usr/bin/python3 tools/render_flat.py out/demo/carotid.ply out/demo/carotid-flat.obj out/demo/carotid.png
echo "demo: out/demo/carotid-flat.obj, out/demo/carotid-report.json, out/demo/carotid.png"

artery=../shared/data/real/vampy/artery.vtp
if [ ! -f "$artery" ]; then
  echo "demo: $artery not found; skipped the real carotid-like mesh"
  exit 0
fi
build/bin/vessel-pulse "$artery" out/demo/artery-pulse --name WSS_synthetic
build/bin/vessel-flatten "$artery" -o out/demo/artery-flat.vtp \
  --fields out/demo/artery-pulse.pvd --field WSS_synthetic --report out/demo/artery-report.json \
  --image out/demo/artery-wss.png --image-3d --image-time 0.31 --image-units Pa
build/bin/vessel-flatten "$artery" -o out/demo/artery-flat.vtp \
  --fields out/demo/artery-pulse.pvd --field WSS_synthetic --quiet \
  --image out/demo/artery-wss.svg --image out/demo/artery-wss.pdf --image-time 0.31 --image-units Pa
echo "demo: out/demo/artery-flat.vtp (+ -map.vtp, .pvd), out/demo/artery-wss.png, .svg, .pdf"
