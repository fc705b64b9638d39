#!/usr/bin/env bash
# tools/fmi_bench.sh — a 10 s run of each example's FMU under fmusim beside
# the example's own simulator: whole processes (start-up, unzipping the FMU
# and writing CSV included), the fastest of 3 runs each. Co-simulation runs
# the model's own integrator; model exchange fmusim's CVODE at the tolerance
# tests/fmi uses. Needs the FMUs and fmusim of tests/fmi (a build with
# ../shared beside the source, or MBGC_FMUSIM). Prints CSV:
#
#   example,fmi,native_s,cs_s,me_s
#
#   tools/fmi_bench.sh [build dir, default build] > bench/fmi.csv
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$root/build}"
fmusim="${MBGC_FMUSIM:-$build/tests/fmi/fmusim-build/fmusim}"
[ -x "$fmusim" ] || { echo "no fmusim at $fmusim (MBGC_FMUSIM=...)" >&2; exit 1; }
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

fastest() {  # COMMAND...: the fastest wall time of 3 runs, in seconds
  local best=""
  for _ in 1 2 3; do
    local start end
    start=$(date +%s.%N)
    "$@" > /dev/null 2>&1 || { echo "failed: $*" >&2; exit 1; }
    end=$(date +%s.%N)
    best=$(awk -v a="$best" -v s="$start" -v e="$end" 'BEGIN { t = e - s; if (a == "" || t < a) a = t; printf "%.4f", a }')
  done
  echo "$best"
}

echo "example,fmi,native_s,cs_s,me_s"
# example, its simulator in examples/, fmusim's model-exchange tolerance (tests/fmi)
while read -r example simulator tolerance; do
  native=$(fastest "$build/examples/$simulator" --t-end 10 --quiet -o "$work/native.csv")
  for version in 3 2; do
    fmu="$build/tests/fmi/fmu${version}_$example.fmu"
    cs=$(fastest "$fmusim" --interface-type cs --stop-time 10 --output-file "$work/cs.csv" "$fmu")
    me=$(fastest "$fmusim" --interface-type me --solver cvode --tolerance "$tolerance" --stop-time 10 \
                 --output-file "$work/me.csv" "$fmu")
    echo "$example,$version,$native,$cs,$me"
  done
done <<'LIST'
dc_motor dc_motor 1e-10
bouncing_ball bouncing_ball 1e-10
pendulum pendulum_coordinates 1e-10
rotating_beam rotating_beam_coordinates 1e-8
crank_rocker crank_rocker_coordinates 1e-8
two_track two_track 1e-8
LIST
