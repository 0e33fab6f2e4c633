# Sourced by the command-line tests: expect_exit, expect_stdout_empty, expect_stderr_has.
HP_BIN="$1"; HP_SRC="$2"
fails=0; passes=0
TMP=$(mktemp -d); trap 'rm -rf "$TMP"' EXIT
# run ARGS...: runs headplan, keeps stdout in $TMP/out, stderr in $TMP/err, status in $rc.
run() { "$HP_BIN" "$@" >"$TMP/out" 2>"$TMP/err"; rc=$?; }
ok() { passes=$((passes+1)); }
bad() { fails=$((fails+1)); echo "FAIL: $*"; echo "  stdout: $(head -c 400 "$TMP/out")"; echo "  stderr: $(head -c 400 "$TMP/err")"; }
expect_exit() { [ "$rc" -eq "$1" ] && ok || bad "$2: exit $rc, want $1"; }
expect_stdout_empty() { [ ! -s "$TMP/out" ] && ok || bad "$1: stdout not empty"; }
expect_stderr_has() { grep -qF -- "$1" "$TMP/err" && ok || bad "$2: stderr lacks '$1'"; }
expect_stdout_has() { grep -qF -- "$1" "$TMP/out" && ok || bad "$2: stdout lacks '$1'"; }
# under_sanitizers: true in the sanitizer build's run (HP_UNDER_ASAN=1, set by ctest there),
# where a script may take the first of its cases: that build runs its code 3 to 10 times
# slower, on a machine .ci/run loads on purpose.
under_sanitizers() { [ "${HP_UNDER_ASAN:-0}" = 1 ]; }
finish() { echo "$passes passed, $fails failed"; [ "$fails" -eq 0 ]; }
# patient_scenes: prints the folder of a copy of scenarios/ in which every time budget a scene
# states (solver.max_time_s) is 60 s. The scenes' own budgets (1 s a plan) are read on the wall
# clock, and the receding horizon stops each row's solve within four fifths of one: on a machine
# stalled that long a row ends "time-limit" and the exit status and output change. A test
# whose verdict needs no row stopped by time plans these instead.
patient_scenes() {
    cp -r "$HP_SRC/scenarios" "$TMP/scenarios_60s" &&
        find "$TMP/scenarios_60s" -name '*.yaml' -exec \
            sed -i -E 's/max_time_s: [0-9.eE+-]+/max_time_s: 60/' {} + &&
        echo "$TMP/scenarios_60s"
}
# drop_measured FILE: a batch CSV result with its measured columns (the solve time: not a
# function of the inputs) blanked, its metadata and header kept, for comparing two runs.
# Which columns are measured is the program's column table (`headplan batch --columns`).
drop_measured() {
    awk -F, -v OFS=, -v measured="$("$HP_BIN" batch --columns | awk -F'\t' 'NR > 1 && $7 == "yes" { print $1 }')" '
        BEGIN { n = split(measured, m, "\n"); for (i = 1; i <= n; i++) drop[m[i]] = 1 }
        /^#/ { print; next }
        !h { for (i = 1; i <= NF; i++) if ($i in drop) c[i] = 1; h = 1; print; next }
        { for (i in c) $i = ""; print }' "$1"
}
