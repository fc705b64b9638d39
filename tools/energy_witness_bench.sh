#!/usr/bin/env bash
# tools/energy_witness_bench.sh — what the energy witness costs (issue 19,
# point 5): each example run with and without --no-energy-witness, the
# fastest of 5 runs each (the run summary's wall time, CSV writing included),
# on one core. Prints CSV:
#
#   model,solver,wall_s_with,wall_s_without,ratio
#
# CVODE and IDA evaluate the model's power() once per step (quadratures),
# rk4 and dopri5 once per stage.
#
#   tools/energy_witness_bench.sh [build dir, default build] > bench/energy_witness.csv
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$root/build}"
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

fastest() {  # simulator options...: the least wall time of 5 runs
  local best=""
  for _ in 1 2 3 4 5; do
    local w
    w=$("$@" --out "$out/run.csv" 2>&1 | awk '/^  wall time/ { print $3 }')
    [ -n "$w" ] || { echo "no wall time from: $*" >&2; exit 1; }
    best=$(awk -v a="$best" -v b="$w" 'BEGIN { print (a == "" || b < a) ? b : a }')
  done
  echo "$best"
}

echo "model,solver,wall_s_with,wall_s_without,ratio"
while read -r model solver options; do
  sim="$build/examples/$model"
  [ -x "$sim" ] || { echo "no $sim: build first (cmake --build $build)" >&2; exit 1; }
  # shellcheck disable=SC2086  # options is a list of words
  with=$(fastest "$sim" --solver "$solver" $options)
  # shellcheck disable=SC2086
  without=$(fastest "$sim" --solver "$solver" $options --no-energy-witness)
  awk -v m="$model" -v s="$solver" -v a="$with" -v b="$without" 'BEGIN { printf "%s,%s,%s,%s,%.3f\n", m, s, a, b, a / b }'
done <<'CASES'
pendulum ida
pendulum_coordinates cvode
chain_32 ida
chain_8_coordinates cvode
chain_8_coordinates dopri5
chain_8_coordinates rk4 --step 1e-4
crank_rocker ida
dc_motor cvode
quarter_car cvode
two_track cvode
two_track dopri5
two_track rk4 --step 1e-4
CASES
