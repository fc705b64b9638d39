#!/usr/bin/env bash
# tools/realtime_bench.sh — how much faster than real time the generated
# simulators run with a fixed-step RK4, one core: the issue-17 real-time
# benchmark. Each case runs 20 s of simulated time with --realtime 1e9 (no
# pacing: every frame is late, so the run never sleeps) and reads the run
# summary's compute time per frame (median and worst, a frame being one
# communication interval of 10 steps, its CSV row included). Prints CSV:
#
#   model,step_s,steps_per_frame,median_frame_s,worst_frame_s,worst_settled_s,median_step_us,times_real_time,wall_s
#
# worst_settled_s leaves out the first 10 frames (cold caches, lazy binding).
#
# times_real_time = step / (median frame / steps per frame). Targets (issue
# 17, point 5): two_track at 1 ms >= 1000x, the flexible-body version >= 100x.
#
#   tools/realtime_bench.sh [build dir, default build] > realtime.csv
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$root/build}"

echo "model,step_s,steps_per_frame,median_frame_s,worst_frame_s,worst_settled_s,median_step_us,times_real_time,wall_s"
run() {  # name simulator step [extra options]
  local name="$1" sim="$2" step="$3"
  shift 3
  [ -x "$sim" ] || { echo "no $sim: build first (cmake --build $build)" >&2; exit 1; }
  local interval
  interval=$(awk -v h="$step" 'BEGIN { printf "%.10g", 10 * h }')
  local log
  log=$("$sim" --solver rk4 --step "$step" --interval "$interval" --t-end 20 --realtime 1e9 --out /dev/null "$@" 2>&1 >/dev/null) || {
    echo "$name: the run failed" >&2
    echo "$log" >&2
    exit 1
  }
  local median worst settled wall
  median=$(sed -n 's/.*compute per frame: median \([^ ]*\) s, worst .*/\1/p' <<<"$log")
  worst=$(sed -n 's/.*compute per frame: median [^ ]* s, worst \([^ ]*\) s.*/\1/p' <<<"$log")
  settled=$(sed -n 's/.* (\([^ ]*\) s after the first 10).*/\1/p' <<<"$log")
  wall=$(sed -n 's/^  wall time *\([^ ]*\) s.*/\1/p' <<<"$log")
  awk -v n="$name" -v h="$step" -v m="$median" -v w="$worst" -v s="$settled" -v t="$wall" \
    'BEGIN { printf "%s,%s,10,%s,%s,%s,%.3g,%.0f,%s\n", n, h, m, w, s, m / 10 * 1e6, h / (m / 10), t }'
}
run two_track "$build/examples/two_track" 1e-3
run two_track_lane_change "$build/examples/two_track_lane_change" 1e-3
run two_track_frame "$build/examples/two_track_frame" 1e-3
run single_track "$build/examples/single_track" 1e-3
run tyre_rig "$build/tests/numeric/tyre_rig" 1e-3
# flexible bodies in joint coordinates: four reduced FE arms and three rigid bodies
run reduced_joints "$build/tests/numeric/reduced_joints_coordinates" 1e-4
