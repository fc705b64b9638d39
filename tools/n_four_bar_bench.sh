#!/usr/bin/env bash
# tools/n_four_bar_bench.sh — IFToMM's N four-bar (tests/numeric/models/
# n_four_bar.mbg: N + 1 cranks joined by N couplers, every rod 1 m and 1 kg,
# spun over the top at 2 rad/s) through its aligned configurations, 10 s,
# against its exact one-degree-of-freedom motion, for each N, each form and
# each solver. Prints CSV:
#
#   N,form,solver,cpp_bytes,compile_s,status,reached_s,worst_error_m,wall_s
#
# form: coordinates (joint coordinates, a cut joint per loop: the default) or
# lagrange (multipliers, a DAE, run at rtol 1e-10, atol 1e-12); compile_s: c++ -O2 of the generated source;
# status: the simulator's exit status; worst_error_m: the largest distance
# of the last coupler's end from where the exact motion puts it, over the
# rows written (the exact motion: I theta'' = -k cos theta, classical RK4 at
# 1e-4 s); wall_s: the run summary's wall time.
#
#   tools/n_four_bar_bench.sh [build dir, default build] [N ...] > n_four_bar.csv
#
# Needs mbgc and the runtime built (cmake --build build --target mbgc mbgrt);
# N = 1, 4, 10 and 40 take about 9 minutes on 2 cores, most of it the
# multiplier form of N = 40 (a minute to compile, four to run).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="$(cd "${1:-$root/build}" && pwd)"
shift || true
sizes=("$@")
[ ${#sizes[@]} -gt 0 ] || sizes=(1 4 10 40)
mbgc="$build/compiler/mbgc"
[ -x "$mbgc" ] || { echo "no $mbgc: build first (cmake --build $build --target mbgc mbgrt)" >&2; exit 1; }
export PKG_CONFIG_PATH="$build/pkgconfig${PKG_CONFIG_PATH:+:$PKG_CONFIG_PATH}"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
model="$root/tests/numeric/models/n_four_bar.mbg"

# worst distance of (x, y) from (N + cos theta, sin theta), theta exact
worst_error() {  # N csv
  awk -F, -v N="$1" '
    function rate(th) { return -k * cos(th) / I }
    BEGIN { I = N / 3 + 1 / 3 + N; k = 9.81 * (N / 2 + 1 / 2 + N); th = atan2(1, 0); w = 2; dt = 1e-4; done = 0; worst = 0 }
    NR == 1 { for (c = 1; c <= NF; ++c) { if ($c == "x") cx = c; if ($c == "y") cy = c }; next }
    {
      target = int($1 / dt + 0.5)
      for (; done < target; ++done) {
        a1 = w; b1 = rate(th)
        a2 = w + dt / 2 * b1; b2 = rate(th + dt / 2 * a1)
        a3 = w + dt / 2 * b2; b3 = rate(th + dt / 2 * a2)
        a4 = w + dt * b3; b4 = rate(th + dt * a3)
        th += dt / 6 * (a1 + 2 * a2 + 2 * a3 + a4); w += dt / 6 * (b1 + 2 * b2 + 2 * b3 + b4)
      }
      dx = $cx - (N + cos(th)); dy = $cy - sin(th); e = sqrt(dx * dx + dy * dy)
      if (e > worst) worst = e
      reached = $1
    }
    END { printf "%s,%.3g", reached, worst }' "$2"
}

echo "N,form,solver,cpp_bytes,compile_s,status,reached_s,worst_error_m,wall_s"
for n in "${sizes[@]}"; do
  for form in coordinates lagrange; do
    src="$work/nfb_${form}_$n.cpp" sim="$work/nfb_${form}_$n"
    "$mbgc" "$model" --set "N=$n" --constraints "$form" -o "$src" 2>/dev/null
    t0=$(date +%s.%N)
    # shellcheck disable=SC2046  # pkg-config's output is a list of words
    c++ -std=c++17 -O2 "$src" $(pkg-config --cflags --libs mbgrt) -o "$sim"
    compile=$(awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f", b - a }')
    bytes=$(wc -c <"$src")
    solvers=(dopri5 cvode)
    [ "$form" = lagrange ] && solvers=(ida)
    # IDA at the model's rtol 1e-8 drifts 1e-4 m in 10 s on its own, change
    # points or not: the multiplier form runs at 1e-10 (atol 1e-12)
    tolerances=()
    [ "$form" = lagrange ] && tolerances=(--rtol 1e-10 --atol 1e-12)
    for solver in "${solvers[@]}"; do
      status=0
      "$sim" --solver "$solver" "${tolerances[@]}" -o "$work/out.csv" 2>"$work/log" || status=$?
      wall=$(sed -n 's/^  wall time *\([^ ]*\) s.*/\1/p' "$work/log")
      echo "$n,$form,$solver,$bytes,$compile,$status,$(worst_error "$n" "$work/out.csv"),${wall:-}"
    done
  done
done
