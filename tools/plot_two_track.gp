# plot_two_track.gp — the figure of examples/two_track/README.md, from the CSVs
# that README names (run from the repository root after writing them to build/plots/).
set datafile separator ','
set terminal pngcairo size 1200,850 font ',10'
set output 'examples/two_track/two_track.png'
set termoption noenhanced
set multiplot layout 2,2 title 'Two-track vehicle, 14 DOF, Magic Formula tyres (examples/two_track)'
set key top right
set xlabel 't (s)'
set title 'step steer 0.03 rad at 20 m/s'
set ylabel 'yaw rate (rad/s), ay / 20 (m/s^2)'
set y2label 'roll (rad)'
set y2tics
plot 'build/plots/two_track_step.csv' using 1:'yaw_rate [rad/s]' with lines lw 2 title 'yaw rate', \
     '' using 1:(column('ay [m/s^2]') / 20) with lines lw 2 title 'ay / 20', \
     '' using 1:'roll [rad]' axes x1y2 with lines lw 2 dt 2 title 'roll'
unset y2label
unset y2tics
set title 'ISO 3888-1 double lane change at 80 km/h (open-loop steering)'
set xlabel 'x (m)'
set ylabel 'y (m)'
plot 'build/plots/two_track_lane_change.csv' using 'x [m]':'y [m]' with lines lw 2 title 'path of the centre of mass'
set xlabel 't (s)'
set title 'lane change: wheel loads'
set ylabel 'Fz (N)'
plot 'build/plots/two_track_lane_change.csv' using 1:'Fz_fl [N]' with lines title 'Fz fl', '' using 1:'Fz_fr [N]' with lines title 'Fz fr', \
     '' using 1:'Fz_rl [N]' with lines title 'Fz rl', '' using 1:'Fz_rr [N]' with lines title 'Fz rr'
set title 'a 5 cm bump at 10 m/s: front wheel loads and the energy balance'
set ylabel 'Fz (N)'
set y2label 'energy balance (J, 0 = exact)'
set y2tics
plot 'build/plots/two_track_bump.csv' using 1:'Fz_fl [N]' with lines lw 2 title 'Fz fl', '' using 1:'Fz_rl [N]' with lines lw 2 title 'Fz rl', \
     '' using 1:(column('balance [J]') - 90471.3482423941) axes x1y2 with lines dt 2 title 'balance - start'
unset multiplot
