# headplan-bench (the benchmark lab): the IK family's CSV, accuracy relations and charts (no timing assertions:
# times depend on the machine; accuracies do not).
source "$2/tests/cli_lib.sh"

OUT="$TMP/bench out"   # a space in the folder name: gnuplot runs without a shell
# whole_family NAME: true unless under the sanitizers, where the families that take minutes
# there (stability, peers, levels, fidelity: half an hour of CI's sanitizer pass) are left
# to the plain pass, which checks every family; the lab's shared code (catalogue, CSV,
# charts, options) runs under them in the families kept, and the load family in
# tests/cli/hostile_names.sh.
whole_family() {
  if under_sanitizers; then echo "note: the $1 family is checked in the plain build only"; return 1; fi
}
run --quick --only ik --out "$OUT" --seed 7
expect_exit 0 "bench --quick"
expect_stdout_has "median_ns" "summary table header"
expect_stdout_has "closed" "summary names the closed form"
expect_stderr_has "bench ik: [ 1/34] closed" "progress on stderr"
csv="$OUT/ik.csv"

want_header="method,family,variant,parameter,input_set,median_ns,p99_ns,max_error,worst_input,max_violation,model_error,failures,inputs,samples,batch,ratio_to_baseline,pareto,round_ratio,round_ns"
[ -f "$csv" ] && [ "$(head -n 1 "$csv")" = "$want_header" ] && ok || bad "ik.csv header"

# One row per method: closed form (value, with derivatives), Gauss-Legendre orders
# 2..64 and adaptive tolerances 1e-4..1e-13, each on both integral forms.
methods="closed closed-derivs"
for f in cur ref; do
  for n in 2 4 8 16 32 64; do methods="$methods gl-$f-$n"; done
  for e in 04 05 06 07 08 09 10 11 12 13; do methods="$methods aq-$f-1e-$e"; done
done
for m in $methods; do
  [ "$(awk -F, -v m="$m" 'NR > 1 && $1 == m' "$csv" | wc -l)" -eq 1 ] && ok || bad "row for $m"
done
[ "$(($(wc -l <"$csv") - 1))" -eq 34 ] && ok || bad "34 rows"

# field METHOD COLUMN_NAME: the value of a named column in a method's row.
field() {
  awk -F, -v m="$1" -v name="$2" 'NR == 1 { for (i = 1; i <= NF; i++) if ($i == name) c = i }
                                  NR > 1 && $1 == m && c { print $c }' "$csv"
}
# Every row: positive times with p99 >= median, a measured error, no failures, 1000 inputs.
bad_rows=$(awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
  !($c["median_ns"] > 0 && $c["p99_ns"] >= $c["median_ns"] && $c["max_error"] != "" &&
    $c["failures"] == 0 && $c["inputs"] == 1000) { print $1 }' "$csv")
[ -z "$bad_rows" ] && ok || bad "rows with missing values: $bad_rows"

# The closed form is within 1e-14 relative of the __float128 reference everywhere
# (docs/accuracy.md measures 8.8 ulps = 2e-15 worst over a wider sweep).
awk -v e="$(field closed max_error)" 'BEGIN { exit !(e != "" && e <= 1e-14) }' && ok || bad "closed max_error $(field closed max_error) > 1e-14"
awk -v e="$(field closed-derivs max_error)" 'BEGIN { exit !(e != "" && e <= 1e-14) }' && ok || bad "closed-derivs max_error"
# The ratio column divides by the closed form's own median: 1 on its own row.
[ "$(field closed ratio_to_baseline)" = "1" ] && ok || bad "closed ratio_to_baseline $(field closed ratio_to_baseline)"
# The IK methods are timed each in its own window (not in rounds): no per-round columns.
[ -z "$(field closed round_ratio)$(field closed round_ns)" ] && ok || bad "ik rows carry rounds"

# Quadrature converges: 2 points are far worse than 64 on both forms (2 points: ~0.25 and
# ~0.5 relative; 64 points: rounding level), and a tight adaptive tolerance beats a loose one.
for f in cur ref; do
  awk -v a="$(field gl-$f-2 max_error)" -v b="$(field gl-$f-64 max_error)" 'BEGIN { exit !(a > 1e-3 && b < 1e-12 && a > b) }' \
    && ok || bad "gl-$f-2 ($(field gl-$f-2 max_error)) not worse than gl-$f-64 ($(field gl-$f-64 max_error))"
  awk -v a="$(field aq-$f-1e-04 max_error)" -v b="$(field aq-$f-1e-13 max_error)" 'BEGIN { exit !(a > b && b < 1e-12) }' \
    && ok || bad "aq-$f-1e-04 not worse than aq-$f-1e-13"
done
# The closed form is at least as accurate as every other IK method (an accuracy relation
# only: whether it is on the time/error Pareto front depends on the clock, and two methods
# tie on accuracy, so the front is not asserted: a busy machine may reorder the times).
worse=$(awk -F, -v e="$(field closed max_error)" 'NR > 1 && $2 == "ik" && $8 + 0 < e + 0 { print $1 }' "$csv")
[ -z "$worse" ] && ok || bad "more accurate than the closed form: $worse"

# Charts: PNG (magic bytes \x89PNG) and SVG, non-empty; the script is kept beside them.
png="$OUT/ik_pareto.png"; svg="$OUT/ik_pareto.svg"
[ -s "$png" ] && [ "$(head -c 4 "$png" | od -An -tx1 | tr -d ' \n')" = "89504e47" ] && ok || bad "ik_pareto.png"
[ -s "$svg" ] && grep -q "<svg" "$svg" && ok || bad "ik_pareto.svg"
[ -s "$OUT/ik_pareto.gp" ] && ok || bad "ik_pareto.gp kept"
[ -z "$(ls "$OUT" | grep '\.tmp$')" ] && ok || bad "temporary files left behind"

# The planner family (quick: 4 targets per group, a 40-row trace): a row per method, the baseline's ratio 1,
# and no returned pressure or stretch outside its limits (the planner's promise: 0 exactly).
run --quick --only planner --out "$OUT" --scene "$HP_SRC/scenarios/default.yaml"
expect_exit 0 "bench --only planner"
csv="$OUT/planner.csv"
[ "$(($(wc -l <"$csv") - 1))" -eq 36 ] && ok || bad "planner: 36 rows"
# What restarts cost: Ipopt and SLSQP with restarts 0 beside the default, binding and
# reachable, every plan answered; the docs' table (regen_docs.py restarts_cost) reads them.
for b in ipopt nlopt-slsqp; do
  for m in "$b-surface-1e-09-r0 binding" "$b-surface-1e-09-reach reachable" \
           "$b-surface-1e-09-reach-r0 reachable"; do
    read -r name set <<<"$m"
    [ "$(field "$name" input_set)" = "$set" ] && [ "$(field "$name" failures)" = 0 ] \
      && ok || bad "planner: $name row ($set, no failure)"
  done
done
PYTHONPATH="$HP_SRC/scripts" /usr/bin/python3 -c \
  "import sys, regen_docs; t = regen_docs.restarts_cost(sys.argv[1]); assert t.count('\n| ') == 5, t" \
  "$OUT" && ok || bad "planner: regen_docs.restarts_cost reads the rows"
# The warm-trace rows walk the trace in order: every row answered, none failed.
for lv in linear plane surface; do
  [ "$(field trace-realtime-$lv input_set)" = trace ] && [ "$(field trace-realtime-$lv failures)" = 0 ] \
    && ok || bad "planner: trace-realtime-$lv row"
done
[ "$(field ipopt-surface-1e-09 ratio_to_baseline)" = "1" ] && ok || bad "planner baseline ratio"
# All planner methods are timed together in 7 rounds: every row carries 7 positive round
# medians, and the baseline's median per-round ratio to itself is 1.
badr=$(awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
  { k = split($c["round_ns"], v, ";"); okr = (k == 7); for (j = 1; j <= k; j++) if (!(v[j] > 0)) okr = 0
    if (!okr || !($c["round_ratio"] > 0)) print $1 }' "$csv")
[ -z "$badr" ] && ok || bad "planner: rows without 7 timed rounds: $badr"
[ "$(field ipopt-surface-1e-09 round_ratio)" = "1" ] && ok || bad "planner baseline round ratio"
viol=$(awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
  $c["max_violation"] != 0 { print $1 "=" $c["max_violation"] }' "$csv")
[ -z "$viol" ] && ok || bad "planner: limit violations: $viol"
# The fast path at the surface level is the exact chain: its round trip returns the
# reference pose to well below a micrometre (LM in contact FK stops at ~1e-14 m).
awk -v e="$(field fastpath-surface max_error)" 'BEGIN { exit !(e != "" && e < 1e-6) }' \
  && ok || bad "fastpath-surface max_error $(field fastpath-surface max_error)"
[ -s "$OUT/planner_pareto.png" ] && [ -s "$OUT/planner_pareto.svg" ] && ok || bad "planner charts"
run --quick --only planner --out "$OUT" --scene "$TMP/missing.yaml"
expect_exit 66 "--scene missing"; expect_stderr_has "missing.yaml" "names the scene"

# col FILE COLUMN_NAME: prints the 1-based index of a named column of a CSV header.
col() { head -n 1 "$1" | tr ',' '\n' | grep -nx -- "$2" | cut -d: -f1; }

if whole_family stability; then
# The stability family (quick: 2 directions x 6 sizes per case): 4 cases x 12 methods x 6
# sizes; every plan is accounted for, nothing leaves a pressure or stretch limit, every
# failure carries a status, and trivial corrections always succeed.
run --quick --only stability --out "$OUT" --scenarios "$HP_SRC/scenarios"
expect_exit 0 "bench --only stability"
expect_stdout_has "silent wrong answers:" "stability summary"
csv="$OUT/stability.csv"
[ "$(($(wc -l <"$csv") - 1))" -eq 288 ] && ok || bad "stability: 288 rows ($(($(wc -l <"$csv") - 1)))"
badrows=$(awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
  !($c["reached"] + $c["closest"] + $c["failures"] == $c["targets"] &&
    $c["verified"] + $c["unverified"] + $c["wrong"] == $c["reached"] + $c["closest"] &&
    $c["targets"] == 2 && $c["max_limit_violation"] == 0 &&
    ($c["failures"] == 0 || $c["failure_statuses"] != "") &&
    $c["success_rate"] >= 0 && $c["success_rate"] <= 1) { print $1 "/" $2 "/" $5 }' "$csv")
[ -z "$badrows" ] && ok || bad "stability: inconsistent rows: $badrows"
# 0.01 mm/deg is reachable by the direct chain on every layout: all verified, 0 iterations.
small=$(awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
  $c["size"] == 0.01 && !($c["verified"] == 2 && $c["max_iterations"] == 0) { print $1 "/" $2 }' "$csv")
[ -z "$small" ] && ok || bad "stability: size 0.01 not all verified: $small"
# Every method of every case has a row at each of the 6 sizes.
[ "$(awk -F, 'NR > 1 { print $1 "/" $2 }' "$csv" | sort | uniq -c | awk '$1 != 6' | wc -l)" -eq 0 ] \
  && ok || bad "stability: a method lacks sizes"
# Every silent wrong answer counted in the CSV is listed in stability_wrong.csv.
wrong_sum=$(awk -F, -v w="$(col "$csv" wrong)" 'NR > 1 { s += $w } END { print s + 0 }' "$csv")
listed=$(awk -F, 'NR > 1 && $7 != "ipopt-worse"' "$OUT/stability_wrong.csv" | wc -l)
[ "$wrong_sum" -eq "$listed" ] && ok || bad "stability: $wrong_sum wrong answers counted, $listed listed"
[ -s "$OUT/stability.png" ] && [ "$(head -c 4 "$OUT/stability.png" | od -An -tx1 | tr -d ' \n')" = "89504e47" ] \
  && grep -q "<svg" "$OUT/stability.svg" && [ -s "$OUT/stability.gp" ] && ok || bad "stability charts"
fi
run --quick --only stability --out "$OUT" --scenarios "$TMP/nowhere"
expect_exit 66 "--scenarios missing"; expect_stderr_has "nowhere" "names the catalogue"
# Checked before the output folder is made: a refused catalogue leaves no folder behind, and
# an empty name is refused as one (not as a file that cannot be opened).
run --quick --only levels --out "$TMP/nofolder" --scenarios "$TMP/nowhere"
expect_exit 66 "--scenarios missing (levels)"; expect_stderr_has "--scenarios: cannot open folder" "names --scenarios"
[ ! -e "$TMP/nofolder" ] && ok || bad "a refused catalogue left the output folder"
for o in --scenarios --scene --python --peer-script --out; do
  run --quick --only fidelity "$o="
  expect_exit 64 "$o empty"; expect_stderr_has "$o: empty name" "names $o"
done

if whole_family peers; then
# The peers family: the baseline (Ipopt, exact Hessian) has ratio 1; every method solves the
# same NLP to the same answer. Ipopt limited-memory stops at tolerance 1e-9, so its answer is
# within 1e-6 mm/deg of the 1e-10 reference; SciPy's SLSQP (ftol 1e-12 on an objective in
# mm^2) within 1e-3 (measured 2e-7 analytic, 8e-7 with finite differences).
run --quick --only peers --out "$OUT" --scene "$HP_SRC/scenarios/default.yaml" \
  --peer-script "$HP_SRC/bench/scipy_peer.py"
expect_exit 0 "bench --only peers"
csv="$OUT/peers.csv"
[ "$(($(wc -l <"$csv") - 1))" -eq 8 ] && ok || bad "peers: 8 rows"
[ "$(field ipopt-exact-linear ratio_to_baseline)" = "1" ] && ok || bad "peers baseline ratio"
# headplan's methods are timed together in rounds (7 round medians each); SciPy, timed in its
# own process, has none, so no per-round ratio.
[ "$(field ipopt-exact-linear round_ratio)" = "1" ] && ok || bad "peers baseline round ratio"
for m in ipopt-lbfgs-linear realtime-linear nlopt-slsqp-linear ipopt-exact-surface ipopt-lbfgs-surface; do
  [ "$(field $m round_ns | tr ';' '\n' | wc -l)" -eq 7 ] && ok || bad "peers: $m rounds"
done
[ -z "$(field scipy-slsqp round_ns)$(field scipy-slsqp round_ratio)" ] && ok || bad "peers: scipy has rounds"
for m in ipopt-exact-linear ipopt-lbfgs-linear realtime-linear ipopt-exact-surface ipopt-lbfgs-surface; do
  awk -v e="$(field $m max_error)" -v f="$(field $m failures)" 'BEGIN { exit !(e != "" && e < 1e-6 && f == 0) }' \
    && ok || bad "peers: $m max_error $(field $m max_error) failures $(field $m failures)"
done
for m in scipy-slsqp scipy-slsqp-fd; do
  awk -v e="$(field $m max_error)" -v f="$(field $m failures)" 'BEGIN { exit !(e != "" && e < 1e-3 && f == 0) }' \
    && ok || bad "peers: $m max_error $(field $m max_error) failures $(field $m failures)"
done
[ -s "$OUT/peers_pareto.png" ] && [ -s "$OUT/peers_problem.json" ] && ok || bad "peers files"
fi
# SciPy missing: status 70 naming --python, before anything is measured.
run --quick --only peers --out "$TMP/nopy" --python /nonexistent/python3 \
  --scene "$HP_SRC/scenarios/default.yaml" --peer-script "$HP_SRC/bench/scipy_peer.py"
expect_exit 70 "--python missing"; expect_stderr_has "--python" "names --python"
[ ! -e "$TMP/nopy" ] && ok || bad "output folder created although SciPy is missing"

if whole_family levels; then
# The levels family: one row per level for each of the 11 layout scenes (the 4 load scenes
# are planned at the kinematic levels here: the load family below times the load level); auto picks the
# cheapest level whose error bound meets the scene's tolerance; the surface level is the
# reference (bound 0, error 0).
run --quick --only levels --out "$OUT" --scenarios "$HP_SRC/scenarios"
expect_exit 0 "bench --only levels"
csv="$OUT/levels.csv"
[ "$(($(wc -l <"$csv") - 1))" -eq 33 ] && ok || bad "levels: 33 rows"
badlv=$(awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
  { s = $c["scene"]; b[s, $c["level"]] = $c["bound_mm"]; tol[s] = $c["tolerance_mm"]; a[s] = $c["auto_level"]
    if ($c["level"] == "surface" && !($c["bound_mm"] == 0 && $c["max_error"] == 0)) print s ": surface not exact" }
  END { for (s in a) {
      want = (b[s, "linear"] <= tol[s]) ? "linear" : (b[s, "plane"] <= tol[s]) ? "plane" : "surface"
      if (a[s] != want) print s ": auto " a[s] ", want " want } }' "$csv")
[ -z "$badlv" ] && ok || bad "levels: $badlv"
[ "$(awk -F, '$1 == "sphere_head" && $9 == 1 { print $8 }' "$csv")" = "linear" ] && ok || bad "levels: sphere_head auto"
[ "$(awk -F, '$1 == "large_rotation" && $9 == 1 { print $8 }' "$csv")" = "surface" ] && ok || bad "levels: large_rotation auto"
fi

# The load family: the 4 load scenes × 3 backends; load_prone is refused at create on every
# backend, the supine scene is reached, load_tilted is closest (the chin bladders at the
# indentation range, indent_max), load_heavy is closest (its closest held pose is a saddle:
# the stable hold found lower, docs/load.md "Stable holds"); the kinematic
# plan's sag is unbounded on all four (its bladders touch with zero force); the chart.
run --quick --only load --out "$OUT" --scenarios "$HP_SRC/scenarios"
expect_exit 0 "bench --only load"
csv="$OUT/load.csv"
[ "$(head -n 1 "$csv")" = "scene,kinematic_median_ns,kinematic_sag_mm,backend,load_status,load_median_ns" ] \
  && ok || bad "load.csv header"
[ "$(($(wc -l <"$csv") - 1))" -eq 12 ] && ok || bad "load: 12 rows"
badld=$(awk -F, 'NR > 1 { want = $1 == "load_prone" ? "refused" : $1 == "load_heavy" || $1 == "load_tilted" ? "closest" : "reached"
                 if ($5 != want) print $1 "/" $4 ": " $5 ", want " want
                 if ($3 != "inf") print $1 ": sag " $3 }' "$csv")
[ -z "$badld" ] && ok || bad "load: $badld"
[ "$(head -c 4 "$OUT/load.png" | od -An -tx1 | tr -d ' \n')" = "89504e47" ] \
  && grep -q "<svg" "$OUT/load.svg" && [ -s "$OUT/load.gp" ] && ok || bad "load charts"

# Command-line errors: one line on stderr naming the option, usage status, no stdout.
# The loop family (quick: 120 cycles a trace): 72 rows (3 levels x 2 backends x 3 traces x
# 4 modes), every free row's ratio 1, no call returned an error (hp_plan, set_measured), every
# plan counted once, and without a deadline no plan held (every status reached or closest);
# the deadline rows count their overshoots beyond 100 us apart too (a count, not judged).
# With a deadline the outcomes depend on where the host's clock stopped each plan (a time-
# limited answer is the next plan's start), so those rows are only counted, never judged: no
# assertion here depends on time.
run --quick --only loop --out "$OUT" --scene "$HP_SRC/scenarios/default.yaml"
expect_exit 0 "bench --only loop"
lcsv="$OUT/loop.csv"
[ "$(($(wc -l <"$lcsv") - 1))" -eq 72 ] && ok || bad "loop: 72 rows"
badl=$(awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
  { id = $1 "/" $2 "/" $3 "/" $4
    if ($c["errors"] != 0) print id ": errors " $c["errors"]
    if ($c["reached"] + $c["closest"] + $c["time_limit"] + $c["other"] != $c["cycles"]) print id ": statuses"
    if ($4 != "deadline" && $c["other"] + $c["time_limit"] != 0) print id ": held without a deadline"
    if ($4 == "free" && ($c["ratio_median"] != 1 || $c["rate_binding"] != 0)) print id ": free row"
    if (!($c["median_us"] > 0)) print id ": median"
    if (!("overshoots_host" in c)) { print "no column overshoots_host"; exit }
    if ($4 == "deadline" && !($c["overshoots_host"] >= 0 && $c["overshoots_host"] <= $c["cycles"]))
      print id ": overshoots_host " $c["overshoots_host"]
    if ($c["overshoots_host"] > $c["overshoots"]) print id ": host overshoots beyond overshoots" }' "$lcsv")
[ -z "$badl" ] && ok || bad "loop: $badl"
# The docs' loop tables (regen_docs.py loop_table, loop_headline) read the rows: 18 rows
# (levels x backends x traces) and a headline row for each level.
PYTHONPATH="$HP_SRC/scripts" /usr/bin/python3 -c \
  "import sys, regen_docs as r; t = r.loop_table(sys.argv[1]); h = r.loop_headline(sys.argv[1])
assert t.count(' of 120') == 18, t
assert [l.split()[0] for l in h.splitlines()[3:-1]] == ['linear', 'plane', 'surface'], h" \
  "$OUT" && ok || bad "loop: regen_docs.loop_table / loop_headline read the rows"
# The step trace makes the rate limits bind (500 Pa a plan against steps of kPa).
awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
  $3 == "step" && $4 == "rate" && $c["rate_binding"] > 0 { n++ } END { exit !(n == 6) }' "$lcsv" \
  && ok || bad "loop: rate limits never bind on the step trace"
# The rate limits' window ends, counted: none without rate limits; solved on the step trace
# (its targets jump beyond the rate) and found among the slowest plans there.
awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
  $4 == "free" && $c["ends_per_1000"] != 0 { bad = 1 }
  $2 == "realtime" && $3 == "step" && $4 == "rate" && !($c["ends_per_1000"] > 0 && $c["evals_per_end"] >= 1) { bad = 1 }
  END { exit bad }' "$lcsv" && ok || bad "loop: ends_per_1000 / evals_per_end"
# --repeat pools the cycles of N runs of each trace; from three runs on, each cycle's median
# time over the runs gives the plans' own p99.9 (p999_cycle_median_us), the deadline
# planner's too but without a ratio (its runs differ where the clock stopped them): a cycle's
# median lies within the pooled times, and the free row is its own baseline. Without three
# runs it is not formed.
run --quick --only loop --repeat 3 --out "$TMP/rep" --scene "$HP_SRC/scenarios/default.yaml"
expect_exit 0 "bench --only loop --repeat 3"
awk -F, 'NR > 1 && $5 != 360 { bad = 1 } END { exit bad }' "$TMP/rep/loop.csv" && ok || bad "loop --repeat 3: 360 cycles a row"
badc=$(awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
  { id = $1 "/" $2 "/" $3 "/" $4; v = $c["p999_cycle_median_us"]; x = $c["ratio_p999_cycle_median"]
    if ($4 == "deadline" && x != "nan") print id ": a ratio under a deadline"
    if (!(v > 0 && v <= $c["max_us"] + 0.0005)) print id ": p999_cycle_median_us " v " beyond (0, max]"
    if ($4 == "free" && x != 1) print id ": free ratio " x }' "$TMP/rep/loop.csv")
[ -z "$badc" ] && ok || bad "loop --repeat 3: $badc"
awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
  $c["p999_cycle_median_us"] != "nan" { bad = 1 } END { exit bad }' "$lcsv" \
  && ok || bad "loop without --repeat 3: p999_cycle_median_us formed from one run"
run --repeat 0 --out "$TMP/x"
expect_exit 64 "--repeat 0"; expect_stderr_has "--repeat" "names --repeat"
# --repeat repeats the loop family's traces only: with no loop family asked for it would be
# ignored, so it is refused before any measuring.
run --quick --only ik --repeat 3 --out "$TMP/x"
expect_exit 64 "--repeat without the loop family"; expect_stderr_has "--repeat" "names --repeat"
# --loop-level and --loop-backend keep the loop family to one level and backend (so that two
# builds can take many quick turns): only those rows, all of them; a name the family does not
# run, or either option without the loop family, is refused before any measuring.
run --quick --only loop --loop-level linear --loop-backend realtime --out "$TMP/lone" \
  --scene "$HP_SRC/scenarios/default.yaml"
expect_exit 0 "bench --only loop --loop-level linear --loop-backend realtime"
awk -F, 'NR > 1 { n++; if ($1 != "linear" || $2 != "realtime") bad = 1 } END { exit bad || n != 12 }' \
  "$TMP/lone/loop.csv" && ok || bad "loop --loop-level linear --loop-backend realtime: 12 linear realtime rows"
run --quick --only loop --loop-level load --out "$TMP/x"
expect_exit 64 "--loop-level load"; expect_stderr_has "--loop-level" "names --loop-level"
run --quick --only loop --loop-backend ipopt --out "$TMP/x"
expect_exit 64 "--loop-backend ipopt"; expect_stderr_has "--loop-backend" "names --loop-backend"
run --quick --only ik --loop-level plane --out "$TMP/x"
expect_exit 64 "--loop-level without the loop family"; expect_stderr_has "--loop-level" "names --loop-level"
# --loop-budget-us sets the deadline planner's budget (its rows' budget_us column says so); a
# value that is not a number of microseconds > 0 and at most 1e6, or the option without the
# loop family, is refused before any measuring.
run --quick --only loop --loop-level linear --loop-backend realtime --loop-budget-us 3 \
  --out "$TMP/lbud" --scene "$HP_SRC/scenarios/default.yaml"
expect_exit 0 "bench --only loop --loop-budget-us 3"
awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) if ($i == "budget_us") c = i }
         NR > 1 && $4 == "deadline" { n++; if ($c != 3) bad = 1 } END { exit bad || n != 3 }' \
  "$TMP/lbud/loop.csv" && ok || bad "loop --loop-budget-us 3: the deadline rows' budget_us"
for v in 0 -2 nan inf 2e6 3us "" 4e-324; do
  run --quick --only loop --loop-budget-us "$v" --out "$TMP/x"
  expect_exit 64 "--loop-budget-us '$v'"; expect_stderr_has "--loop-budget-us" "names --loop-budget-us ($v)"
  expect_stdout_empty "--loop-budget-us '$v'"
done
run --quick --only ik --loop-budget-us 3 --out "$TMP/x"
expect_exit 64 "--loop-budget-us without the loop family"
expect_stderr_has "--loop-budget-us: only the loop family" "names --loop-budget-us"
run --only nonsense --out "$TMP/x"
expect_exit 64 "--only nonsense"; expect_stderr_has "--only" "names --only"; expect_stdout_empty "--only nonsense"
run --seed -3 --out "$TMP/x"
expect_exit 64 "--seed -3"; expect_stderr_has "--seed" "names --seed"
run --frobnicate
expect_exit 64 "unknown option"; expect_stderr_has "--frobnicate" "names the option"
run --out
expect_exit 64 "--out without value"
# An option given twice is refused (one of its values would be dropped without a word), before
# any measuring: a flag, an option with a value, and the loop family's own.
run --quick --quick --only ik --out "$TMP/x"
expect_exit 64 "--quick twice"; expect_stderr_has "--quick: given more than once" "names --quick"
run --quick --only ik --only loop --out "$TMP/x"
expect_exit 64 "--only twice"; expect_stderr_has "--only: given more than once" "names --only"
run --quick --only loop --loop-level linear --loop-level=plane --out "$TMP/x"
expect_exit 64 "--loop-level twice"; expect_stderr_has "--loop-level: given more than once" "names --loop-level"
[ ! -e "$TMP/x/loop.csv" ] && [ ! -e "$TMP/x/ik.csv" ] && ok || bad "a refused command line wrote a table"
run --help
expect_exit 0 "--help"; expect_stdout_has "--quick" "help lists --quick"

# An output folder that cannot be created: status 73, naming it.
touch "$TMP/file"
run --quick --only ik --out "$TMP/file/sub"
expect_exit 73 "--out under a file"; expect_stderr_has "$TMP/file" "names the folder"

if whole_family fidelity; then
# The fidelity family (no timing at all): each level's pressures rested under the head's
# weight with the fitted contact law, against the pose the plan claims.
run --quick --only fidelity --out "$OUT" --scenarios "$HP_SRC/scenarios"
expect_exit 0 "bench --only fidelity"
csv="$OUT/fidelity.csv"
[ -f "$csv" ] && [ "$(head -n 1 "$csv")" = "scene,case,level,backend,law,status,mass,tolerance,level_tolerance_mm,law_band,pose_mm,pose_deg,band_mm,band_deg,indent_max,carried,domain,own_mm,own_stable" ] \
  && ok || bad "fidelity.csv header"
# Four levels per case, in order; the single-bladder studies are left out; the load scenes
# carry their own mass, the others the default head's.
bad_rows=$(awk -F, 'NR > 1 && $3 != substr("linear plane  surfaceload   ", 1 + 7 * ((NR - 2) % 4), length($3)) { print NR ": " $3 }' "$csv")
[ -z "$bad_rows" ] && ok || bad "fidelity: levels out of order: $bad_rows"
[ "$(awk -F, 'NR > 1 && $1 ~ /^paper_/' "$csv" | wc -l)" -eq 0 ] && ok || bad "fidelity: a bladder study measured"
[ "$(awk -F, 'NR > 1 && $1 == "load_supine" && $3 == "linear"' "$csv" | wc -l)" -ge 2 ] && ok || bad "fidelity: load_supine cases"
bad_rows=$(awk -F, 'NR > 1 && (($1 ~ /^load_/) != ($7 == "scene")) { print $1 }' "$csv" | sort -u)
[ -z "$bad_rows" ] && ok || bad "fidelity: mass source: $bad_rows"
# The law's band is its worst error over its own tables' domain (a few per cent), the same
# on every row; only the load level has a planning law, and on the load scenes it has one.
[ "$(awk -F, 'NR > 1 { print $10 }' "$csv" | sort -u | wc -l)" -eq 1 ] && awk -F, 'NR == 2 { exit !($10 > 0.01 && $10 < 0.1) }' "$csv" \
  && ok || bad "fidelity: law_band"
bad_rows=$(awk -F, 'NR > 1 && (($3 == "load") != ($5 != "-")) && $6 != "refused" { print NR }' "$csv")
[ -z "$bad_rows" ] && ok || bad "fidelity: law column on rows $bad_rows"
awk -F, 'NR > 1 && $1 == "load_supine" && $3 == "load" && ($5 == "cap" || $5 == "fitted") { n++ } END { exit !(n > 0) }' "$csv" \
  && ok || bad "fidelity: load_supine's load level names its law"
# Relations every row keeps: no plan, no measurement; a rest or none ("no rest" exactly when
# the error is unbounded); the band's error is at least the nominal law's; a rest inside the
# law's domain is indented at most 0.26 of the radius, one beyond it is flagged; a kinematic
# plan's bladders just touch the head at the pose it claims, so they bear next to nothing of
# the weight (up to its geometry's difference from the surface's: 4e-4 seen on linear).
bad_rows=$(awk -F, 'NR > 1 {
    planned = $6 != "refused" && $6 != "error"
    if (!planned && ($11 != "nan" || $17 != "-")) print NR ": measured without a plan"
    if (planned && (($11 == "inf") != ($17 == "no rest"))) print NR ": unbounded vs no rest"
    if (planned && $11 != "inf" && !($13 + 0 >= $11 + 0 && $14 + 0 >= $12 + 0)) print NR ": band below nominal"
    if ($17 == "in" && !($15 + 0 <= 0.26 + 1e-6)) print NR ": in the domain at indent " $15
    if (planned && $11 != "inf" && $15 + 0 > 0.26 + 1e-6 && $17 !~ /:/) print NR ": beyond, not flagged"
    if (planned && $3 != "load" && !($16 + 0 < 0.01)) print NR ": a kinematic plan carries " $16 " of the weight"
  }' "$csv")
[ -z "$bad_rows" ] && ok || bad "fidelity: $bad_rows"
# The harness's own check: where the load level's own model is stiff (positive definite) at
# the pose the plan claims, its pressures rest there under that model (Newton's rest to
# 1e-12 mm steps; 1e-6 mm leaves room for the plan's tolerance, 1e-9). Where it is not, the
# claimed pose is an unstable equilibrium and the rest may leave it (own_mm inf), so no
# relation is asserted there. Other levels have no own load model. Only answers are
# measured (reached, closest, uncommanded): a plan that is no answer has neither.
bad_rows=$(awk -F, 'NR > 1 && ($6 == "reached" || $6 == "closest" || $6 == "uncommanded") {
    if ($3 == "load" && $19 == 1 && !($18 + 0 <= 1e-6 && $18 != "inf")) print NR ": stable, own rest " $18
    if ($3 == "load" && $19 == -1) print NR ": stiffness unknown"
    if ($3 != "load" && ($18 != "nan" || $19 != -1)) print NR ": own columns on " $3 }' "$csv")
[ -z "$bad_rows" ] && ok || bad "fidelity: $bad_rows"
awk -F, 'NR > 1 && $3 == "load" && $19 == 1 { n++ } END { exit !(n > 0) }' "$csv" && ok || bad "fidelity: no stable load plan to check the harness on"
# Whatever law it plans with, the load level's pressures bear more of the weight on the
# supine load scene than any kinematic level's (which bear next to none): by a margin of
# 10 % of the weight (the cap-law plans bear 22-29 % in the quick run).
bad_rows=$(awk -F, 'NR > 1 && $1 == "load_supine" { c[$2, $3] = $16 + 0; s[$2, $3] = $6; n[$2] = 1 }
  END { for (k in n) for (l = 1; l <= 3; l++) { lv = l == 1 ? "linear" : l == 2 ? "plane" : "surface"
    if (s[k, "load"] != "refused" && !(c[k, "load"] > c[k, lv] + 0.1)) print k ":" lv } }' "$csv")
[ -z "$bad_rows" ] && ok || bad "fidelity: load level bears no more of the weight than a kinematic level on load_supine: $bad_rows"
# When the load level plans with the fitted law, its pressures hold the head under that law
# wherever the hold is stable (own_stable 1; a saddle hold lets the head go, docs/load.md
# "Unstable holds"): the load level's error on the supine load scene is then bounded and
# below every kinematic level's on the same case (those ignore the weight), and such a case
# exists.
if awk -F, 'NR > 1 && $1 == "load_supine" && $3 == "load" && $5 == "fitted" { f = 1 } END { exit !f }' "$csv"; then
  awk -F, 'NR > 1 && $1 == "load_supine" && $3 == "load" && $19 == 1 && $6 != "refused" && $6 != "error" { n++ } END { exit !(n > 0) }' "$csv" && ok || bad "fidelity: no stable load hold on load_supine"
  bad_rows=$(awk -F, 'NR > 1 && $1 == "load_supine" { e[$2, $3] = $13 + 0; s[$2, $3] = $6; h[$2, $3] = $19 }
    END { for (k in s) { split(k, p, SUBSEP); c = p[1]
      if (p[2] == "load" && h[k] == 1 && (s[k] == "reached" || s[k] == "closest")) for (l in s) { split(l, q, SUBSEP)
        if (q[1] == c && q[2] != "load" && !(e[k] < e[l])) print c ":" q[2] } } }' "$csv")
  [ -z "$bad_rows" ] && ok || bad "fidelity: load level not below the kinematic levels on load_supine: $bad_rows"
fi
expect_stdout_has "median_mm" "fidelity summary header"
png="$OUT/fidelity.png"; svg="$OUT/fidelity.svg"
[ -s "$png" ] && [ "$(head -c 4 "$png" | od -An -tx1 | tr -d ' \n')" = "89504e47" ] && ok || bad "fidelity.png"
[ -s "$svg" ] && grep -q "<svg" "$svg" && ok || bad "fidelity.svg"
# The scene names reach the script as quoted text only, never inside its data block.
awk '/^\$d << EOD/ { on = 1; next } /^EOD/ { on = 0 }
     on { for (i = 1; i <= NF; i++) if ($i !~ /^-?[0-9.]+(e[-+][0-9]+)?$/ && $i != "nan" && $i != "-nan") bad = 1 }
     END { exit bad }' "$OUT/fidelity.gp" \
  && ok || bad "fidelity.gp: text inside the data block"
fi

# A scene that is not a layout scene: refused before any measurement, no output folder.
run --quick --only planner --out "$TMP/notlayout" --scene "$HP_SRC/scenarios/paper_expansion.yaml"
expect_exit 65 "--scene single-bladder study"; expect_stderr_has "not a layout scene" "says why"
[ ! -e "$TMP/notlayout/planner.csv" ] && ok || bad "planner.csv written for a bad scene"
run --out /dev/null/x --only ik --quick
expect_exit 73 "--out under a device"; expect_stderr_has "/dev/null/x" "names the folder"

# gnuplot missing: status 70 with a clear message, before any measuring or output.
HP_BIN_ABS=$(cd "$(dirname "$HP_BIN")" && pwd)/$(basename "$HP_BIN")
PATH=/nonexistent "$HP_BIN_ABS" --quick --only ik --out "$TMP/nognu" >"$TMP/out" 2>"$TMP/err"; rc=$?
expect_exit 70 "gnuplot missing"; expect_stderr_has "gnuplot not found" "says gnuplot is missing"
[ ! -e "$TMP/nognu" ] && ok || bad "output folder created although gnuplot is missing"

finish
