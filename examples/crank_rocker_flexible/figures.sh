#!/usr/bin/env bash
# figures.sh — the flexible crank-rocker's figures (thesis Figs. 9-18, 9-19)
# from the simulators the README's set-up builds:
#   startup.png: 1 s start-up, flexible coupler against the rigid one
#                (examples/crank_rocker): speeds, current, axial force, deflection
#   buckling.png: the rocker x200: the coupler buckles and the run stops
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
build="${BUILD_DIR:-$here/../../build}"
out="$build/plots/crank_rocker_flexible"
mkdir -p "$out"
"$build/examples/crank_rocker_flexible" --quiet -o "$out/flexible.csv"
"$build/examples/crank_rocker" --quiet -o "$out/rigid.csv"
"$build/examples/crank_rocker_flexible" --quiet --set rocker_scale=200 -o "$out/heavy.csv" 2> "$out/heavy.log" || true
# columns (flexible): 1 t, 2 omega_crank, 3 omega_rocker, 4 current, 5 force_j1, 6 axial_force, 7 deflection_mid
gnuplot <<GP
set terminal pngcairo size 1000, 800 font 'DejaVu Sans,10'
set datafile separator ','
set grid
set key top left
set xlabel 't [s]'
set output '$here/startup.png'
set multiplot layout 3, 2 title 'crank-rocker with a flexible coupler: 60 V start-up (thesis Fig. 9-18)'
set ylabel 'crank speed [rad/s]'
plot '$out/flexible.csv' using 1:2 with lines lw 2 title 'flexible coupler', '$out/rigid.csv' using 1:2 with lines dt 2 lw 2 title 'rigid coupler'
set ylabel 'rocker speed [rad/s]'
plot '$out/flexible.csv' using 1:3 with lines lw 2 title 'flexible coupler', '$out/rigid.csv' using 1:3 with lines dt 2 lw 2 title 'rigid coupler'
set ylabel 'armature current [A]'
plot '$out/flexible.csv' using 1:4 with lines lw 2 title 'flexible coupler', '$out/rigid.csv' using 1:4 with lines dt 2 lw 2 title 'rigid coupler'
set ylabel 'joint 1 force [N]'
plot '$out/flexible.csv' using 1:5 with lines lw 2 title 'flexible coupler', '$out/rigid.csv' using 1:5 with lines dt 2 lw 2 title 'rigid coupler'
set ylabel 'coupler axial force [N] (> 0: tension)'
plot '$out/flexible.csv' using 1:6 with lines lw 2 title 'flexible coupler'
set ylabel 'coupler mid-point deflection [mm]'
plot '$out/flexible.csv' using 1:(1000*\$7) with lines lw 2 title 'flexible coupler'
unset multiplot
set output '$here/buckling.png'
set terminal pngcairo size 1000, 560 font 'DejaVu Sans,10'
set multiplot layout 2, 2 title 'rocker mass and inertia x200: the coupler buckles, the run stops (thesis Fig. 9-19)'
set xrange [0:0.45]
set ylabel 'crank speed [rad/s]'
plot '$out/heavy.csv' using 1:2 with lines lw 2 title 'rocker x200'
set ylabel 'rocker speed [rad/s]'
plot '$out/heavy.csv' using 1:3 with lines lw 2 title 'rocker x200'
set ylabel 'coupler axial force [N]'
plot '$out/heavy.csv' using 1:6 with lines lw 2 title 'rocker x200', -2286.04 with lines dt 2 lw 1 title 'Euler load -π²EI/L² (2286 N)'
set ylabel 'coupler mid-point deflection [mm]'
plot '$out/heavy.csv' using 1:(1000*\$7) with lines lw 2 title 'rocker x200 (stops at the slope limit)'
unset multiplot
GP
echo "wrote $here/startup.png and $here/buckling.png"
