#!/usr/bin/env bash
# tools/realtime_bench.sh — how much faster than real time the vehicles run
# with each fixed-step method at a 1 ms step, and how accurate each is.
# Each run is the simulator's normal run of 8 s with its CSV at 10 ms and
# the energy witness as a run has it by default; its compute time is the run
# summary's wall time (the process start excluded), the fastest of 3 runs.
# The error is the largest, over yaw rate, lateral acceleration and the four
# wheel loads, of max_t |y - y_ref| / max_t |y_ref|, against RK4 at 0.1 ms.
# A second run of each, paced with --realtime 1e9 (frames of 10 steps, no
# waiting; the witness left out, as a paced run does), gives the median and
# the worst compute time per step. Prints CSV:
#
#   model,method,step_s,error,times_real_time,compute_s,median_step_us,worst_step_us,status
#
#   tools/realtime_bench.sh [build dir, default build] > bench/realtime.csv
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$root/build}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
t_end=8
methods=(euler heun symplectic_euler rk4 linearly_implicit_euler ros2 generalized_alpha)

summary() {  # LOG FIELD: a number from the run summary
  case "$2" in
    wall) sed -n 's/^  wall time *\([^ ]*\) s.*/\1/p' "$1" ;;
    median) sed -n 's/.*compute per frame: median \([^ ]*\) s, worst .*/\1/p' "$1" ;;
    worst) sed -n 's/.*compute per frame: median [^ ]* s, worst \([^ ]*\) s.*/\1/p' "$1" ;;
  esac
}

echo "model,method,step_s,error,times_real_time,compute_s,median_step_us,worst_step_us,status"
# (two_track_native: the car compiled with -march=native, mbgc_add_simulation's NATIVE)
for model in two_track two_track_native two_track_frame; do
  sim="$build/examples/$model"
  [ -x "$sim" ] || { echo "no $sim: build first (cmake --build $build)" >&2; exit 1; }
  "$sim" --solver rk4 --step 1e-4 --t-end $t_end --interval 0.01 --quiet -o "$work/ref.csv"
  for method in "${methods[@]}"; do
    best=""
    status=ok
    for k in 1 2 3; do
      if ! "$sim" --solver "$method" --step 1e-3 --t-end $t_end --interval 0.01 -o "$work/run.csv" 2> "$work/run.log"; then
        status="failed: $(grep -m1 'error:' "$work/run.log" | sed 's/.*error: //; s/,/;/g' | cut -c1-120)"
        break
      fi
      wall=$(summary "$work/run.log" wall)
      best=$(awk -v a="$best" -v b="$wall" 'BEGIN { print (a == "" || b < a) ? b : a }')
    done
    if [ "$status" != ok ]; then
      echo "$model,$method,1e-3,inf,,,,,\"$status\""
      continue
    fi
    error=$(python3 - "$work/run.csv" "$work/ref.csv" <<'PY'
import csv, sys
run, ref = ([row for row in csv.reader(open(p))] for p in sys.argv[1:3])
wanted = ("yaw_rate", "ay", "Fz_fl", "Fz_fr", "Fz_rl", "Fz_rr")
worst = 0.0
for c, name in enumerate(ref[0]):
    if name.split(" ")[0] not in wanted:
        continue
    y = [float(r[c]) for r in run[1:]]
    y_ref = [float(r[c]) for r in ref[1:]]
    scale = max(abs(v) for v in y_ref)
    worst = max(worst, max(abs(a - b) for a, b in zip(y, y_ref)) / scale)
print(f"{worst:.3g}")
PY
)
    "$sim" --solver "$method" --step 1e-3 --t-end $t_end --interval 0.01 --realtime 1e9 -o /dev/null 2> "$work/paced.log"
    median=$(summary "$work/paced.log" median)
    worst=$(summary "$work/paced.log" worst)
    awk -v m="$model" -v s="$method" -v e="$error" -v w="$best" -v md="$median" -v wo="$worst" -v t="$t_end" \
      'BEGIN { printf "%s,%s,1e-3,%s,%.0f,%s,%.3g,%.3g,ok\n", m, s, e, t / w, w, md / 10 * 1e6, wo / 10 * 1e6 }'
  done
done
