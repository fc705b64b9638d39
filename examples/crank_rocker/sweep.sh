#!/usr/bin/env bash
# sweep.sh — the crank-rocker's peak coupler force against the motor voltage:
# one parameter sweep (--sweep motor.V_supply=10:120:12, a run-time parameter
# of the DC motor instance), plotted from its summary. force_j1 is the
# ground's force on the crank at O2; the crank's centre of mass is on its
# pivot and the mechanism is planar without gravity, so it equals the crank's
# force on the coupler at A. Writes sweep.png here and the summary under
# $BUILD_DIR/plots/crank_rocker.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
build="${BUILD_DIR:-$here/../../build}"
out="$build/plots/crank_rocker"
mkdir -p "$out"
"$build/examples/crank_rocker" --sweep motor.V_supply=10:120:12 -o "$out/sweep.csv"
col() { head -n 1 "$out/sweep.csv" | tr ',' '\n' | grep -nx "$1" | cut -d: -f1; }
V=$(col motor.V_supply); F=$(col force_j1_max); W=$(col omega_crank_final)
F60=$(awk -F, -v v="$V" -v f="$F" 'NR > 1 && $v == 60 { print $f }' "$out/sweep.csv")   # the model's own 60 V
gnuplot <<GP
set terminal pngcairo size 900, 480 font 'DejaVu Sans,10'
set output '$here/sweep.png'
set datafile separator ','
set grid
set key top left
set xlabel 'motor supply voltage V [V]'
set ylabel 'peak coupler force over the first second [N]'
set y2label 'crank speed at t = 1 s [rad/s]'
set ytics nomirror
set y2tics
set title 'crank-rocker started from rest: peak coupler force against motor voltage (--sweep motor.V\\_supply=10:120:12)'
plot '$out/sweep.csv' using $V:$F skip 1 with linespoints lw 2 title 'peak |force at A|', \
     '' using $V:($F60 * (\$$V / 60)**2) skip 1 with lines dt 2 lw 1 title 'the 60 V peak scaled by (V / 60 V)^2', \
     '' using $V:$W skip 1 axes x1y2 with linespoints lw 2 title 'crank speed at t = 1 s (right axis)'
GP
echo "wrote $here/sweep.png"
