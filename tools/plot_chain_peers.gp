# plot_chain_peers.gp — wall time of a 1 s chain run (to 1e-6 rad) against N,
# one line per engine, from bench/peers' CSV (n,engine,step_s,steps,error_rad,
# run_s,us_per_step,ratio_to_mbgc; five engines per N, in the same order;
# the header is line 0 of `every`).
#   gnuplot -e "csv='chain_peers.csv'; png='chain_peers.png'" tools/plot_chain_peers.gp
set datafile separator ','
set terminal pngcairo size 800, 560 font 'DejaVu Sans,10'
set output png
set termoption noenhanced
set title 'planar chain, 1 s to 1e-6 rad with RK4: wall time against N (tools/bench_peers.sh)'
set logscale xy
set xtics (2, 8, 32, 100)
set xrange [1.6:130]
set xlabel 'N (rods)'
set ylabel 'wall time of one 1 s run [s]'
set grid
set key left top
engine(i) = system(sprintf("awk -F, 'NR == %d { print $2 }' '%s'", i + 2, csv))
plot for [i = 0:4] csv every 5::(i + 1) using 1:6 with linespoints linewidth 2 pointtype 7 title engine(i)
