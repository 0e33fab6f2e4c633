#!/usr/bin/env bash
# Instructions per `headplan batch` row, counted by valgrind's callgrind (a benchmark, not a
# test: the counts depend on the compiler and the code, not on how busy the machine is), and
# where they go. docs/batch.md quotes a run.
#
#   bench/batch_instructions.sh [ROWS] [HEADPLAN] [SCENE]
#     ROWS      rows of the shorter run (default 2000)
#     HEADPLAN  default build/headplan; to measure another commit, build its headplan_cli
#               (git archive COMMIT | tar -x -C DIR; cmake -S DIR -B DIR/build; cmake
#               --build DIR/build --target headplan_cli) and pass DIR/build/headplan
#
# Each case runs twice, on the first ROWS and the first 2·ROWS rows of a generated trace
# (bench/batch_traces.sh), output CSV to stdout (discarded) with --no-times; a row's count is
# the difference of the two runs over ROWS, so start-up (loading, planner creation) drops
# out. The parts are the same differences of callgrind's inclusive counts:
#   state    hp_planner_set_previous_result (the state from the previous row's output;
#            hp_planner_set_previous, from the previous pressures, before 2026-12-01)
#   plan     hp_plan
#   numbers  cli_fmt_len (the ~60 numbers in shortest round-trip form; cli_fmt before
#            2026-12-02)
#   write    the rest of writing the row (batch_sink_rows without cli_fmt)
#   read     hp_trace_next (reading and checking the trace row)
#   hash     sha256_file (the trace's SHA-256 for the metadata)
set -euo pipefail
ROWS=${1:-2000}
HP=${2:-build/headplan}
SCENE=${3:-scenarios/default.yaml}
command -v valgrind >/dev/null || { echo "needs valgrind (Debian package 'valgrind')" >&2; exit 1; }
command -v callgrind_annotate >/dev/null || { echo "needs callgrind_annotate (valgrind)" >&2; exit 1; }
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
source "$(dirname "$0")/batch_traces.sh"

# counts TRACE LEVEL OUT: total and the parts' inclusive counts, one "name count" a line.
# (callgrind_annotate puts a long name's "[binary]" on the next line: names end at " [" or
# at the line's end.)
counts() {
  valgrind --tool=callgrind --callgrind-out-file="$tmp/cg" "$HP" batch "$SCENE" "$1" \
    --level "$2" --no-progress --no-times --format csv -o - >/dev/null 2>"$tmp/err" \
    || { tail -n 5 "$tmp/err" >&2; exit 1; }
  callgrind_annotate --inclusive=yes --threshold=100 "$tmp/cg" >"$tmp/ann"
  awk '
    function grab(name, pat) { if ($0 ~ pat && !(name in got)) { c = $1; gsub(",", "", c); got[name] = c } }
    /PROGRAM TOTALS/ { c = $1; gsub(",", "", c); got["total"] = c }
    { grab("state", "[^_]hp_planner_set_previous(_result)?( \\[|$)");
      grab("plan", "[^_]hp_plan( \\[|$)");
      grab("numbers", "[^_]cli_fmt(_len)?( \\[|$)");
      grab("rows", "[^_]batch_sink_rows( \\[|$)");
      grab("read", "[^_]hp_trace_next( \\[|$)");
      grab("hash", "[^_]sha256_file( \\[|$)") }
    END { for (k in got) print k, got[k] }' "$tmp/ann" >"$3"
}

# case NAME AMPLITUDE LEVEL
case_() {
  batch_trace "$ROWS" "$2" 1 >"$tmp/a.csv"
  batch_trace $((2 * ROWS)) "$2" 1 >"$tmp/b.csv"
  counts "$tmp/a.csv" "$3" "$tmp/ca"
  counts "$tmp/b.csv" "$3" "$tmp/cb"
  awk -v n="$ROWS" -v name="$1" -v level="$3" '
    NR == FNR { a[$1] = $2; next } { b[$1] = $2 }
    END {
      for (k in b) d[k] = (b[k] - a[k]) / n
      d["write"] = d["rows"] - d["numbers"]
      printf "%-9s %-8s row %7.0f   state %6.0f  plan %6.0f  numbers %6.0f  write %6.0f  read %6.0f  hash %5.0f  other %6.0f\n",
        name, level, d["total"], d["state"], d["plan"], d["numbers"], d["write"], d["read"], d["hash"],
        d["total"] - d["state"] - d["plan"] - d["numbers"] - d["write"] - d["read"] - d["hash"]
    }' "$tmp/ca" "$tmp/cb"
}
echo "instructions per row (callgrind), $ROWS-row difference:"
case_ reachable 0.25 linear
case_ reachable 0.25 surface
case_ binding 3 linear
case_ binding 3 surface
