# plot_tree_peers.gp — wall time of a 1 s run (to 1e-6 m) of the two 3-D
# models, one pair of bars per engine, from tree_peers' CSVs (n,engine,step_s,
# steps,error_m,run_s,us_per_step,ratio_to_mbgc; the same five engines in the
# same order in both), labelled with the number of steps each engine needed.
#   gnuplot -e "tree='binary_tree_peers.csv'; chain='spherical_chain_peers.csv'; png='tree_peers.png'" tools/plot_tree_peers.gp
set datafile separator ','
set terminal pngcairo size 900, 560 font 'DejaVu Sans,10'
set output png
set termoption noenhanced
set title "3-D models, 1 s to 1e-6 m: wall time per engine (tools/bench_peers.sh)\n(bar labels: RK4 steps needed)"
set logscale y
set yrange [1e-3:*]
set ylabel 'wall time of one 1 s run [s]'
set grid ytics
set key left top
set style data histograms
set style histogram cluster gap 1
set style fill solid 0.7 border -1
set boxwidth 0.9
set xtics scale 0
set xrange [0.4:5.6]  # (the header line takes histogram slot 0)
plot tree using 6:xtic(2) title 'binary tree, N = 31 (ball + universal joints)', \
     chain using 6 title 'spherical chain, N = 32 (ball joints)', \
     tree using ($0 - 0.15):($6 * 1.15):(sprintf('%d', $4)) with labels notitle, \
     chain using ($0 + 0.15):($6 * 1.15):(sprintf('%d', $4)) with labels notitle
