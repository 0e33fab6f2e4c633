#!/usr/bin/env bash
# Streams N generated rows into `headplan batch` and reports peak RSS and rows per second
# (a benchmark, not a test: its numbers depend on the machine). docs/batch.md quotes a run.
#
#   bench/batch_memory.sh [ROWS] [JOBS] [HEADPLAN] [SCENE]
#     ROWS      rows to plan (default 10000000)
#     JOBS      --jobs (default 1)
#     HEADPLAN  the binary (default build/headplan)
#     SCENE     the scene (default scenarios/default.yaml)
#
# The trace is made by awk on the fly (a slow drift of a few mm and tenths of a degree, as a
# tracker reports it) and piped in (`-` is stdin), the output goes to /dev/null through
# `-o -`, so neither is held on disk. Peak RSS is GNU time's "Maximum resident set size" of
# headplan alone (the generator is a separate process outside the measurement).
set -euo pipefail
ROWS=${1:-10000000}
JOBS=${2:-1}
HP=${3:-build/headplan}
SCENE=${4:-scenarios/default.yaml}
[ -x /usr/bin/time ] || { echo "needs GNU time (/usr/bin/time, Debian package 'time')" >&2; exit 1; }
log=$(mktemp); trap 'rm -f "$log"' EXIT

gen() {
  awk -v n="$ROWS" 'BEGIN {
    print "# headplan-trace: rows=deviation"
    print "t_s,x_mm,y_mm,z_mm,pitch_deg,roll_deg,yaw_deg"
    for (i = 0; i < n; i++) {
      t = i / 10; s = sin(t / 40)
      printf "%.1f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f\n", t, 2*s, 1.2*s, -1.5*s, 0.5*s, 0.2*s, -0.3*s
    }
  }'
}

start=$(date +%s.%N)
gen | /usr/bin/time -v "$HP" batch "$SCENE" - --jobs "$JOBS" --no-progress --no-times \
  --format csv -o - >/dev/null 2>"$log" || { tail -n 30 "$log" >&2; exit 1; }
end=$(date +%s.%N)
rss_kb=$(awk -F': ' '/Maximum resident set size/ {print $2}' "$log")
wall=$(awk -F': ' '/Elapsed \(wall clock\)/ {print $2}' "$log")
grep '^headplan batch: [0-9]* rows' "$log"
awk -v rows="$ROWS" -v jobs="$JOBS" -v rss="$rss_kb" -v s="$start" -v e="$end" -v wall="$wall" \
  'BEGIN { printf "rows %d, jobs %d: peak RSS %.1f MB, %.0f rows/s (%s wall)\n",
           rows, jobs, rss / 1024, rows / (e - s), wall }'
