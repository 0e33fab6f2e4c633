# headplan-bench-count's tail mode replays the loop benchmark's traces (bench/loop_trace.h),
# bench/loop_tail.sh counts its plans' instructions and bench/loop_profile.sh groups the
# loop mode's by phase. No timing: counts of plans on which
# a rate limit binds, which depend on the trace and the planners alone.
# Arguments: headplan-bench, headplan-bench-count, the source tree. Under the sanitizers
# (under_sanitizers, tests/cli_lib.sh) the valgrind parts are left out: valgrind cannot run
# a program the sanitizers instrument.
BENCH="$1"; COUNT="$2"
source "$3/tests/cli_lib.sh" "$COUNT" "$3"
SCENE="$HP_SRC/scenarios/default.yaml"

# The loop benchmark's quick run (120 cycles a trace): its rate and measured rows count the
# plans that bound a rate limit; the tail mode's rate-limited planner (FEED 0 its own
# answers, FEED 1 the readings) must count the same on the same trace, at every level.
"$BENCH" --quick --only loop --out "$TMP/loop" >"$TMP/out" 2>"$TMP/err"
rc=$?; expect_exit 0 "bench --quick --only loop"
levels=(linear plane surface)
for lv in 0 1 2; do
  for tr in smooth noisy step; do
    for feed in 0 1; do
      mode=$([ $feed -eq 0 ] && echo rate || echo measured)
      want=$(awk -F, -v l="${levels[$lv]}" -v t="$tr" -v m="$mode" '
        NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
        $1 == l && $2 == "realtime" && $3 == t && $4 == m { print $c["rate_binding"] }' "$TMP/loop/loop.csv")
      run "$SCENE" tail $lv $tr $feed 120
      expect_exit 0 "tail $lv $tr $feed"
      got=$(awk '$2 == 1 { s += $4 } END { print s + 0 }' "$TMP/out")
      lines=$(wc -l <"$TMP/out")
      [ -n "$want" ] && [ "$got" = "$want" ] && [ "$lines" -eq 240 ] && ok \
        || bad "tail $lv $tr $feed: $got plans bound a rate limit ($lines lines), loop.csv says '$want'"
    done
  done
done
# The bits mode replays the same traces (every level, trace and feed, in that order) and
# prints each answer whole: its statuses are the tail mode's, plan for plan.
run "$SCENE" bits 20
expect_exit 0 "bits 20"
cp "$TMP/out" "$TMP/bits"
[ "$(wc -l <"$TMP/bits")" -eq 720 ] && ok || bad "bits 20: $(wc -l <"$TMP/bits") lines, want 720"
run "$SCENE" tail 1 step 1 20
awk '{ print $1, $2, $3 }' "$TMP/out" >"$TMP/tail_st"
awk '$1 == "L1" && $2 == "T2" && $3 == "F1" { print $4, $5, $6 }' "$TMP/bits" >"$TMP/bits_st"
cmp -s "$TMP/tail_st" "$TMP/bits_st" && ok || bad "bits: level 1 step feed 1 statuses differ from the tail mode's"
for args in "0" "x" "-3"; do
  run "$SCENE" bits $args
  expect_exit 64 "bits $args"
done
# bench/plan_bits.sh: a build against itself is the same bits; a folder without the
# library is refused; two libraries whose answers differ in one plan are reported so.
if ! under_sanitizers; then
  libdir=$(dirname "$COUNT")
  bash "$HP_SRC/bench/plan_bits.sh" "$libdir" "$libdir" 20 >"$TMP/out" 2>"$TMP/err"
  rc=$?; expect_exit 0 "plan_bits.sh self"
  expect_stdout_has "plan_bits: 720 plans, the same bits" "plan_bits.sh self"
  bash "$HP_SRC/bench/plan_bits.sh" "$libdir" "$TMP" 20 >"$TMP/out" 2>"$TMP/err"
  rc=$?; expect_exit 66 "plan_bits.sh without a library"
  # Two libraries that differ: the same library loaded from a folder named shim, with an
  # hp_plan interposed (LD_PRELOAD, for both runs) that moves the first bladder's pressure
  # of the 100th plan by one ulp when the hp_plan it wraps was loaded from that folder.
  # plan_bits.sh must count one differing plan, name it and exit 1.
  mkdir "$TMP/shim"
  for f in "$libdir"/libheadplan.so*; do ln -s "$(cd "$libdir" && pwd)/$(basename "$f")" "$TMP/shim/"; done
  cat >"$TMP/perturb.c" <<'C'
#define _GNU_SOURCE
#include <dlfcn.h>
#include <math.h>
#include <string.h>
#include "headplan/headplan.h"
typedef hp_error (*plan_fn)(hp_planner *, const double *, hp_result *);
hp_error hp_plan(hp_planner *p, const double desired[6], hp_result *result)
{
    static plan_fn real;
    static long calls;
    if (!real) {
        void *sym = dlsym(RTLD_NEXT, "hp_plan");
        memcpy(&real, &sym, sizeof real);
    }
    hp_error e = real(p, desired, result);
    Dl_info in;
    void *addr;
    memcpy(&addr, &real, sizeof addr);
    if (++calls == 100 && dladdr(addr, &in) && strstr(in.dli_fname, "/shim/"))
        result->bladders[0].pressure = nextafter(result->bladders[0].pressure, INFINITY);
    return e;
}
C
  inc=(-I "$HP_SRC/include" -I "$libdir/include")
  cc -shared -fPIC -std=c11 "${inc[@]}" "$TMP/perturb.c" -o "$TMP/perturb.so" -ldl -lm 2>"$TMP/err" \
    && ok || bad "plan_bits.sh differ: the interposer did not compile: $(head -c 300 "$TMP/err")"
  LD_PRELOAD="$TMP/perturb.so" bash "$HP_SRC/bench/plan_bits.sh" "$libdir" "$TMP/shim" 20 \
    >"$TMP/out" 2>"$TMP/err"
  rc=$?; expect_exit 1 "plan_bits.sh differ"
  expect_stdout_has "plan_bits: 720 plans, 1 differ; the first: " "plan_bits.sh differ"
fi
# The tail mode's arguments are checked.
for args in "0 jump 0 10" "3 step 0 10" "0 step 2 10" "0 step 0 0" "x step 0 10" "0 step 1x 10"; do
  run "$SCENE" tail $args
  expect_exit 64 "tail $args"
done

# loop_tail.sh over 20 cycles: a row each planner, and with 20 plans the nearest-rank p99.9
# is the largest (rank ceil(19.98) = 20).
if ! under_sanitizers && command -v valgrind >/dev/null; then
  bash "$HP_SRC/bench/loop_tail.sh" "$COUNT" "$SCENE" 0 step 0 20 >"$TMP/out" 2>"$TMP/err"
  rc=$?; expect_exit 0 "loop_tail.sh"
  awk '$1 == "rate-free" || $1 == "rate-limited" { n++; if (!($4 == $5 && $2 > 0 && $3 >= $2)) bad_row = 1 }
       END { exit !(n == 2 && !bad_row) }' "$TMP/out" && ok || bad "loop_tail.sh rows"
  expect_stdout_has "the slowest 1 rate-limited plans, by function" "loop_tail.sh profile"
  # bench/loop_profile.sh over 10 plans: a row per level and backend whose phase shares add
  # up to the plan (100 % to their rounding), with the solver a named phase of each (a
  # grouping that misses the phases' functions puts everything under "other").
  bash "$HP_SRC/bench/loop_profile.sh" "$COUNT" "$SCENE" 10 >"$TMP/out" 2>"$TMP/err"
  rc=$?; expect_exit 0 "loop_profile.sh"
  awk '$1 == "plane" || $1 == "surface" {
         n++; sum = 0; solver = 0
         for (i = 4; i <= NF; i++) if ($i ~ /%$/) { v = $i; sub("%", "", v); sum += v
                                                    if ($(i - 1) == "solver") solver = v }
         if (!($3 > 0 && sum >= 97 && sum <= 103 && solver >= 10)) bad_row = 1 }
       END { exit !(n == 4 && !bad_row) }' "$TMP/out" && ok || bad "loop_profile.sh rows: $(cat "$TMP/out")"
  bash "$HP_SRC/bench/loop_profile.sh" "$COUNT" "$SCENE" 10 "1 3" >"$TMP/out" 2>"$TMP/err"
  rc=$?; expect_exit 64 "loop_profile.sh level 3"
  grep -q "level '3': must be 0, 1 or 2" "$TMP/err" && ok || bad "loop_profile.sh level 3: $(cat "$TMP/err")"
fi
finish
