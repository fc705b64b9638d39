#!/usr/bin/env bash
# tools/animate.sh — the quick start's second line: the rotating beam's run
# as a 3-D animation. On a fresh Debian machine: install the packages, build
# mbgc, its runtime, the viewer (three.js from npm) and the rotating-beam
# example in build-demo/ (as tools/demo.sh), run it with --animate, draw a
# still of the bent blade in headless Chromium, and say how to watch it.
#
#   tools/animate.sh [cmake -D options]
#       # writes build-demo/demo/{rotating_beam.glb,rotating_beam.csv,rotating_beam.png}
#
# Exits nonzero if anything fails. See tools/common.sh for BUILD_DIR, BUILD_TYPE, JOBS.
set -euo pipefail
# shellcheck source=tools/common.sh
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
BUILD_DIR=${BUILD_DIR:-build-demo}

mbgc_install_packages
mbgc_configure_quick_start -DMBGC_VIEWER=ON "$@"
mbgc_build mbgc mbgrt mbgc_viewer rotating_beam

DEMO=$BUILD_DIR/demo
mkdir -p "$DEMO"
SIM=$BUILD_DIR/examples/rotating_beam
GLB=$DEMO/rotating_beam.glb
step "Simulating with --animate: $SIM --out $DEMO/rotating_beam.csv --animate $GLB"
"$SIM" --out "$DEMO/rotating_beam.csv" --animate "$GLB"

# The blade lags most at 7.02 s, 0.28 m at the tip: seen from above, drawn
# ten times larger (examples/rotating_beam/README.md, examples/stills.sh).
PNG=$DEMO/rotating_beam.png
still=(--t 7.02 --eye 0,-0.5,22 --target 0,3.5,0 --deform 10 --size 720x480)
step "Drawing the frame at t = 7.02 s: node $BUILD_DIR/viewer/still.mjs $GLB $PNG ${still[*]}"
node "$BUILD_DIR/viewer/still.mjs" "$GLB" "$PNG" "${still[@]}"
[ -s "$PNG" ] || die "no still was written"
echo
echo "Still: $(realpath "$PNG")"
echo "Watch it: open $(realpath "$BUILD_DIR/viewer/mbgc-view.html") in a browser and choose $(realpath "$GLB") with Open..."
