# Pose error over time of the greedy, receding-horizon and offline plans (docs/horizon.md).
# Data: horizon_step.csv and horizon_breathing.csv, written by
#   headplan horizon scenarios/horizon/step.yaml -o docs/figures/horizon_step.csv
#   headplan horizon scenarios/horizon/breathing.yaml --prediction periodic \
#       -o docs/figures/horizon_breathing.csv
# Redraw: cd docs/figures && gnuplot horizon.gp
set terminal pngcairo size 1000,700 font "DejaVu Sans,10"
set output "horizon.png"
set datafile separator ","
set multiplot layout 2,1
set grid
set ylabel "pose error (largest axis, mm or deg)"
set key top right
set xlabel "time (s)"
plan(name, col) = (strcol(1) eq name) ? column(col) : 1/0
set title "step trace (a patient shifting), rate limit 0.25 kPa per row at 10 Hz"
set xrange [0:30]
plot "horizon_step.csv" using 2:(plan("greedy", 15)) with lines lw 1.5 lc rgb "#d62728" title "greedy", \
     "" using 2:(plan("receding", 15)) with lines lw 1.5 dt 2 lc rgb "#1f77b4" title "receding horizon (N 10, hold)", \
     "" using 2:(plan("offline", 15)) with lines lw 1.5 lc rgb "#2ca02c" title "offline (whole trace)", \
     0.5 with lines lw 1.5 lc rgb "black" dt 3 title "tolerance 0.5"
set title "breathing trace (0.25 Hz), rate limit 0.25 kPa per row at 10 Hz"
set xrange [0:60]
plot "horizon_breathing.csv" using 2:(plan("greedy", 15)) with lines lw 1.5 lc rgb "#d62728" title "greedy", \
     "" using 2:(plan("receding", 15)) with lines lw 1.5 dt 2 lc rgb "#1f77b4" title "receding horizon (N 10, periodic)", \
     "" using 2:(plan("offline", 15)) with lines lw 1.5 lc rgb "#2ca02c" title "offline (whole trace)", \
     0.5 with lines lw 1.5 lc rgb "black" dt 3 title "tolerance 0.5"
unset multiplot
