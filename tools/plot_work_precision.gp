# plot_work_precision.gp — error against wall time, one line per integrator,
# from a simulator's --work-precision CSV (columns: solver,rtol,atol,step_s,
# wall_s,steps,rhs_evals,fd_jac_rhs_evals,jac_evals,max_rel_error,energy_residual,status).
#   gnuplot -e "csv='wp.csv'; png='wp.png'; name='dc_motor'; solvers='rk4 dopri5 cvode'" tools/plot_work_precision.gp
set datafile separator ','
set terminal pngcairo size 800, 560 font 'DejaVu Sans,10'
set output png
set termoption noenhanced
set title sprintf('%s: work-precision (simulator --work-precision)', name) noenhanced
set logscale xy
set format x '10^{%L}'
set format y '10^{%L}'
set termoption enhanced
set xlabel 'wall time per run [s]'
set ylabel 'max relative error of the outputs'
set grid
set key outside right top
# ten integrators, ten colours (gnuplot's default cycle has eight)
set linetype 9 linecolor rgb '#8c564b'
set linetype 10 linecolor rgb '#7f7f7f'
set linetype cycle 10
# failed runs have error inf: gnuplot skips them
if (!exists('solvers')) solvers = 'euler heun symplectic_euler rk4 dopri5 linearly_implicit_euler ros2 generalized_alpha cvode ida'
plot for [s in solvers] csv every ::1 using (strcol(1) eq s ? $5 : NaN):($10 > 0 ? $10 : NaN) \
     with linespoints linewidth 2 pointtype 7 title s noenhanced
