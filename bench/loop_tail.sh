#!/usr/bin/env bash
# The loop benchmark's tail in instructions: each plan's own work, counted by valgrind's
# callgrind (one profile dump after each hp_plan), so the p99.9 does not depend on how busy
# the machine is. Runs headplan-bench-count's tail mode (bench/plan_count.c: the loop
# benchmark's trace on a rate-free and a rate-limited realtime planner in turn, rate_max
# 500 Pa) and prints, for each planner, the median, p99, p99.9 and max of the instructions a
# plan (nearest rank, as the loop benchmark's percentiles), the rate-limited planner's ratios
# to the rate-free one's, its slowest plans beside the rate-free plan of the same cycle, and
# where its slowest 1 % of plans spend their instructions (inclusive, a plan on average).
# docs/control-loop.md quotes a run.
#
#   bench/loop_tail.sh [COUNT_PROGRAM] [SCENE] [LEVEL] [TRACE] [FEED] [CYCLES]
#   defaults: build/headplan-bench-count scenarios/default.yaml 0 step 0 3000
#   LEVEL 0 linear, 1 plane, 2 surface; TRACE smooth, noisy or step; FEED 1 feeds the
#   rate-limited planner ±3 Pa readings of its answers (the loop benchmark's measured mode).
# Needs bash 4 or later (an associative array) and valgrind.
set -euo pipefail
PROG=${1:-build/headplan-bench-count}
SCENE=${2:-scenarios/default.yaml}
LEVEL=${3:-0}
TRACE=${4:-step}
FEED=${5:-0}
CYCLES=${6:-3000}
command -v valgrind >/dev/null || { echo "loop_tail.sh: needs valgrind (Debian package 'valgrind')" >&2; exit 1; }
command -v callgrind_annotate >/dev/null || { echo "loop_tail.sh: needs callgrind_annotate (valgrind)" >&2; exit 1; }
[ -x "$PROG" ] || { echo "loop_tail.sh: $PROG: not an executable program" >&2; exit 1; }
[ -r "$SCENE" ] || { echo "loop_tail.sh: $SCENE: cannot read the scene" >&2; exit 1; }
prog=$(cd "$(dirname "$PROG")" && pwd)/$(basename "$PROG")
scene=$(cd "$(dirname "$SCENE")" && pwd)/$(basename "$SCENE")
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
mkdir "$tmp/cg"
# Dumps are numbered from 1 in the order of the plans: plan i of the listing is dump i.
(cd "$tmp/cg" && valgrind --tool=callgrind --collect-atstart=no --toggle-collect=hp_plan \
    --dump-after=hp_plan --dump-instr=no --dump-line=no --callgrind-out-file=cg \
    "$prog" "$scene" tail "$LEVEL" "$TRACE" "$FEED" "$CYCLES" >"$tmp/plans" 2>"$tmp/err") \
  || { tail -n 5 "$tmp/err" >&2; exit 1; }
n=$(wc -l <"$tmp/plans")
[ "$n" -eq $((2 * CYCLES)) ] || { echo "loop_tail.sh: $n plans listed, expected $((2 * CYCLES))" >&2; exit 1; }
# A dump beyond the plans (an hp_plan call the listing does not show) would shift every
# plan onto another's dump.
[ -e "$tmp/cg/cg.$((n + 1))" ] && { echo "loop_tail.sh: more profile dumps than plans" >&2; exit 1; }
(cd "$tmp/cg" && seq 1 "$n" | sed 's/^/cg./' | xargs awk '/^summary:/ { print $2; nextfile }') >"$tmp/ir"
[ "$(wc -l <"$tmp/ir")" -eq "$n" ] || { echo "loop_tail.sh: fewer profile dumps than plans" >&2; exit 1; }
paste -d' ' "$tmp/plans" "$tmp/ir" >"$tmp/joined"
echo "level $LEVEL, $TRACE trace, feed $FEED, $CYCLES cycles: instructions a plan (callgrind)"
# Nearest-rank percentile of a sorted column, as bench_percentile (bench/bench_timing.c).
pct() { # FILE P
  sort -n "$1" | awk -v p="$2" '{ a[NR] = $1 } END {
    if (p == 0.5) { print (NR % 2) ? a[(NR + 1) / 2] : 0.5 * (a[NR / 2] + a[NR / 2 + 1]); exit }
    k = p * NR; k = (k == int(k)) ? k : int(k) + 1; if (k < 1) k = 1; if (k > NR) k = NR
    print a[k] }'
}
declare -A st
for m in 0 1; do
  awk -v m=$m '$2 == m { print $5 }' "$tmp/joined" >"$tmp/ir$m"
  for p in 0.5 0.99 0.999 1; do st[$m,$p]=$(pct "$tmp/ir$m" $p); done
done
printf '%-13s %9s %9s %9s %9s\n' planner median p99 p99.9 max
printf '%-13s %9.0f %9.0f %9.0f %9.0f\n' rate-free "${st[0,0.5]}" "${st[0,0.99]}" "${st[0,0.999]}" "${st[0,1]}"
printf '%-13s %9.0f %9.0f %9.0f %9.0f\n' rate-limited "${st[1,0.5]}" "${st[1,0.99]}" "${st[1,0.999]}" "${st[1,1]}"
awk -v a="${st[1,0.5]}" -v b="${st[0,0.5]}" -v c="${st[1,0.999]}" -v d="${st[0,0.999]}" \
  'BEGIN { printf "ratio         median %.2f  p99.9 %.2f\n", a / b, c / d }'
echo "slowest rate-limited plans (cycle, instructions, the rate-free plan's of the cycle):"
awk '$2 == 1 { print $1, $5 }' "$tmp/joined" | sort -k2,2nr | awk 'NR <= 8' >"$tmp/top"
while read -r j ir; do
  printf '  %5d %7d %7d\n' "$j" "$ir" "$(awk -v j="$j" '$1 == j && $2 == 0 { print $5 }' "$tmp/joined")"
done <"$tmp/top"
# The slowest 1 % of the rate-limited plans, by function (inclusive, mean a plan).
slow=$(( (CYCLES + 99) / 100 ))
awk '$2 == 1 { print NR, $5 }' "$tmp/joined" | sort -k2,2nr | awk -v n="$slow" 'NR <= n' | cut -d' ' -f1 >"$tmp/slow"
while read -r i; do
  callgrind_annotate --inclusive=yes --auto=no --threshold=100 "$tmp/cg/cg.$i" >"$tmp/ann" \
    || { echo "loop_tail.sh: callgrind_annotate failed on the dump of plan $i" >&2; exit 1; }
  awk '/^-+$/ { sec++ } sec >= 3 && $1 ~ /^[0-9,]+$/ && $0 ~ /:/ {
        ir = $1; gsub(",", "", ir); f = $0; sub(/ \[.*/, "", f); sub(/.*:/, "", f); gsub(/ /, "_", f)
        if (!(f in m) || ir + 0 > m[f]) m[f] = ir + 0 }
        END { for (f in m) print f, m[f] }' "$tmp/ann" # a function inlined elsewhere is listed once more
done <"$tmp/slow" | awk -v n="$slow" '{ s[$1] += $2 } END { for (f in s) printf "%s %.0f\n", f, s[f] / n }' \
  | sort -k2,2nr | awk '!/^(main|\(below|0x|__libc_start)/' | awk 'NR <= 16' >"$tmp/fn"
echo "the slowest $slow rate-limited plans, by function (inclusive, mean a plan):"
awk '{ printf "  %-36s %7d\n", $1, $2 }' "$tmp/fn"
