#!/usr/bin/env bash
# Instructions per hp_plan call, counted by valgrind's callgrind (a benchmark, not a test:
# counts depend on the compiler and the code, not on how busy the machine is). Runs
# headplan-bench-count (bench/plan_count.c) on the default scene: 40 seeded targets of
# ±6 mm, ±4° (most bind a limit) and of ±0.5 mm, ±0.3° (the direct chain), cold, 3 passes,
# at each level. CHANGELOG.md (realtime backend speed work) quotes runs.
#
#   bench/plan_instructions.sh [COUNT_PROGRAM] [SCENE]
#     COUNT_PROGRAM  default build/headplan-bench-count; to measure another commit, build its
#                    headplan_static and compile bench/plan_count.c against it (section 6).
set -euo pipefail
PROG=${1:-build/headplan-bench-count}
SCENE=${2:-scenarios/default.yaml}
command -v valgrind >/dev/null || { echo "needs valgrind (Debian package 'valgrind')" >&2; exit 1; }
command -v callgrind_annotate >/dev/null || { echo "needs callgrind_annotate (valgrind)" >&2; exit 1; }
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
names=(linear plane surface)
for spec in "0 6 4" "1 6 4" "2 6 4" "0 0.5 0.3" "1 0.5 0.3" "2 0.5 0.3"; do
  set -- $spec
  valgrind --tool=callgrind --callgrind-out-file="$tmp/cg" "$PROG" "$SCENE" cold "$1" "$2" "$3" 3 \
    >"$tmp/out" 2>"$tmp/err" || { tail -n 5 "$tmp/err" >&2; exit 1; }
  # Inclusive instructions of hp_plan over the 3 × 40 plans.
  callgrind_annotate --inclusive=yes "$tmp/cg" >"$tmp/ann"
  ir=$(awk '/[^_]hp_plan \[/ && !done { gsub(",", "", $1); print $1; done = 1 }' "$tmp/ann")
  [ -n "$ir" ] || { echo "hp_plan not found in the profile" >&2; exit 1; }
  printf '%-8s ±%s mm ±%s deg: %7d instructions per hp_plan   (%s)\n' "${names[$1]}" "$2" "$3" \
    $((ir / 120)) "$(cat "$tmp/out")"
done
