#!/usr/bin/env bash
# bench/compiler_speed.sh — how mbgc and g++ scale with the model: the planar
# chain of examples/chain at N = 10, 100, 1000 rods, with multipliers
# (lagrange) and in joint coordinates. For each: mbgc's wall time (the
# fastest of 3 for N = 10, one run above), the generated C++'s size, and g++ -O2's time
# to compile it: in joint coordinates for N <= GXX_MAX_N (default 100; issue
# 15's target is 15 s at N = 100), with multipliers for N = 10 only (N = 100
# took 535 s). Writes bench/compiler_speed.csv.
#
#   bench/compiler_speed.sh [build dir, default build]
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$root/build}"
mbgc="$build/compiler/mbgc"
[ -x "$mbgc" ] || { echo "no $mbgc: build first (tools/demo.sh or cmake --build build)" >&2; exit 1; }
gxx_max="${GXX_MAX_N:-100}"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
csv="$root/bench/compiler_speed.csv"
echo "n,constraints,mbgc_s,cpp_bytes,gxx_O2_s" > "$csv"

seconds() {  # command... -> wall seconds (stderr of /usr/bin/time)
  /usr/bin/time -f "%e" "$@" 2>&1 >/dev/null | tail -1
}

for n in 10 100 1000; do
  for strategy in lagrange coordinates; do
    out="$work/chain_${n}_$strategy.cpp"
    best=""
    for rep in 1 2 3; do
      s=$(seconds "$mbgc" "$root/examples/chain/chain.mbg" --set N="$n" --constraints "$strategy" -o "$out")
      if [ -z "$best" ] || awk -v a="$s" -v b="$best" 'BEGIN { exit !(a < b) }'; then best="$s"; fi
      [ "$n" -ge 100 ] && break  # one run: they take seconds to minutes
    done
    bytes=$(stat -c %s "$out")
    gxx=""
    if [ "$n" -le "$gxx_max" ] && { [ "$strategy" = coordinates ] || [ "$n" -le 10 ]; }; then
      gxx=$(seconds g++ -std=c++20 -O2 -c -I"$root/runtime/include" "$out" -o "$work/x.o")
    fi
    echo "$n,$strategy,$best,$bytes,$gxx" | tee -a "$csv"
  done
done
echo "wrote $csv"
