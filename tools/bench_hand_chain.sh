#!/usr/bin/env bash
# tools/bench_hand_chain.sh BUILD_DIR OUT.csv — the generated 32-rod planar
# chain against the hand-written one of ../shared/bench/hand_chain (its
# README: a tight O(N) articulated-body model, written outside the project),
# both RK4 at 2 ms for 100 s, as whole processes with one output row, built
# by the same g++ with the same flags: CMake's Release flags (-O3 -DNDEBUG),
# then those with -march=native. The generated source is compiled with the
# flags (what mbgc_add_simulation's NATIVE does), the runtime library it
# links is BUILD_DIR's (Release). The simulator runs as a user runs it: the
# energy witness on. Five runs of each, alternating; writes
# flags,program,run,seconds to OUT.csv and prints per flag set the range of
# each and the ratio of the medians (mbgc / hand-written).
# HAND_CHAIN_DIR=... points at another copy; without one it says so and stops.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="$1"
out="$2"
hand_dir="${HAND_CHAIN_DIR:-$root/../shared/bench/hand_chain}"
if [ ! -f "$hand_dir/eigen_peer.cpp" ]; then
  echo "no hand-written chain at $hand_dir (HAND_CHAIN_DIR=...): the comparison was not run" >&2
  exit 0
fi
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
"$build/compiler/mbgc" "$root/examples/chain/chain.mbg" --set N=32 --constraints coordinates -o "$work/chain_32.cpp"
read -r -a runtime <<< "$(PKG_CONFIG_PATH="$build/pkgconfig" pkg-config --cflags --libs mbgrt)"
sundials=(-lsundials_cvode -lsundials_nvecserial -lsundials_sunlinsoldense -lsundials_sunmatrixdense
          -lsundials_sunnonlinsolfixedpoint)

seconds() {  # COMMAND...: its wall time in seconds
  local t0 t1
  t0=$(date +%s.%N)
  "$@" > /dev/null
  t1=$(date +%s.%N)
  awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.3f\n", b - a }'
}

echo "flags,program,run,seconds" > "$out"
for flags in "-O3 -DNDEBUG" "-O3 -DNDEBUG -march=native"; do
  read -r -a f <<< "$flags"
  g++ -std=c++17 "${f[@]}" -o "$work/mbgc_chain" "$work/chain_32.cpp" "${runtime[@]}"
  g++ -std=c++17 "${f[@]}" -I/usr/include/eigen3 -o "$work/hand_chain" "$hand_dir/eigen_peer.cpp" "${sundials[@]}"
  for run in 1 2 3 4 5; do
    echo "$flags,hand_chain,$run,$(seconds "$work/hand_chain" W1 32 rk4 aba 0.002 100 1)" >> "$out"
    echo "$flags,mbgc,$run,$(seconds "$work/mbgc_chain" --solver rk4 --step 0.002 --t-end 100 --interval 100 --quiet -o /dev/null)" >> "$out"
  done
done
python3 - "$out" <<'PY'
import csv, statistics, sys
rows = list(csv.DictReader(open(sys.argv[1])))
for flags in dict.fromkeys(r["flags"] for r in rows):
    t = {p: sorted(float(r["seconds"]) for r in rows if r["flags"] == flags and r["program"] == p)
         for p in ("hand_chain", "mbgc")}
    ratio = statistics.median(t["mbgc"]) / statistics.median(t["hand_chain"])
    print(f"{flags}: hand_chain {t['hand_chain'][0]:.2f}-{t['hand_chain'][-1]:.2f} s, "
          f"mbgc {t['mbgc'][0]:.2f}-{t['mbgc'][-1]:.2f} s, ratio of medians {ratio:.2f}")
PY
