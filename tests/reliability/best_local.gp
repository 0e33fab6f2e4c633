# The chart of the best-local-answer sweep beyond the clinical range (docs/control-loop.md,
# "The best local answer"): for every plan of the CSV that test_best_local writes with
# HP_BEST_LOCAL_BEYOND=1 HP_BEST_LOCAL_CSV=FILE, how much farther each backend's answer lies
# from the desired pose than the best answer (realtime, ipopt, nlopt-slsqp, multi-start), over
# the correction's size. The data is read from the file, never written into this script.
# Run: gnuplot -e "in='best_local.csv'; out='best_local.png'" tests/reliability/best_local.gp
# Columns: 1 case, 2 level, 3 t_mm, 4 angle_deg, then status and distance of realtime (5, 6),
# ipopt (7, 8), nlopt-slsqp (9, 10), multi-start (11, 12), and 13 the best distance.
if (!exists("in")) in = "best_local.csv"
if (!exists("out")) out = "best_local.png"
# A relative path is read as a path, never as gnuplot's '<command' or '|command'.
if (in[1:1] ne "/") in = "./".in
if (out[1:1] ne "/") out = "./".out
if (strstrt(GPVAL_TERMINALS, "pngcairo") > 0) {
  set terminal pngcairo size 1200,520 enhanced font "Sans,10"
} else {
  set terminal png size 1200,520
}
set output out
set datafile separator ","
floor = 1e-9   # a gap below the solvers' tolerances is drawn on this line
gap(c) = (valid(c) && valid(13)) ? ((column(c) - column(13)) > floor ? column(c) - column(13) : floor) : NaN
set multiplot layout 1,2 title "Distance to the desired pose beyond the best answer (plane and surface levels)" font ",12"
set grid
set logscale y
set format y "10^{%L}"
set ylabel "distance - best distance [mm/deg]"
set key top left box noenhanced
set yrange [floor / 3:*]
# The sweep's tolerance (BL_TOL): above this line an answer counts as worse.
set arrow from graph 0, first 1e-4 to graph 1, first 1e-4 nohead dt 2 lc rgb "#666666"
set xlabel "translation [mm]"
plot in using 3:(gap(8)) skip 1 with points pt 5 ps 0.6 lc rgb "#d95f02" title "ipopt", \
     in using 3:(gap(10)) skip 1 with points pt 9 ps 0.6 lc rgb "#7570b3" title "nlopt-slsqp", \
     in using 3:(gap(6)) skip 1 with points pt 6 ps 1.4 lc rgb "#1b9e77" title "realtime"
set xlabel "largest angle [deg]"
plot in using 4:(gap(8)) skip 1 with points pt 5 ps 0.6 lc rgb "#d95f02" title "ipopt", \
     in using 4:(gap(10)) skip 1 with points pt 9 ps 0.6 lc rgb "#7570b3" title "nlopt-slsqp", \
     in using 4:(gap(6)) skip 1 with points pt 6 ps 1.4 lc rgb "#1b9e77" title "realtime"
unset multiplot
