#!/usr/bin/env bash
# tools/fidelity.sh OUTPUT T "LABEL=SIMULATOR [options]"... — what each
# fidelity knob (modes, geometric stiffness, a rigid counterpart, the
# constraint strategy, the integrator and its tolerance) costs and what it
# changes: runs every variant (the fastest wall time of three runs, from the
# run summary), reads OUTPUT at time T, and prints a Markdown table with the
# difference from the first variant (the reference). Example:
#
#   tools/fidelity.sh tip_deflection 8 "3 modes=build/examples/rotating_beam" \
#       "1 mode=build/examples/rotating_beam_1_modes"
set -euo pipefail
output="${1:?usage: tools/fidelity.sh OUTPUT T \"LABEL=SIMULATOR [options]\"...}"
at="${2:?usage: tools/fidelity.sh OUTPUT T \"LABEL=SIMULATOR [options]\"...}"
shift 2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

value_at() {  # CSV, column name, time -> value (empty if absent)
  awk -F, -v name="$2" -v t="$3" 'NR == 1 { for (i = 1; i <= NF; i++) { h = $i; sub(/ \[.*\]$/, "", h); if (h == name) c = i } next }
    c && ($1 - t < 1e-9 && t - $1 < 1e-9) { print $c; exit }' "$1"
}

echo "| variant | wall time [s] | steps | $output at t = $at s | difference from the first |"
echo "|---|---|---|---|---|"
ref=""
for variant in "$@"; do
  label="${variant%%=*}"
  read -r -a cmd <<< "${variant#*=}"
  best="" steps="" status=0
  for _ in 1 2 3; do
    if "${cmd[@]}" --out "$work/run.csv" 2> "$work/run.log"; then status=0; else status=$?; fi
    wall=$(awk '/^  wall time/ { print $3 }' "$work/run.log")
    steps=$(awk '/^  steps/ { print $2 }' "$work/run.log")
    if [ -z "$best" ] || awk -v a="$wall" -v b="$best" 'BEGIN { exit !(a < b) }'; then best="$wall"; fi
  done
  v=$(value_at "$work/run.csv" "$output" "$at")
  if [ "$status" -ne 0 ] || [ -z "$v" ]; then
    reason=$(grep -m1 'mbgrt: error' "$work/run.log" | cut -c1-120 || true)
    echo "| $label | $best | $steps | stopped: ${reason:-no row at t = $at} | |"
    continue
  fi
  if [ -z "$ref" ]; then ref="$v"; diff="(reference)"; else diff=$(awk -v a="$v" -v b="$ref" 'BEGIN { d = a - b; printf "%.3g", d < 0 ? -d : d }'); fi
  printf '| %s | %s | %s | %.7g | %s |\n' "$label" "$best" "$steps" "$v" "$diff"
done
