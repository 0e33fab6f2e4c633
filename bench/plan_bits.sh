#!/usr/bin/env bash
# Are two builds of the library's answers the same bits? Compiles bench/plan_count.c once
# against this tree's headers and runs its bits mode against each folder's libheadplan.so
# (LD_LIBRARY_PATH): the loop benchmark's three traces at the three contact levels, each
# with the planner's own answers and with measured pressures fed back, on a rate-free and
# a rate-limited planner (18 replays, 2·CYCLES plans each: 108 000 plans at the default
# 3000). Every answer's pose, pose error, pressures, radii and binding flags are printed in
# %a and compared as text; prints the count and the first differing plan, exit 1 if any
# differ. A change meant to keep every answer (a speed-up) is checked this way:
#   cp -a build/libheadplan.so* /tmp/before   (on the commit before)
#   bash bench/plan_bits.sh /tmp/before build
#
#   bench/plan_bits.sh LIBDIR_A LIBDIR_B [CYCLES]     CYCLES default 3000
set -euo pipefail
[ $# -ge 2 ] || { sed -n 2,13p "$0" >&2; exit 64; }
A=$1; B=$2; CYCLES=${3:-3000}
NAME=plan_bits
source "$(dirname "$0")/count_two.sh"
run "$A" bits "$CYCLES" >"$tmp/a"
run "$B" bits "$CYCLES" >"$tmp/b"
n=$(wc -l <"$tmp/a")
if cmp -s "$tmp/a" "$tmp/b"; then
  echo "plan_bits: $n plans, the same bits"
else
  d=$(diff "$tmp/a" "$tmp/b" | grep -c '^<' || true)
  # diff exits 1 on a difference (and may die of a closed pipe after grep's first match):
  # under pipefail that would stop the script here, before the report.
  first=$(diff "$tmp/a" "$tmp/b" | grep -m1 '^<' | cut -d' ' -f2-7 || true)
  echo "plan_bits: $n plans, $d differ; the first: $first (level, trace, feed, cycle, planner, status)"
  exit 1
fi
