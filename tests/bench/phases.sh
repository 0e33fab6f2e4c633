# headplan-bench-phases (bench/loop_phases.c): the loop benchmark's slowest plans by phase.
# No timing: the calls each phase made in the plans listed (which plans are the slowest is the
# host's), and the refusals. Arguments: headplan-bench-phases, the source tree.
source "$2/tests/cli_lib.sh" "$1" "$2"
SCENE="$HP_SRC/scenarios/default.yaml"

# The step trace's first 600 cycles (two jumps), three repeats, the five slowest plans of
# each planner and its median one: 3 × 6 rows after the header lines.
run "$SCENE" 0 step 600 3 5
expect_exit 0 "phases 0 step 600 3 5"
[ "$(awk '($1 == "free" || $1 == "rate" || $1 == "measured") && $2 != "calls"' "$TMP/out" | wc -l)" -eq 18 ] \
  && ok || bad "phases: 18 planner rows"
# Columns: planner rank cycle total resolve n qp n answer n setup n other. The rate-free
# planner resolves no window end and runs no lazy QP; every plan takes one answer.
awk '$1 == "free" && $2 != "calls" && ($6 != 0 || $8 != 0 || $10 != 1) { bad = 1 } END { exit bad }' "$TMP/out" \
  && ok || bad "phases: the free planner resolved an end or ran a lazy QP"
# A plan sets up stand-ins at most once.
awk '($1 == "rate" || $1 == "measured") && $2 != "calls" && $12 > 1 { bad = 1 } END { exit bad }' \
  "$TMP/out" && ok || bad "phases: a plan set up stand-ins twice"
# Over the trace (calls: resolve R qp Q answer A setup S): the rate-free planner resolves no end
# and runs no lazy QP; the rate-limited ones resolve ends (after the jumps) and run lazy QPs;
# every plan of every planner takes one answer. The timers are live: a wrap that missed its
# call would count none.
awk '$2 == "calls" && $1 == "free" && !($4 == 0 && $6 == 0 && $8 == 600) { bad = 1 }
     $2 == "calls" && $1 != "free" && !($4 > 0 && $6 > 0 && $8 == 600) { bad = 1 }
     $2 == "calls" { n++ } END { exit bad || n != 3 }' "$TMP/out" \
  && ok || bad "phases: the calls over the trace"
# Refusals: one line naming the argument, exit 64; a scene that cannot be read, 66.
run "$SCENE" 3 step 600 3 5; expect_exit 64 "level 3"; expect_stderr_has "LEVEL" "names LEVEL"
run "$SCENE" 0 stairs 600 3 5; expect_exit 64 "trace stairs"; expect_stderr_has "TRACE" "names TRACE"
run "$SCENE" 0 step 0 3 5; expect_exit 64 "cycles 0"; expect_stderr_has "CYCLES" "names CYCLES"
run "$SCENE" 0 step 600 51 5; expect_exit 64 "repeats 51"; expect_stderr_has "REPEATS" "names REPEATS"
run "$SCENE" 0 step 600 3 x; expect_exit 64 "top x"; expect_stderr_has "TOP" "names TOP"
run "$SCENE" 0 step; expect_exit 64 "too few arguments"; expect_stderr_has "usage" "usage"
run "$TMP/none.yaml" 0 step 600 3 5; expect_exit 66 "missing scene"
finish
