#!/usr/bin/env bash
# Runs every cmocka test executable (the ctest tests other than the cli_* scripts and the
# install test) under valgrind memcheck, then the headplan program once per subcommand
# (solve on every layout scenario with every backend, batch, analyze, paper, ik, fk).
# Any memcheck error or definite leak fails the run (--error-exitcode=1).
#
#   bash scripts/valgrind.sh            build in build-valgrind/ (RelWithDebInfo) and run all
#   VG_BUILD=dir bash scripts/valgrind.sh   use another build directory
#   VG_ONLY=tests|cli bash scripts/valgrind.sh   only the test executables / only the program
#
# Logs: $VG_BUILD/valgrind/<name>.log. Suppressions: tests/valgrind.supp (third-party only).
set -uo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh || exit 1
export LC_ALL=C CMOCKA_MESSAGE_OUTPUT=stdout
B=${VG_BUILD:-build-valgrind}
ONLY=${VG_ONLY:-all}
cmake -S . -B "$B" -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null || exit 1
cmake --build "$B" -j"$(nproc)" >"$B/valgrind-build.log" 2>&1 || {
  tail -30 "$B/valgrind-build.log"; exit 1; }
mkdir -p "$B/valgrind"
VG=(valgrind --quiet --error-exitcode=1 --leak-check=full --errors-for-leak-kinds=definite
    --show-leak-kinds=definite --track-origins=yes --num-callers=30
    --suppressions=tests/valgrind.supp)
status=0; n_ok=0; n_fail=0; n_warn=0

# vg EXPECT NAME CMD...: one run under memcheck. With --quiet the log file stays empty
# unless memcheck found something, so a non-empty log is a failure whatever the exit status
# (the program's own statuses overlap --error-exitcode=1: solve exits 1 for "closest").
# EXPECT "0": a non-zero exit without a memcheck error is reported as WARN (a test that
# fails under valgrind: run it natively); "any": the command is meant to fail or may.
vg() {
  local expect=$1 name=$2; shift 2
  local log="$B/valgrind/$name.log"
  "${VG[@]}" --log-file="$log" "$@" >"$log.out" 2>"$log.err"
  local rc=$?
  if [ -s "$log" ]; then
    echo "valgrind FAIL: $name (exit $rc; $log)"; status=1; n_fail=$((n_fail+1))
  elif [ "$expect" = 0 ] && [ "$rc" -ne 0 ]; then
    echo "valgrind WARN: $name: memcheck clean, but it exited $rc ($log.out)"
    n_warn=$((n_warn+1))
  else
    echo "valgrind ok:   $name (exit $rc)"; n_ok=$((n_ok+1))
  fi
}

if [ "$ONLY" != cli ]; then
  # The executables ctest knows (tests/CMakeLists.txt names each after its target).
  mapfile -t tests < <(ctest --test-dir "$B" -N -LE cli | sed -n 's/^ *Test *#[0-9]*: //p' |
                       grep -v '^install')
  [ ${#tests[@]} -gt 0 ] || { echo "valgrind.sh: ctest lists no tests in $B"; exit 1; }
  for t in "${tests[@]}"; do
    exe="$B/tests/$t"
    [ -x "$exe" ] || { echo "valgrind FAIL: $t (no executable $exe)"; status=1; continue; }
    # test_alloc wraps malloc itself and counts allocations: valgrind replaces malloc, so
    # the wrapped counters see nothing; it still runs, the memcheck verdict is what counts.
    vg 0 "$t" "$exe"
  done
fi

if [ "$ONLY" != tests ]; then
  H="$B/headplan"
  for sc in scenarios/*.yaml; do
    case $sc in *paper_*) continue;; esac
    # A scene that states no correction (a trace scenario) gets a small one.
    corr=(); grep -q '^correction:' "$sc" || corr=(--correction 1,0,-0.5,0.3,0,-0.2)
    for be in realtime ipopt nlopt-slsqp nlopt-cobyla; do
      # Exit 1 (closest) is normal; 70 can be Ipopt's CPU-time budget (solver.max_time_s)
      # running out under valgrind's ~50x slowdown: memcheck's verdict is what counts.
      vg any "solve-$(basename "$sc" .yaml)-$be" "$H" solve "$sc" --backend "$be" --json \
         "${corr[@]}"
    done
  done
  for tr in scenarios/traces/*.csv; do
    vg any "batch-$(basename "$tr")" "$H" batch scenarios/default.yaml "$tr" --no-progress
  done
  vg any "batch-jobs2" "$H" batch scenarios/default.yaml scenarios/traces/drift_10hz.csv --jobs 2 \
     --no-progress --format jsonl
  for sc in scenarios/default.yaml scenarios/sphere_head.yaml; do
    vg 0 "analyze-$(basename "$sc" .yaml)" "$H" analyze "$sc" --json
  done
  vg 0 paper "$H" paper
  vg 0 paper-json "$H" paper --json scenarios/paper_expansion.yaml scenarios/paper_compression.yaml
  vg 0 ik "$H" ik --Ri 27 --Ro 30 --ri 30 --c1 1.1e4 --c2 2.2e4
  vg 0 fk "$H" fk --Ri 27 --Ro 30 --pressure 500 --c10 5.5e3 --c01 1.1e4 --json
  vg any fk-above-limit "$H" fk --Ri 27 --Ro 30 --pressure 1e6 --c1 1.1e4 --c2 0
  vg any solve-bad-scene "$H" solve tests/scenes_bad/duplicate_key.yaml
  vg any batch-bad-trace "$H" batch scenarios/default.yaml tests/scenes_bad/empty.yaml
  printf 't_s,x_mm,y_mm,z_mm,pitch_deg,roll_deg,yaw_deg\n0,0,0,0,0,0,0\n0.1,nan,0,0,0,0,0\n' \
    >"$B/valgrind/bad_row.csv"
  vg any batch-bad-row "$H" batch scenarios/default.yaml "$B/valgrind/bad_row.csv" \
     -o "$B/valgrind/bad_row.out.jsonl" --format jsonl
  vg any batch-out-unwritable "$H" batch scenarios/default.yaml "$B/valgrind/bad_row.csv" \
     -o /dev/null/out.csv
fi
echo "valgrind: $n_ok ok, $n_warn warned (test exit, no memory error), $n_fail failed"
exit $status
