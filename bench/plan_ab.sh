#!/usr/bin/env bash
# Compare two builds of the library (a benchmark, not a test: the times depend on the
# machine and its load). Compiles bench/plan_count.c once against the headers of this tree
# and runs it against each folder's libheadplan.so (LD_LIBRARY_PATH):
#   1. answers: 400 seeded targets, cold and warm, at the given level and size; prints how
#      many statuses or active-set step counts differ and the largest difference of the
#      achieved poses (mm or deg);
#   2. time: PAIRS runs of the time mode in alternation, so a slow spell of the host hits
#      both; prints both medians and the median of the per-pair ratios B/A.
#   3. interleaved: both libraries in one process (bench/plan_ab_inproc.c), ROUNDS_IN
#      rounds of 80 cold plans of each in alternating order; the median of the round
#      ratios B/A resolves ~1 % where part 2 does not (the host drifts by ±10 % over
#      seconds). A build against itself gave 0.985 to 1.006 in three runs of 400 to 2000
#      rounds: differences under ~2 % need repeated runs in both orders.
# To keep a build for later: cp -a build/libheadplan.so* DIR
#
#   bench/plan_ab.sh LIBDIR_A LIBDIR_B [LEVEL MM DEG [PAIRS [ROUNDS [ROUNDS_IN]]]]
#     defaults: LEVEL 2 (surface), MM 6, DEG 4 (binding targets), PAIRS 16, ROUNDS 30,
#     ROUNDS_IN 2000 (0 skips part 3; PAIRS 0 skips part 2)
set -euo pipefail
[ $# -ge 2 ] || { sed -n 2,19p "$0" >&2; exit 64; }
A=$1; B=$2; LEVEL=${3:-2}; MM=${4:-6}; DEG=${5:-4}; PAIRS=${6:-16}; ROUNDS=${7:-30}
ROUNDS_IN=${8:-2000}
NAME=plan_ab
source "$(dirname "$0")/count_two.sh"
for warm in 0 1; do
  run "$A" answers "$LEVEL" "$MM" "$DEG" "$warm" >"$tmp/a"
  run "$B" answers "$LEVEL" "$MM" "$DEG" "$warm" >"$tmp/b"
  python3 - "$tmp/a" "$tmp/b" "$warm" <<'PY'
import sys
a = [l.split() for l in open(sys.argv[1])]; b = [l.split() for l in open(sys.argv[2])]
scale = [1e3] * 3 + [57.29577951308232] * 3          # m -> mm, rad -> deg
diff = sum(x[:2] != y[:2] for x, y in zip(a, b))
worst = max(abs(float.fromhex(x[2 + i]) - float.fromhex(y[2 + i])) * scale[i]
            for x, y in zip(a, b) for i in range(6))
print("answers (%s, %d targets): %d differ in status or steps, largest pose difference %.3g mm/deg"
      % ("warm" if sys.argv[3] == "1" else "cold", len(a), diff, worst))
PY
done
if [ "$PAIRS" -gt 0 ]; then
for i in $(seq "$PAIRS"); do
  echo "$(run "$A" time "$LEVEL" "$MM" "$DEG" "$ROUNDS") $(run "$B" time "$LEVEL" "$MM" "$DEG" "$ROUNDS")"
done | python3 -c '
import sys, statistics as s
r = [tuple(map(float, l.split())) for l in sys.stdin]
a = [x for x, _ in r]; b = [y for _, y in r]
print("time: A median %.0f ns, B median %.0f ns, B/A %.3f, median of pair ratios %.3f (%d pairs)"
      % (s.median(a), s.median(b), s.median(b) / s.median(a), s.median([y / x for x, y in r]), len(r)))'
fi
if [ "$ROUNDS_IN" -gt 0 ]; then
  cc -O2 -std=c11 "${inc[@]}" "$here/bench/plan_ab_inproc.c" \
    -o "$tmp/inproc" -ldl -lm
  # two files, so the loader maps two copies even when A and B are the same build
  cp "$A/libheadplan.so" "$tmp/a.so"
  cp "$B/libheadplan.so" "$tmp/b.so"
  "$tmp/inproc" "$tmp/a.so" "$tmp/b.so" "$scene" "$LEVEL" "$MM" "$DEG" "$ROUNDS_IN"
fi
