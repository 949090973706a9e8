#!/usr/bin/env bash
# Takes the README's pictures of radiosity-view with its own --screenshot (under xvfb-run when
# there is no display): the five modes, the live solve, and a picked patch's form-factor row and
# hemicube. Run from a build with the viewer: bash scripts/viewer_screenshots.sh [BUILD_DIR].
set -euo pipefail
cd "$(dirname "$0")/.."
view=${1:-build}/radiosity-view
run() {
  if [ -n "${DISPLAY:-}" ]; then
    "$view" --quiet "$@"
  else
    xvfb-run -a -s "-screen 0 1280x1024x24" "$view" --quiet "$@"
  fi
}
# The lecture's patches, flat and smooth shading (XI.1-XI.3) on 50 mm patches.
for mode in wireframe flat smooth reflectance emission; do
  run cornell --max-edge 50 --mode "$mode" --width 256 --height 256 \
    --screenshot "docs/viewer_$mode.png"
done
# Shooting stopped after 40 shots, with the panels: the light has reached only what the first
# shooters see; the plot shows the unshot energy falling.
run cornell --mode flat --stop-after 40 --ui --width 1200 --height 540 --screenshot docs/viewer_live.png
# A patch of the green wall picked: its row F_ij over the scene and its hemicube (XI.7).
run cornell --pick 850,300 --ui --width 1200 --height 600 --screenshot docs/viewer_pick.png
