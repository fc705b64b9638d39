#!/usr/bin/env bash
# figures.sh — the rotating beam's two figures (thesis Figs. 9-14 and 9-15)
# from the simulators the README's set-up builds:
#   tip.png:        tip deflection for Omega_s = 2 and 4 rad/s, with and without
#                   geometric stiffness (the linear model at 4 rad/s stops
#                   where its deflection leaves the modal model's range)
#   frequencies.png: first two natural frequencies against a constant spin,
#                   from --linearize-at after a slow spin-up
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
build="${BUILD_DIR:-$here/../../build}"
out="$build/plots/rotating_beam"
mkdir -p "$out"
for ws in 2 4; do
  "$build/examples/rotating_beam" --quiet --set Omega_s=$ws -o "$out/gs_$ws.csv"
  "$build/examples/rotating_beam_linear" --quiet --set Omega_s=$ws -o "$out/linear_$ws.csv" 2> "$out/linear_$ws.log" || true
done
: > "$out/frequencies.csv"
for w in 0 0.5 1 1.5 2 2.5 2.8 3 3.5 4 4.5 5; do
  gs=$("$build/examples/rotating_beam" --quiet --set Omega_s=$w --set T_s=10 --t-end 12 --linearize-at 12 -o - |
       awk -F, 'NR > 1 && $2 > 1e-3 { print $2 }' | head -2 | paste -sd' ')
  # without geometric stiffness: only below the first frequency (2.91 rad/s) is there a steady state
  lin=$("$build/examples/rotating_beam_linear" --quiet --set Omega_s=$w --set T_s=10 --t-end 12 --linearize-at 12 -o - 2>/dev/null |
        awk -F, 'NR > 1 && $2 > 1e-3 { print $2 }' | head -2 | paste -sd' ' || true)
  echo "$w $gs ${lin:-nan nan}" >> "$out/frequencies.csv"
done
gnuplot <<GP
set terminal pngcairo size 900, 420 font 'DejaVu Sans,10'
set datafile separator ','
set grid
set output '$here/tip.png'
set xlabel 't [s]'; set ylabel 'tip deflection in the plane of rotation [m]'
set title 'rotating beam: spin-up to Ω_s in T_s = 15 s (thesis Fig. 9-15)'
set yrange [-1.5:1.5]
plot '$out/gs_2.csv' using 1:3 with lines lw 2 title 'Ω_s = 2, geometric stiffness', \
     '$out/gs_4.csv' using 1:3 with lines lw 2 title 'Ω_s = 4, geometric stiffness', \
     '$out/linear_2.csv' using 1:3 with lines lw 2 dt 2 title 'Ω_s = 2, linear model', \
     '$out/linear_4.csv' using 1:3 with lines lw 2 dt 2 title 'Ω_s = 4, linear model (stops: diverged)'
set datafile separator whitespace
set output '$here/frequencies.png'
set terminal pngcairo size 900, 700 font 'DejaVu Sans,10'
set multiplot layout 2, 1 title 'rotating beam: first two eigenvalues against a constant spin (thesis Fig. 9-14), from --linearize-at'
set xlabel 'spin [rad/s]'
set yrange [*:*]
set ylabel 'omega_1^2 [1/s^2]'
set title 'mode 1 (the linear model has no steady state above 2.91 rad/s: its omega_1^2 < 0)'
plot '$out/frequencies.csv' using 1:(\$2**2) with linespoints lw 2 title 'geometric stiffness', \
     '' using 1:(\$4**2) with linespoints lw 2 dt 2 title 'linear model'
set ylabel 'omega_2^2 [1/s^2]'
set title 'mode 2'
plot '$out/frequencies.csv' using 1:(\$3**2) with linespoints lw 2 title 'geometric stiffness', \
     '' using 1:(\$5**2) with linespoints lw 2 dt 2 title 'linear model'
unset multiplot
GP
echo "wrote $here/tip.png and $here/frequencies.png"
