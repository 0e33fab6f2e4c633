# Standard input and '--' attacked (empty, a directory, closed,
# garbage, given twice, the output on the input). Every refusal is one line naming the file
# (FILE:LINE:COL for its content) with its own exit code, and writes nothing.
source "$2/tests/cli_lib.sh"
HP_BIN=$(realpath "$HP_BIN"); HP_SRC=$(realpath "$HP_SRC")
S=$(patient_scenes) || exit 1 # time budgets of 60 s (tests/cli_lib.sh)

# plot RESULT that could not be read (a directory, as a file or on standard input) was
# "empty (no header)", exit 65: the read error was checked after the header. Now 66 with
# the reason, as solve and batch say it.
run plot "$TMP" -o "$TMP/p.svg"
expect_exit 66 "plot, a directory as RESULT"
expect_stderr_has "$TMP: cannot read: Is a directory" "plot names the directory"
"$HP_BIN" plot - -o "$TMP/p.svg" < "$TMP" > "$TMP/out" 2> "$TMP/err"; rc=$?
expect_exit 66 "plot - < DIR"; expect_stderr_has "<stdin>: cannot read: Is a directory" "plot - < DIR"
[ ! -e "$TMP/p.svg" ] && ok || bad "plot drew an unreadable result"
"$HP_BIN" plot - -o "$TMP/p.svg" < /dev/null > "$TMP/out" 2> "$TMP/err"; rc=$?
expect_exit 65 "plot - < /dev/null"; expect_stderr_has "<stdin>: empty (no header)" "plot empty stdin"

# Each scene reader, given an empty, unreadable, closed or garbage standard input.
for cmd in solve analyze render batch horizon; do
    extra=""; [ "$cmd" = render ] && extra="-o $TMP/r.svg"; [ "$cmd" = batch ] && extra="--format csv"
    "$HP_BIN" $cmd - $extra < /dev/null > "$TMP/out" 2> "$TMP/err"; rc=$?
    expect_exit 65 "$cmd - < /dev/null"; expect_stdout_empty "$cmd - < /dev/null"
    expect_stderr_has "<stdin>:1:1: headplan_scene: empty file" "$cmd empty stdin"
    "$HP_BIN" $cmd - $extra < "$TMP" > "$TMP/out" 2> "$TMP/err"; rc=$?
    expect_exit 66 "$cmd - < DIR"; expect_stderr_has "<stdin>: cannot read: Is a directory" "$cmd - < DIR"
    "$HP_BIN" $cmd - $extra <&- > "$TMP/out" 2> "$TMP/err"; rc=$?
    expect_exit 66 "$cmd - <&-"; expect_stderr_has "<stdin>: cannot read:" "$cmd closed stdin"
    printf 'headplan_scene: 1\n\0\n' | "$HP_BIN" $cmd - $extra > "$TMP/out" 2> "$TMP/err"; rc=$?
    expect_exit 65 "$cmd - NUL"; expect_stderr_has "<stdin>:2:1: NUL byte" "$cmd NUL on stdin"
    [ "$(wc -l < "$TMP/err")" -eq 1 ] && ok || bad "$cmd: more than one line for a NUL byte"
    "$HP_BIN" $cmd - - $extra < "$S/default.yaml" > "$TMP/out" 2> "$TMP/err"; rc=$?
    expect_exit 64 "$cmd - -"; expect_stdout_empty "$cmd - -"
done
[ ! -e "$TMP/r.svg" ] && ok || bad "render wrote from a refused scene"
head -c 700 "$S/default.yaml" | "$HP_BIN" solve - > "$TMP/out" 2> "$TMP/err"; rc=$?
expect_exit 65 "solve, a scene cut short on stdin"; expect_stderr_has "<stdin>:18:1: yaml:" "cut scene"

# '--': nothing after it is "missing", a second one is a file named '--', '-' after it is
# still standard input.
run solve --
expect_exit 64 "solve --"; expect_stderr_has "SCENE: missing" "solve -- names SCENE"
run solve -- --
expect_exit 66 "solve -- --"; expect_stderr_has "--: cannot open" "solve -- -- names the file"
"$HP_BIN" solve -- - < "$S/default.yaml" > "$TMP/out" 2> "$TMP/err"; rc=$?
expect_exit 0 "solve -- - (stdin)"
run solve "$S/default.yaml" -- --
expect_exit 64 "solve SCENE -- --"

# The scene's trace on standard input's scene is taken from the current directory (README).
(cd "$TMP" && "$HP_BIN" batch - --format csv < "$S/nodding.yaml" > "$TMP/out" 2> "$TMP/err"); rc=$?
expect_exit 66 "batch -, relative trace from elsewhere"; expect_stdout_empty "batch - relative trace"
expect_stderr_has "traces/nodding.csv: cannot open" "the trace named"
(cd "$S" && "$HP_BIN" batch - --format csv --no-times < nodding.yaml > "$TMP/out" 2> "$TMP/err"); rc=$?
expect_exit 0 "batch - from the scene's directory"; expect_stdout_has "# scene: <stdin>" "scene named <stdin>"

# Outputs on the input or on /dev/stdin are refused before anything is written.
cp "$S/traces/nodding.csv" "$TMP/t.csv"; cp "$TMP/t.csv" "$TMP/t.orig"
for cmd in batch horizon; do
    extra=""; [ "$cmd" = batch ] && extra="--format csv"
    "$HP_BIN" $cmd "$S/default.yaml" - $extra -o "$TMP/t.csv" < "$TMP/t.csv" > "$TMP/out" 2> "$TMP/err"; rc=$?
    expect_exit 73 "$cmd -o the trace on stdin"; expect_stderr_has "is the trace <stdin>: refused" "$cmd names it"
    cmp -s "$TMP/t.csv" "$TMP/t.orig" && ok || bad "$cmd overwrote its trace"
    "$HP_BIN" $cmd "$S/default.yaml" - $extra -o /dev/stdin < "$TMP/t.csv" > "$TMP/out" 2> "$TMP/err"; rc=$?
    expect_exit 73 "$cmd -o /dev/stdin"; cmp -s "$TMP/t.csv" "$TMP/t.orig" && ok || bad "$cmd wrote /dev/stdin"
done
# A five-bladder scene (rotations partly uncommanded) is planned by batch; horizon refused it
# (65, "start pressures: ... did not converge", then "no pose holds them"): its start, the
# scene's own nominal pressures, was fitted in all six components, which five distances
# cannot give.
grep -v 'side_chin\|side_fore_right' "$S/default.yaml" \
    | sed "s#traces/drift_10hz.csv#$S/traces/nodding.csv#" > "$TMP/five.yaml"
run horizon "$TMP/five.yaml"
expect_exit 0 "horizon, a five-bladder scene"; expect_stdout_has "receding,max" "horizon five"
run batch "$TMP/five.yaml" --format csv --no-times
expect_exit 0 "batch, a five-bladder scene"
# '-o -' is standard output in batch only; horizon, fit layout and fit --plot created a file
# named '-' in the current folder (exit 0, nothing said), and fit layout with its scene on
# standard input called '-o -' "an input of the fit". Now each is refused by name (64).
mkdir "$TMP/cwd"; cd "$TMP/cwd"
run horizon "$S/nodding.yaml" -o -
expect_exit 64 "horizon -o -"; expect_stderr_has "-o -: this output cannot be standard output" "horizon -o -"
run fit layout "$S/default.yaml" "$HP_SRC/examples/calibration/layout_rows.csv" -o -
expect_exit 64 "fit layout -o -"; expect_stderr_has "-o -: this output cannot be standard output" "fit -o -"
"$HP_BIN" fit layout - "$HP_SRC/examples/calibration/layout_rows.csv" -o - < "$S/default.yaml" > "$TMP/out" 2> "$TMP/err"; rc=$?
expect_exit 64 "fit layout - -o -"; expect_stderr_has "-o -: this output cannot be standard output" "fit - -o -"
run fit material "$HP_SRC/examples/calibration/material_ri.csv" --Ri-mm 27 --Ro-mm 30 --plot -
expect_exit 64 "fit material --plot -"; expect_stderr_has "--plot -: this output cannot be standard output" "fit --plot -"
[ ! -e ./- ] && ok || bad "a file named '-' was written"
cd - > /dev/null
finish
