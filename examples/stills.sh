#!/usr/bin/env bash
# examples/stills.sh — the still of each multibody example's animation
# (examples/<name>/animation.png, shown in its README): its simulator from
# the build tree runs with --animate, and the viewer (build/viewer) draws the
# frame at the time given below in headless Chromium, with the viewer's
# default camera (everything the bodies sweep over the run, or the bodies at
# that time where the run dwarfs them: docs/animation.md).
#
#   examples/stills.sh [BUILD_DIR]    # default build; needs the examples and mbgc_viewer built
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
BUILD=${1:-build}
STILL=$BUILD/viewer/still.mjs
[ -f "$STILL" ] || { echo "error: $STILL not found: build the target mbgc_viewer" >&2; exit 1; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# example directory, simulator target, time of the still (s), the still's
# camera (still.mjs options; none: framed on the whole run)
while read -r dir sim time camera; do
  [ -n "$dir" ] && [ "${dir:0:1}" != "#" ] || continue
  exe=$BUILD/examples/$sim
  [ -x "$exe" ] || { echo "error: $exe not built" >&2; exit 1; }
  # (a run that stops early still writes the rows it reached: the flexible
  # double pendulum stops at 3.27 s, examples/flexible_double_pendulum/README.md)
  "$exe" --quiet --out "$work/$sim.csv" --animate "$work/$sim.glb" || [ -s "$work/$sim.glb" ]
  # shellcheck disable=SC2086  # camera is a list of words
  node "$STILL" "$work/$sim.glb" "examples/$dir/animation.png" --t "$time" --size 720x480 $camera
  echo "examples/$dir/animation.png: $sim at t = $time s"
done <<'TABLE'
andrews                     andrews                      0.015
bouncing_ball               bouncing_ball                0.6
chain                       chain_8                      0.5
crank_rocker                crank_rocker                 0.3
crank_rocker_flexible       crank_rocker_flexible        0.3
double_pendulum_3d          double_pendulum_3d           1.5
flexible_double_pendulum    flexible_double_pendulum     1
flexible_double_pendulum_fe flexible_double_pendulum_fe  1
pendulum                    pendulum                     1
rocking_rod                 rocking_rod                  1
rotating_beam               rotating_beam                7.02  --eye 0,-0.5,22 --target 0,3.5,0 --deform 10
sliding_block               sliding_block                1
snap_fit                    snap_fit                     0.3
space_manipulator           space_manipulator            10
torque_free_body            torque_free_body             20
two_track                   two_track_lane_change        3     --eye 61,-3,3 --target 66.2,3.6,0.3
TABLE
