#!/usr/bin/env bash
# sweep.sh — the rotating beam's largest tip lag against the final spin rate
# Omega_s, for 1, 2, 3 and 4 modes: one parameter sweep per mode count (the
# mode count fixes the model's structure, so each is its own simulator,
# rotating_beam_N_modes; Omega_s is a run-time parameter), plotted from the
# sweeps' summaries (tip_deflection_min: the tip lags, so its smallest value
# is the largest lag). Writes sweep.png here and the summaries under
# $BUILD_DIR/plots/rotating_beam.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
build="${BUILD_DIR:-$here/../../build}"
out="$build/plots/rotating_beam"
mkdir -p "$out"
for n in 1 2 3 4; do
  sim="$build/examples/rotating_beam_${n}_modes"
  [ "$n" = 3 ] && sim="$build/examples/rotating_beam"   # the model as written has 3
  "$sim" --sweep Omega_s=0.25:4:16 -o "$out/sweep_${n}_modes.csv"
done
# the 4-mode lags beside each summary's, for the second panel
for n in 1 2 3; do
  paste -d, "$out/sweep_${n}_modes.csv" "$out/sweep_4_modes.csv" > "$out/sweep_${n}_vs_4.csv"
done
gnuplot <<GP
set terminal pngcairo size 900, 720 font 'DejaVu Sans,10'
set output '$here/sweep.png'
set datafile separator ','
set grid
set multiplot layout 2, 1 title 'rotating beam: peak tip deflection against spin rate and mode count (--sweep Omega\\_s=0.25:4:16)'
set key top left
set xlabel 'final spin rate Ω_s [rad/s] (spin-up over T_s = 15 s)'
set ylabel 'largest tip lag [m]'
# columns: case, Omega_s, status, spin_final, spin_min, spin_max, tip_deflection_final, tip_deflection_min, ...
plot for [n=1:4] sprintf('$out/sweep_%d_modes.csv', n) using 2:(-\$8) skip 1 with linespoints lw 2 title sprintf('%d mode%s', n, n > 1 ? 's' : '')
set ylabel '|lag - 4-mode lag| [m]'
set logscale y
set format y '10^{%T}'
set key bottom right
cols = 14   # columns per summary row (the 4-mode row follows)
plot for [n=1:3] sprintf('$out/sweep_%d_vs_4.csv', n) using 2:(abs(\$8 - column(cols + 8))) skip 1 with linespoints lw 2 title sprintf('%d mode%s', n, n > 1 ? 's' : '')
unset multiplot
GP
echo "wrote $here/sweep.png"
