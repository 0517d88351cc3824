#!/usr/bin/env bash
# Regenerates the field images in docs/images/ (described in docs/images.md) with vessel-render:
# the carotid phantom with a synthetic WSS-like field (PNG with the 3D view, and the map alone as
# SVG and PDF), a real aorta with the geodesic distance, a real artery with a synthetic WSS vector
# field drawn as arrows, and a travelling pulse as frames (+ GIF when ffmpeg is installed). Needs
# build/bin/vessel-render, vessel-flatten, vessel-phantom and vessel-pulse (scripts/build.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
bin=build/bin
out=docs/images
data=../shared/data/real
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
[ -x $bin/vessel-render ] || cmake --build build --target vessel-render vessel-phantom vessel-pulse vessel-flatten

$bin/vessel-phantom carotid --stenosis 0.5 -o "$work/carotid.ply"
$bin/vessel-render "$work/carotid.ply" $out/map-carotid-wss.png --field wss --view3d \
  --labels CCA ICA ECA
for ext in svg pdf; do
  $bin/vessel-render "$work/carotid.ply" $out/map-carotid-wss.$ext --field wss \
    --labels CCA ICA ECA --size 900 --height 800
done
$bin/vessel-render $data/vmtk-test-data/aorta-surface-open-ends.ply $out/map-aorta-geodesic.png \
  --field geodesic --units mm --view3d --labels "inlet (aorta)" "outlet 1" "outlet 2"
$bin/vessel-render $data/svfsi-tests/pulmonary-glenn-wall.ply $out/map-glenn-geodesic.png \
  --field geodesic --units mm --view3d
# A synthetic WSS vector series (vessel-pulse --vector: magnitude of a travelling pulse, direction
# away from the inlet along the wall; not a flow result): colour |WSS|, arrows its direction.
$bin/vessel-pulse $data/vampy/artery.vtp "$work/artery-pulse" --name WSS --vector --quiet
$bin/vessel-flatten $data/vampy/artery.vtp -o "$work/artery-flat.vtp" --quiet \
  --fields "$work/artery-pulse.pvd" --field WSS --image $out/map-artery-wss-arrows.png \
  --image-time 0.31 --image-arrows WSS --image-units Pa --image-3d

# 90 steps over 1.8 s (the paper's heart cycle), shown 2x slower at 10 frames per second.
$bin/vessel-render "$work/carotid.ply" unused.png --frames "$work/frames" --steps 90 --period 1.8 \
  --fps 10 --slowdown 2 --size 600 --height 400 --labels CCA ICA ECA --animation "$work/pulse.gif"
cp "$work/frames/frame_0012.png" $out/pulse-frame-0012.png
if [ -f "$work/pulse.gif" ]; then cp "$work/pulse.gif" $out/pulse.gif; fi
ls -la $out
