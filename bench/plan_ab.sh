#!/usr/bin/env bash
# Time two builds of the library against each other (a benchmark, not a test: the numbers
# depend on the machine and its load). Compiles bench/plan_time.c once against the headers of
# this tree and runs it PAIRS times in alternation against each folder's libheadplan.so
# (LD_LIBRARY_PATH), so a slow spell of the host hits both; prints both medians and the
# median of the per-pair ratios B/A. To keep a build for later: cp -a build/libheadplan.so* DIR
#
#   bench/plan_ab.sh LIBDIR_A LIBDIR_B [LEVEL MM DEG [PAIRS [ROUNDS]]]
#     defaults: LEVEL 2 (surface), MM 6, DEG 4 (binding targets), PAIRS 16, ROUNDS 30
set -euo pipefail
[ $# -ge 2 ] || { sed -n 2,10p "$0" >&2; exit 64; }
A=$1; B=$2; LEVEL=${3:-2}; MM=${4:-6}; DEG=${5:-4}; PAIRS=${6:-16}; ROUNDS=${7:-30}
for d in "$A" "$B"; do
  [ -e "$d/libheadplan.so" ] || { echo "plan_ab: no libheadplan.so in $d" >&2; exit 66; }
done
here=$(cd "$(dirname "$0")/.." && pwd)
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
cc -O2 -std=c11 -I "$here/include" -I "$here/build/include" "$here/bench/plan_time.c" \
  -o "$tmp/plan_time" -L "$A" -lheadplan -lm
scene="$here/scenarios/default.yaml"
for i in $(seq "$PAIRS"); do
  a=$(LD_LIBRARY_PATH=$A "$tmp/plan_time" "$scene" "$LEVEL" "$MM" "$DEG" "$ROUNDS")
  b=$(LD_LIBRARY_PATH=$B "$tmp/plan_time" "$scene" "$LEVEL" "$MM" "$DEG" "$ROUNDS")
  echo "$a $b"
done | python3 -c '
import sys, statistics as s
r = [tuple(map(float, l.split())) for l in sys.stdin]
a = [x for x, _ in r]; b = [y for _, y in r]
print("A median %.0f ns, B median %.0f ns, B/A %.3f, median of pair ratios %.3f (%d pairs)"
      % (s.median(a), s.median(b), s.median(b) / s.median(a), s.median([y / x for x, y in r]), len(r)))'
