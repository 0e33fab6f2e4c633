# headplan-bench-horizon (docs/horizon.md): the receding-horizon benchmark runs on a trace
# and prints one CSV line per horizon and prediction, and every refusal says why on one line
# with a non-zero status. Timing is printed, never checked. Skipped when the bench programs
# are not built (they sit beside headplan).
source "$2/tests/cli_lib.sh"
B="$(dirname "$HP_BIN")/headplan-bench-horizon"
[ -x "$B" ] || { echo "SKIP: $B not built"; exit 0; }
S="$HP_SRC/scenarios"
brun() { "$B" "$@" >"$TMP/out" 2>"$TMP/err"; rc=$?; }
expect_one_line_stderr() { [ "$(wc -l < "$TMP/err")" -eq 1 ] && ok || bad "$1: stderr is not one line"; }

# The docs' command on the first 20 rows of the step trace (the full trace only takes longer).
head -n 21 "$S/traces/step.csv" > "$TMP/step20.csv"
brun rh "$S/horizon/step.yaml" "$TMP/step20.csv"
expect_exit 0 "rh on the step trace"
expect_stdout_has "N,prediction,calls,median_us,p99_us,max_us,mean_iterations,max_iterations,calls_6_or_more,time_limited,cost" "rh header"
[ "$(grep -c ',20,' "$TMP/out")" -eq 21 ] && ok || bad "rh: want 21 lines of 20 calls"
grep -q '^64,velocity,20,' "$TMP/out" && ok || bad "rh: no line for N = 64, velocity"
grep -q '^10,periodic,20,' "$TMP/out" && ok || bad "rh: no line for N = 10, periodic"
# One horizon only (the profile's run): one line per prediction, N = 10.
brun rh "$S/horizon/step.yaml" "$TMP/step20.csv" 10
expect_exit 0 "rh with N"
[ "$(grep -c ',20,' "$TMP/out")" -eq 3 ] && ok || bad "rh 10: want 3 lines"
[ "$(grep -c '^10,' "$TMP/out")" -eq 3 ] && ok || bad "rh 10: every line for N = 10"
# The iterations are counted, not timed: within their bounds (at least one a call, at most
# rh_max_iter's default of 20, the mean between), and the same in a second run.
awk -F, 'NR > 1 && !($7 >= 1 && $7 <= $8 && $8 <= 20 && $9 >= 0 && $9 <= $3) { bad = 1 }
         END { exit bad }' "$TMP/out" && ok || bad "rh 10: iteration columns out of their bounds"
cut -d, -f1-3,7-9 "$TMP/out" > "$TMP/iters1"
brun rh "$S/horizon/step.yaml" "$TMP/step20.csv" 10
cut -d, -f1-3,7-9 "$TMP/out" | cmp -s - "$TMP/iters1" && ok || bad "rh 10: iterations differ between two runs"
# No budget stops a call (the scene's 10 s), and the cost is headplan horizon's for its
# receding plan of the same rows, to the last digit printed (the same planner calls, the same
# start pressures, start interval and tolerances), on 80 rows that hold the first step.
head -n 81 "$S/traces/step.csv" > "$TMP/step80.csv"
brun rh "$S/horizon/step.yaml" "$TMP/step80.csv" 10
expect_exit 0 "rh 10 on 80 rows"
cp "$TMP/out" "$TMP/rh80"
awk -F, 'NR > 1 && $10 != 0 { bad = 1 } END { exit bad }' "$TMP/rh80" && ok \
  || bad "rh 10: a call stopped by the scene's budget"
for pred in hold velocity periodic; do
  "$HP_BIN" horizon "$S/horizon/step.yaml" "$TMP/step80.csv" --rows deviation --mode receding \
    --prediction "$pred" --json > "$TMP/cli.json" 2>/dev/null
  want=$(sed -n 's/.*"cost": \([^,]*\),.*/\1/p' "$TMP/cli.json")
  got=$(awk -F, -v p="$pred" '$2 == p { print $11 }' "$TMP/rh80")
  awk -v a="$want" -v b="$got" 'BEGIN { d = a - b; if (d < 0) d = -d;
      exit !(a != "" && b != "" && a > 0 && d <= 1e-15 * a) }' && ok \
    || bad "rh 10 $pred: cost $got, headplan horizon says $want"
done
# --repeat: the counted columns and the cost are the first run's, the same as one run's.
brun rh "$S/horizon/step.yaml" "$TMP/step80.csv" 10 --repeat 3
expect_exit 0 "rh --repeat 3"
cut -d, -f1-3,7-11 "$TMP/out" | cmp -s - <(cut -d, -f1-3,7-11 "$TMP/rh80") && ok \
  || bad "rh --repeat 3: counted columns or cost differ from one run"
# A budget below the clock's resolution stops every call's solve before its first iteration,
# whatever the machine: every call is counted as stopped (the count is not timed).
brun rh "$S/horizon/step.yaml" "$TMP/step20.csv" 10 --max-time-us 1e-6
expect_exit 0 "rh --max-time-us 1e-6"
awk -F, 'NR > 1 && $10 != $3 { bad = 1 } END { exit bad || NR != 4 }' "$TMP/out" && ok \
  || bad "rh --max-time-us 1e-6: want every call stopped"

# Every refusal: one line on stderr, naming what is wrong, and a non-zero status.
for bad_opt in "--repeat 0" "--repeat 100" "--repeat two" "--max-time-us 0" "--max-time-us -5" \
               "--max-time-us nan" "--max-time-us inf" "--max-time-us 5us" "--repeat" \
               "--max-time-us" "--repeat 3 --repeat 3" "--max-time-us 9 --max-time-us 9" \
               "--bogus 1" "-r 3" "--max-time-us 1e300" "--max-time-us 4e9"; do
  # shellcheck disable=SC2086 # the option and its value are two words
  brun rh "$S/horizon/step.yaml" "$TMP/step20.csv" 10 $bad_opt
  expect_exit 64 "rh $bad_opt"
  expect_one_line_stderr "rh $bad_opt"
  [ -s "$TMP/out" ] && bad "rh $bad_opt: wrote to stdout" || ok
done
brun rh "$S/horizon/step.yaml" "$TMP/step20.csv" 10 --repeat 2 --repeat 3
expect_stderr_has "--repeat: given more than once" "repeated option named"
brun rh "$S/horizon/step.yaml" "$TMP/step20.csv" 10 --max-time-us nan
expect_stderr_has "--max-time-us 'nan'" "bad budget named"
brun rh "$S/horizon/step.yaml" "$TMP/step20.csv" 10 --bogus 1
expect_stderr_has "unknown option '--bogus'" "unknown option named"
brun rh "$S/horizon/step.yaml" "$TMP/step20.csv" 10 --max-time-us 1e300
expect_stderr_has "--max-time-us '1e300': max_time:" "budget beyond the settings' range named"
brun rh "$S/horizon/step.yaml" "$TMP/step20.csv" 10 --repeat " 3"
expect_exit 64 "a value with a leading space"; expect_stderr_has "--repeat ' 3'" "spaced value named"
brun rh "$S/horizon/step.yaml" "$TMP/step20.csv" 10 -r 3
expect_stderr_has "unknown option '-r'" "short option named"
# A trace the horizon planners refuse is refused before anything is printed: a repeated time
# stamp, a desired pose outside the identifiable range (each named with its line).
printf 't_s,x_mm,y_mm,z_mm,pitch_deg,roll_deg,yaw_deg\n0,0,0,0,0,0,0\n0,0,0,0,0,0,0\n' \
  > "$TMP/same_t.csv"
brun rh "$S/horizon/step.yaml" "$TMP/same_t.csv" 10
expect_exit 65 "repeated time stamp"; expect_stderr_has "line 3: t_s" "repeated time stamp named"
expect_one_line_stderr "repeated time stamp"
[ -s "$TMP/out" ] && bad "repeated time stamp: wrote to stdout" || ok
printf 't_s,x_mm,y_mm,z_mm,pitch_deg,roll_deg,yaw_deg\n0,0,0,0,0,0,0\n0.1,500,0,0,0,0,0\n' \
  > "$TMP/far.csv"
brun rh "$S/horizon/step.yaml" "$TMP/far.csv" 10
expect_exit 65 "unreachable row"; expect_stderr_has "far.csv: line 3: desired translation" "row named"
expect_one_line_stderr "unreachable row"
[ -s "$TMP/out" ] && bad "unreachable row: wrote to stdout" || ok
brun rh "$S/horizon/step.yaml" "$TMP/step20.csv" --repeat 3 10
expect_exit 64 "rh N after an option"; expect_one_line_stderr "rh N after an option"
brun windows "$S/horizon/step.yaml" "$TMP/step20.csv" 10 2 --repeat 3
expect_exit 64 "windows with --repeat"; expect_stderr_has "usage:" "windows takes no option"
brun
expect_exit 64 "no arguments"; expect_stderr_has "usage: headplan-bench-horizon rh" "usage"
brun sideways "$S/horizon/step.yaml" "$TMP/step20.csv"
expect_exit 64 "unknown mode"; expect_stderr_has "unknown mode 'sideways'" "unknown mode"
brun windows "$S/horizon/step.yaml" "$TMP/step20.csv" 10
expect_exit 64 "windows without OVERLAP"; expect_stderr_has "usage:" "windows usage"
brun windows "$S/horizon/step.yaml" "$TMP/step20.csv" ten 2
expect_exit 64 "WINDOW not a number"; expect_stderr_has "WINDOW 'ten'" "WINDOW named"
expect_one_line_stderr "WINDOW not a number"
brun windows "$S/horizon/step.yaml" "$TMP/step20.csv" 10 -1
expect_exit 64 "negative OVERLAP"; expect_stderr_has "OVERLAP '-1'" "OVERLAP named"
brun rh "$S/horizon/step.yaml" "$TMP/step20.csv" 0
expect_exit 64 "N = 0"; expect_stderr_has "N '0'" "N named"
expect_one_line_stderr "N = 0"
brun rh "$S/horizon/step.yaml" "$TMP/step20.csv" 65
expect_exit 65 "N beyond the largest horizon"; expect_stderr_has "horizon: must be in 1..64" "N range"
expect_one_line_stderr "N beyond the largest horizon"
brun rh "$TMP/missing.yaml" "$TMP/step20.csv"
expect_exit 66 "missing scene"; expect_stderr_has "missing.yaml" "missing scene named"
expect_one_line_stderr "missing scene"
brun rh "$S/horizon/step.yaml" "$TMP/missing.csv"
expect_exit 66 "missing trace"; expect_stderr_has "missing.csv" "missing trace named"
head -n 2 "$S/traces/step.csv" > "$TMP/one_row.csv"
brun rh "$S/horizon/step.yaml" "$TMP/one_row.csv"
expect_exit 65 "one-row trace"; expect_stderr_has "one_row.csv: 1 row" "short trace named"
expect_one_line_stderr "one-row trace"
printf 't_s,x_mm,y_mm,z_mm,pitch_deg,roll_deg,yaw_deg\n0,0,0,0,0,0,0\n0.1,zero,0,0,0,0,0\n' \
  > "$TMP/bad_row.csv"
brun rh "$S/horizon/step.yaml" "$TMP/bad_row.csv"
expect_exit 65 "bad row"; expect_stderr_has "bad_row.csv:3" "bad row located"
finish
