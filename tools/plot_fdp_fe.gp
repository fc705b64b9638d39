# plot_fdp_fe.gp — the figure of examples/flexible_double_pendulum_fe/README.md, from the
# CSVs that README names (run from the repository root after writing them to build/plots/).
set datafile separator ','
set terminal pngcairo size 1100,800 font ',10'
set output 'examples/flexible_double_pendulum_fe/flexible_double_pendulum_fe.png'
set multiplot layout 2,2 title 'Double pendulum of two 2 x 5 x 900 mm strips: reduced from 1200 bricks (fe) against built-in beams (eb)'
set key top right
set xlabel 't (s)'
set ylabel 'lower tip z (m)'
set title 'held in the plane (knee a hinge about y)'
plot 'build/plots/fdp_fe_planar.csv' using 1:'fe_tip_z' with lines lw 2 title 'fe', '' using 1:'eb_tip_z' with lines dt 2 lw 2 title 'eb'
set ylabel 'lower strip deflection, in plane (m)'
set title 'held in the plane: tip deflection of the lower strip'
plot 'build/plots/fdp_fe_planar.csv' using 1:'fe_deflection_2' with lines lw 2 title 'fe', '' using 1:'eb_deflection_2' with lines dt 2 lw 2 title 'eb'
set ylabel 'sin(roll) of the lower strip'
set title 'on the ball joint (the document''s scene): the lower strip rolls'
set yrange [-1.05:1.05]
plot 'build/plots/fdp_fe_ball.csv' using 1:'roll_2' with lines lw 2 title 'fe (stopped at 1.92 s: validity)', 'build/plots/fdp_ball.csv' using 1:'roll_2' with lines dt 2 lw 2 title 'eb'
set autoscale y
set ylabel 'lower strip deflection, sideways (m)'
set title 'on the ball joint: then bends sideways'
plot 'build/plots/fdp_fe_ball.csv' using 1:'lateral_2' with lines lw 2 title 'fe', 'build/plots/fdp_ball.csv' using 1:'lateral_2' with lines dt 2 lw 2 title 'eb'
unset multiplot
