# Sourced by bench/batch_throughput.sh and bench/batch_instructions.sh: the two generated
# deviation traces (a slow drift as a tracker reports it) both measure.
#   batch_trace ROWS AMPLITUDE_MM OFFSET > FILE
# The drift is a·(OFFSET + sin(t/40)) along x, the other axes in proportion (y 0.6, z −0.75
# in mm; pitch 0.25, roll 0.1, yaw −0.15 in degrees). With OFFSET 1: AMPLITUDE 0.25 stays
# reachable (x up to 0.5 mm), 3 binds a pressure or stretch limit on most rows (x up to 6 mm).
batch_trace() {
  awk -v n="$1" -v a="$2" -v o="$3" 'BEGIN {
    print "# headplan-trace: rows=deviation"
    print "t_s,x_mm,y_mm,z_mm,pitch_deg,roll_deg,yaw_deg"
    for (i = 0; i < n; i++) {
      t = i / 10; s = o + sin(t / 40)
      printf "%.1f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f\n", t, a*s, 0.6*a*s, -0.75*a*s, 0.25*a*s, 0.1*a*s, -0.15*a*s
    }
  }'
}
