# plot_csv.gp — one panel per output column of a simulator CSV, against t.
#   gnuplot -e "csv='run.csv'; png='run.png'; name='dc_motor'" tools/plot_csv.gp
set datafile separator ','
stats csv skip 1 nooutput
ncols = STATS_columns
panels = ncols - 1
set terminal pngcairo size 900, (180 * panels + 60) font 'DejaVu Sans,10'
set output png
set termoption noenhanced
set multiplot layout panels, 1 title sprintf('%s  (mbgc simulation)', name)
set grid
set key top right
set lmargin 12
do for [i = 2:ncols] {
  if (i == ncols) { set xlabel 't [s]' } else { unset xlabel }
  plot csv using 1:i with lines linewidth 2 title columnhead(i)
}
unset multiplot
