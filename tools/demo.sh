#!/usr/bin/env bash
# tools/demo.sh — on a fresh Debian machine: install the packages, build mbgc
# and its runtime (nothing else: the tests and the other examples are
# tools/test.sh's), compile the DC-motor example, simulate it and plot current
# and speed.
#
#   tools/demo.sh [cmake -D options]   # writes build-demo/demo/{dc_motor.cpp,dc_motor.csv,dc_motor.png}
#
# Exits nonzero if anything fails. See tools/common.sh for BUILD_DIR, BUILD_TYPE, JOBS.
# MBGC_DEMO_BY_HAND=1 compiles build-demo/demo/dc_motor.cpp with c++ directly even
# when the build has the example's CMake target.
set -euo pipefail
# shellcheck source=tools/common.sh
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
BUILD_DIR=${BUILD_DIR:-build-demo}

mbgc_install_packages
# Only mbgc, its runtime and the one example, at -O1: the quick start takes
# about 70 s on 2 cores from a clean clone (README, "The two commands").
mbgc_configure_quick_start "$@"
mbgc_build mbgc mbgrt

DEMO=$BUILD_DIR/demo
MODEL=examples/dc_motor/dc_motor.mbg
mkdir -p "$DEMO"

# 1. The compiler: model -> one readable C++ file.
step "Compiling the model: $BUILD_DIR/compiler/mbgc $MODEL -o $DEMO/dc_motor.cpp"
"$BUILD_DIR/compiler/mbgc" "$MODEL" -o "$DEMO/dc_motor.cpp"
echo "$DEMO/dc_motor.cpp: $(wc -l < "$DEMO/dc_motor.cpp") lines of C++"

# 2. The simulator: that C++ linked against the runtime mbgrt. The build tree
# has it as the CMake target `dc_motor` (examples/CMakeLists.txt,
# mbgc_add_simulation, the same compiler and model); otherwise compile by hand.
targets=$(cmake --build "$BUILD_DIR" --target help)
if [ "${MBGC_DEMO_BY_HAND:-0}" != 1 ] && grep -Eq '^(\.\.\. )?dc_motor(:|$| )' <<<"$targets"; then
  mbgc_build dc_motor
  SIM=$(find "$BUILD_DIR/examples" -type f -name dc_motor -perm -u+x | head -n 1)
  [ -n "$SIM" ] || die "built target dc_motor, but found no executable dc_motor under $BUILD_DIR/examples"
else
  # what a user without CMake does: the runtime's flags from pkg-config
  # (mbgrt-uninstalled.pc of this build tree; mbgrt.pc once installed)
  PKG_CONFIG_PATH="$(cd "$BUILD_DIR" && pwd)/pkgconfig${PKG_CONFIG_PATH:+:$PKG_CONFIG_PATH}"
  export PKG_CONFIG_PATH
  step "Building the simulator: c++ -std=c++17 -O2 $DEMO/dc_motor.cpp \$(pkg-config --cflags --libs mbgrt)"
  flags=()
  if grep -q '^MBGC_SANITIZE:BOOL=ON' "$BUILD_DIR/CMakeCache.txt"; then
    flags=("-fsanitize=address,undefined")
  fi
  SIM=$DEMO/dc_motor
  # shellcheck disable=SC2046  # pkg-config's output is a list of words
  c++ -std=c++17 -O2 "${flags[@]}" "$DEMO/dc_motor.cpp" $(pkg-config --cflags --libs mbgrt) -o "$SIM"
fi

# 3. Simulate: the model's own simulate { } settings, CSV out, summary on stderr.
CSV=$DEMO/dc_motor.csv
step "Simulating: $SIM --out $CSV"
"$SIM" --out "$CSV"

awk -F, '
  NR == 1 { for (i = 1; i <= NF; i++) { name = $i; sub(/ \[.*\]$/, "", name); col[name] = i } next }  # "omega [rad/s]"
  { last = $0 }
  END {
    if (!("t" in col) || !("current" in col) || !("omega" in col)) {
      print "error: expected columns t, current, omega in the CSV" > "/dev/stderr"; exit 1
    }
    if (last == "") { print "error: the CSV has no rows" > "/dev/stderr"; exit 1 }
    n = split(last, v, ",")
    printf "\nFinal state (t = %g s):\n", v[col["t"]]
    printf "  armature current  i     = %10.4f A\n", v[col["current"]]
    printf "  rotor speed       omega = %10.4f rad/s  (%.1f rpm)\n",
           v[col["omega"]], v[col["omega"]] * 60 / (2 * 3.141592653589793)
  }' "$CSV"

# 4. Plot current and speed against time, one panel each.
PNG=$DEMO/dc_motor.png
column() { head -n 1 "$CSV" | tr ',' '\n' | sed 's/ \[.*\]$//' | grep -nx "$1" | cut -d: -f1; }
T_COL=$(column t); I_COL=$(column current); W_COL=$(column omega)
step "Plotting: $PNG"
if gnuplot -e 'set terminal pngcairo' >/dev/null 2>&1; then
  terminal="pngcairo noenhanced size 900,700 font ',10'"
else
  terminal="png noenhanced size 900,700"
fi
gnuplot <<GNUPLOT
set terminal $terminal
set output '$PNG'
set datafile separator ','
set key noautotitle
set grid
set xlabel 'time t [s]'
set multiplot layout 2,1 title 'DC motor started on 60 V (examples/dc_motor)'
set ylabel 'armature current i [A]'
plot '$CSV' using $T_COL:$I_COL skip 1 with lines linewidth 2 linecolor rgb '#1f77b4'
set ylabel 'rotor speed omega [rad/s]'
plot '$CSV' using $T_COL:$W_COL skip 1 with lines linewidth 2 linecolor rgb '#d62728'
unset multiplot
GNUPLOT
[ -s "$PNG" ] || die "gnuplot wrote no plot"
echo
echo "Plot: $(realpath "$PNG")"
