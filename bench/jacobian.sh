#!/usr/bin/env bash
# bench/jacobian.sh — what a generated Jacobian saves: every example
# simulator whose model has one (an ODE whose loops are all solved
# symbolically) is run with CVODE at rtol 1e-8 (atol 1e-10) twice, with its
# Jacobian and with --fd-jacobian, the fastest wall time of three runs each.
# Writes bench/jacobian.csv.
#
#   bench/jacobian.sh [build dir, default build]
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$root/build}"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
csv="$root/bench/jacobian.csv"
echo "model,jacobian,wall_s,steps,rhs_evals,fd_jacobian_rhs_evals,jacobian_evals" > "$csv"

summary() {  # simulator, extra option -> "wall,steps,rhs,fd,jac" (fastest of 3)
  local best="" line
  for _ in 1 2 3; do
    "$1" --solver cvode --rtol 1e-8 --atol 1e-10 --out "$work/run.csv" $2 2> "$work/run.log" || return 1
    line=$(awk '/^  wall time/ { w = $3 } /^  steps/ { s = $2 }
      /^  evaluations/ { r = $2; f = $5; for (i = 1; i <= NF; i++) if ($(i + 1) == "Jacobian" && $(i + 2) == "evaluations") j = $i }
      END { print w "," s "," r "," f "," j }' "$work/run.log")
    if [ -z "$best" ] || awk -v a="${line%%,*}" -v b="${best%%,*}" 'BEGIN { exit !(a < b) }'; then best="$line"; fi
  done
  echo "$best"
}

for sim in "$build"/examples/*; do
  [ -x "$sim" ] && [ -f "$sim" ] || continue
  name=$(basename "$sim")
  "$sim" --solver cvode --out "$work/probe.csv" 2> "$work/probe.log" || continue
  grep -q "generated Jacobian" "$work/probe.log" || continue
  gen=$(summary "$sim" "") || continue
  fd=$(summary "$sim" "--fd-jacobian") || continue
  echo "$name,generated,$gen" | tee -a "$csv"
  echo "$name,finite differences,$fd" | tee -a "$csv"
done
echo "wrote $csv"
