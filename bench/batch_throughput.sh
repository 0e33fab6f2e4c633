#!/usr/bin/env bash
# Verified rows per CPU-second of `headplan batch` (a benchmark, not a test: its numbers
# depend on the machine). Every row is planned and, when reached, its strict round trip
# checked inside hp_plan; the output (CSV, every number in its shortest round-trip form) goes
# to /dev/null. Rows per CPU-second = rows / (user + system time of headplan alone), so a
# loaded machine costs wall time, not the rate (up to cache effects). docs/batch.md quotes a run.
#
#   bench/batch_throughput.sh [ROWS] [IPOPT_ROWS] [HEADPLAN] [SCENE]
#     ROWS        rows of each realtime run (default 200000: GNU time counts CPU time in
#                 10 ms steps, so a run must take seconds for the rate to mean 1 %)
#     IPOPT_ROWS  rows of the Ipopt run on the binding trace (default 200)
#
# Two generated traces (deviation rows, a slow drift as a tracker reports it;
# bench/batch_traces.sh):
#   reachable: x from 0 to 0.5 mm (the other axes in proportion, up to 0.13 deg), no limit
#              binds (the direct chain answers);
#   binding:   x from 0 to 6 mm, up to 1.5 deg: a pressure or stretch limit binds on most rows.
# Runs: realtime at the linear and surface levels on both traces, Ipopt at the surface level
# on the first IPOPT_ROWS binding rows; the last line is the ratio of realtime's surface-level
# rate to Ipopt's on the binding rows.
set -euo pipefail
ROWS=${1:-200000}
IROWS=${2:-200}
HP=${3:-build/headplan}
SCENE=${4:-scenarios/default.yaml}
[ -x /usr/bin/time ] || { echo "needs GNU time (/usr/bin/time, Debian package 'time')" >&2; exit 1; }
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT

source "$(dirname "$0")/batch_traces.sh"
batch_trace "$ROWS" 0.25 1 >"$tmp/reachable.csv"
batch_trace "$ROWS" 3 1 >"$tmp/binding.csv"
head -n $((IROWS + 2)) "$tmp/binding.csv" >"$tmp/binding_ipopt.csv"

# run TRACE BACKEND LEVEL ROWS -> prints "rows/s  summary"; sets RATE
run() {
  /usr/bin/time -f '%U %S' -o "$tmp/t" "$HP" batch "$SCENE" "$1" --backend "$2" --level "$3" \
    --no-progress --no-times --format csv -o - >/dev/null 2>"$tmp/log" || { tail -n 5 "$tmp/log" >&2; exit 1; }
  RATE=$(awk -v n="$4" '{ printf "%.0f", n / ($1 + $2) }' "$tmp/t")
  printf '%-10s %-9s %-8s %8d rows %9s rows/CPU-s   %s\n' "$(basename "$1" .csv)" "$2" "$3" "$4" \
    "$RATE" "$(grep -o '[0-9]* reached, [0-9]* closest' "$tmp/log")"
}
run "$tmp/reachable.csv" realtime linear "$ROWS"
run "$tmp/reachable.csv" realtime surface "$ROWS"
run "$tmp/binding.csv" realtime linear "$ROWS"
run "$tmp/binding.csv" realtime surface "$ROWS"; RT=$RATE
run "$tmp/binding_ipopt.csv" ipopt surface "$IROWS"; IP=$RATE
awk -v a="$RT" -v b="$IP" 'BEGIN { printf "binding rows, surface level: realtime / ipopt = %.0fx\n", a / b }'
