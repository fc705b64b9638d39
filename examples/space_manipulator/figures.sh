#!/usr/bin/env bash
# figures.sh — the space manipulator's figures (thesis Figs. 9-22 to 9-26)
# from the simulator the README's set-up builds:
#   planar.png: the planar manoeuvre: the payload tip's path, the flexible
#               arm's tip deviation and the joint torques, rigid and flexible
#   spatial.png: the 3-D manoeuvre (base turned by pi/2 as well)
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
build="${BUILD_DIR:-$here/../../build}"
out="$build/plots/space_manipulator"
mkdir -p "$out"
"$build/examples/space_manipulator" --quiet -o "$out/planar.csv"
"$build/examples/space_manipulator" --quiet --set base_final=1.5707963267948966 -o "$out/spatial.csv"
# columns: 1 t, 2-4 tip_x/y/z, 5 tip_deviation, 6 driven_error, 7-10 torque1..4,
# 11-13 flex_torque2..4, 14 link2_mid, 15 link3_mid, 16-18 driven_angle2..4
for case in planar spatial; do
gnuplot <<GP
set terminal pngcairo size 1000, 720 font 'DejaVu Sans,10'
set datafile separator ','
set grid
set key top right
set output '$here/$case.png'
set multiplot layout 2, 2 title 'space manipulator, $case manoeuvre (T_s = 15 s)'
set xlabel 'x [m]'; set ylabel 'y [m]'
set size ratio -1
set title 'payload tip path, seen along z (rigid arm, prescribed joints)'
plot '$out/$case.csv' using 2:3 with lines lw 2 notitle
set size noratio
set xlabel 't [s]'; set ylabel 'deviation from the rigid arm [m]'
set title 'payload tip: flexible arm'
plot '$out/$case.csv' using 1:5 with lines lw 2 title 'same joint motion', \
     '' using 1:6 with lines lw 2 title "driven by the rigid arm's torques"
set ylabel 'torque [N m]'
set title 'joint torques: rigid arm (solid), flexible arm on the same motion (dashed)'
plot '$out/$case.csv' using 1:8 with lines lw 2 lc 1 title 'joint 2', '' using 1:11 with lines dt 2 lc 1 notitle, \
     '' using 1:9 with lines lw 2 lc 2 title 'joint 3', '' using 1:12 with lines dt 2 lc 2 notitle, \
     '' using 1:10 with lines lw 2 lc 3 title 'joint 4', '' using 1:13 with lines dt 2 lc 3 notitle, \
     '' using 1:7 with lines lw 2 lc 4 title 'joint 1 (base)'
set ylabel 'mid-span deflection [mm]'
set title 'flexible arm on the same motion: link bending in the pins plane'
plot '$out/$case.csv' using 1:(1000*\$14) with lines lw 2 title 'link 2', '' using 1:(1000*\$15) with lines lw 2 title 'link 3'
unset multiplot
GP
done
echo "wrote $here/planar.png and $here/spatial.png"
