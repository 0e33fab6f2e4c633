#!/usr/bin/env bash
# Where a rate-limited plan with measured feedback spends its instructions, by phase
# (valgrind's callgrind: counts, unlike times, do not depend on how busy the machine is).
# Runs headplan-bench-count's loop mode (bench/plan_count.c: the step trace, rate_max
# 500 Pa, ±3 Pa readings through hp_planner_set_measured) at the plane and surface levels on
# the realtime backend and NLopt SLSQP, and prints hp_plan's instructions per plan and the
# share of each phase. docs/control-loop.md quotes a run.
#
#   bench/loop_profile.sh [COUNT_PROGRAM] [SCENE] [CYCLES] [LEVELS]
#   LEVELS: the contact levels to run, "1 2" unless given (0 linear, 1 plane, 2 surface)
set -euo pipefail
PROG=${1:-build/headplan-bench-count}
SCENE=${2:-scenarios/default.yaml}
CYCLES=${3:-3000}
LEVELS=${4:-1 2}
for level in $LEVELS; do
  case $level in
    0|1|2) ;;
    *) echo "loop_profile.sh: level '$level': must be 0, 1 or 2" >&2; exit 64 ;;
  esac
done
command -v valgrind >/dev/null || { echo "needs valgrind (Debian package 'valgrind')" >&2; exit 1; }
command -v callgrind_annotate >/dev/null || { echo "needs callgrind_annotate (valgrind)" >&2; exit 1; }
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
names=(linear plane surface)
printf '%-8s %-12s %9s  %s\n' level backend "Ir/plan" "phase shares of the plan"
for level in $LEVELS; do
  for backend in realtime nlopt-slsqp; do
    valgrind --tool=callgrind --callgrind-out-file="$tmp/cg" "$PROG" "$SCENE" loop "$level" \
      "$backend" "$CYCLES" >"$tmp/out" 2>"$tmp/err" || { tail -n 5 "$tmp/err" >&2; exit 1; }
    # --threshold=100: every function; at the default (99 % of the self cost) hp_plan's few
    # instructions of its own left it out of SLSQP's profile.
    callgrind_annotate --tree=calling --threshold=100 "$tmp/cg" >"$tmp/ann"
    # hp_plan's instructions (its own and its callees', inclusive) are the plan's; plan_once's
    # callees, grouped into phases, are most of them, and the rest (their own code, small
    # calls, keep_rate_bounds after the plan) is "other".
    awk -v cycles="$CYCLES" -v lv="${names[$level]}" -v bk="$backend" '
      /\*  .*:hp_plan \[/ { on = 1; self = $1; gsub(",", "", self); total += self; next }
      /\*  .*:plan_once \[/ { on = 2; next }
      on && /^ *$/ { on = 0 }
      on == 1 && />   / { ir = $1; gsub(",", "", ir); total += ir }
      on == 2 && />   / {
        ir = $1; gsub(",", "", ir)
        f = $0; sub(/.*>   [^:]*:/, "", f); sub(/ .*/, "", f)
        ph = f ~ /cycle_bounds_memo|^rate_bounds|^rate_settle|rate_touch/ ? "rate bounds" \
           : f ~ /recovered_from_nominal/ ? "round trip" \
           : f ~ /^rt_solve|^nlopt_solve/ ? "solver" \
           : f ~ /kkt_measure/ ? "KKT check" \
           : f ~ /answer_from_pose/ ? "answer" \
           : f ~ /contact_inside/ ? "direct chain" : ""
        if (ph != "") { s[ph] += ir; named += ir } }
      END {
        if (total == 0) { print "hp_plan not found in the profile" > "/dev/stderr"; exit 1 }
        s["other"] = total - named
        printf "%-8s %-12s %9d ", lv, bk, total / cycles
        n = split("rate bounds,round trip,solver,KKT check,answer,direct chain,other", o, ",")
        for (i = 1; i <= n; i++) if (s[o[i]] > 0) printf " %s %.0f%%", o[i], 100 * s[o[i]] / total
        printf "\n" }' "$tmp/ann"
  done
done
