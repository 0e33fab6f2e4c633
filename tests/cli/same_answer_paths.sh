# The same scene and trace must give the same answer whichever way they reach the program:
# a scene on a pipe, the kind of rows stated in two places, a scene that asks for the load
# level. Each case here was once answered differently by two paths (see the commit).
source "$2/tests/cli_lib.sh"
S="$HP_SRC/scenarios"
HP_BIN=$(realpath "$HP_BIN") # the empty-name cases run in $TMP

printf '# headplan-trace: rows=correction\nt_s,x_mm,y_mm,z_mm,pitch_deg,roll_deg,yaw_deg\n0,1,0,-0.5,0.3,0,-0.2\n' \
    > "$TMP/c.csv"

# A scene on a pipe is read once: it used to be read for its kind, then found empty.
run solve "$S/default.yaml" --json; cp "$TMP/out" "$TMP/file.json"
"$HP_BIN" solve /dev/stdin --json < <(cat "$S/default.yaml") > "$TMP/out" 2> "$TMP/err"; rc=$?
expect_exit 0 "solve, scene on a pipe"
python3 - "$TMP/file.json" "$TMP/out" <<'PY' && ok || bad "pipe scene plans as the file"
import json, sys
a, b = (json.load(open(p)) for p in sys.argv[1:3])
assert a["status"] == b["status"] == "reached"
assert [x["pressure_pa"] for x in a["bladders"]] == [x["pressure_pa"] for x in b["bladders"]]
PY
"$HP_BIN" batch <(cat "$S/default.yaml") "$TMP/c.csv" --format csv --no-times \
    > "$TMP/out" 2> "$TMP/err"; rc=$?
expect_exit 0 "batch, scene on a pipe"
want=$(sha256sum < "$S/default.yaml" | cut -d' ' -f1)
expect_stdout_has "# scene_sha256: $want" "pipe scene's hash is of its bytes"
run solve /dev/null
expect_exit 65 "empty scene"; expect_stderr_has "/dev/null:1:1: headplan_scene: empty file" "empty"

# horizon: --rows against the scene's own trace.rows is refused, as in batch (it planned the
# deviation trace as corrections, every sign flipped, exit 0), and messages name --rows.
run horizon "$S/horizon/step.yaml" --mode greedy --rows correction
expect_exit 65 "horizon --rows against trace.rows"
expect_stderr_has "--rows says correction but the scene's trace.rows says deviation" "horizon rows"
expect_stdout_empty "horizon rows"
run batch "$S/horizon/step.yaml" --rows correction --format csv
expect_exit 65 "batch --rows against trace.rows"
run horizon "$S/horizon/step.yaml" --mode greedy --rows deviation
expect_exit 0 "horizon --rows agreeing with trace.rows"
run horizon "$S/horizon/step.yaml" "$S/traces/step.csv" --mode greedy
expect_exit 65 "horizon, trace states no kind"; expect_stderr_has "or give --rows" "names --rows"
grep -q "the caller" "$TMP/err" && bad "horizon message says 'the caller'" || ok
run horizon "$S/horizon/step.yaml" "$S/traces/nodding.csv" --mode greedy --rows correction
expect_exit 65 "horizon, trace against --rows"
expect_stderr_has "states rows=deviation but --rows says correction" "horizon names --rows"

# A scene planned at the load level (auto picks it for load_supine; model.level: load) is
# planned at the load level by batch and horizon's greedy mode as by solve (the same
# pressures bit for bit: python/tests/test_load_level.py); horizon's receding and offline
# plans refuse it by name, and render (which draws the contact levels) refuses it.
sed 's/model: {level: auto/model: {level: load/' "$S/load_supine.yaml" > "$TMP/load.yaml"
for sc in "$S/load_supine.yaml" "$TMP/load.yaml"; do
    run batch "$sc" "$TMP/c.csv" --format csv
    expect_exit 0 "batch, load scene $sc"; expect_stdout_has "# level: load" "batch load"
    run horizon "$sc" "$TMP/c.csv" --mode greedy
    expect_exit 0 "horizon greedy, load scene $sc"
    run horizon "$sc" "$TMP/c.csv" --mode receding
    expect_exit 65 "horizon receding, load scene $sc"; expect_stdout_empty "horizon receding load"
    expect_stderr_has "receding: the scene is planned at the load level" "horizon receding load"
    run render "$sc" --dry-run -o "$TMP/r.svg"
    expect_exit 65 "render, load scene $sc"
    run solve "$sc" --correction 1,0,-0.5,0.3,0,-0.2
    expect_exit 0 "solve plans the load scene"; expect_stdout_has "level       load" "solve load"
done
# analyze said its reach was "as solve plans" for a scene solve plans at the load level.
run analyze "$S/load_supine.yaml"
expect_exit 0 "analyze load scene"; expect_stdout_has "solve plans this scene at the load level" "note"
expect_stdout_has "as a kinematic plan (level surface)" "analyze reach is kinematic"
grep -q "as solve plans" "$TMP/out" && bad "analyze: reach 'as solve plans' on a load scene" || ok
run analyze "$S/load_supine.yaml" --json
python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); assert d["solve_level"] == "load"' \
    "$TMP/out" && ok || bad "analyze JSON solve_level"
run analyze "$S/default.yaml" --json
python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); assert d["solve_level"] == "surface"' \
    "$TMP/out" && ok || bad "analyze JSON solve_level, kinematic scene"
run batch "$S/load_supine.yaml" "$TMP/c.csv" --format csv --level surface --no-times
expect_exit 0 "batch, load scene, --level surface"
expect_stdout_has "# level: surface" "batch states the level it planned"
run batch "$S/default.yaml" "$TMP/c.csv" --format csv --level load
expect_exit 64 "batch --level load"; expect_stderr_has "--level: load needs a scene with a 'load' section" "batch --level load without a load section"

# A refused correction in batch says why and where (file:line), as solve does; it said
# "line 4: invalid correction". --jobs 2 gives the same lines.
printf '# headplan-trace: rows=correction\nt_s,x_mm,y_mm,z_mm,pitch_deg,roll_deg,yaw_deg\n0,1,0,0,0,0,0\n1,0,0,0,200,0,0\n2,1,0,0,0,0,0\n' \
    > "$TMP/inv.csv"
for j in 1 2; do
    run batch "$S/default.yaml" "$TMP/inv.csv" --format csv --no-times --jobs $j
    expect_exit 65 "batch invalid row, --jobs $j"
    expect_stderr_has "inv.csv:4: desired pitch: out of range" "batch invalid row names file, line, field"
done

# horizon: times that do not increase are named with the file; the kind of rows (and who
# stated it) is in the CSV header and the JSON, as in batch's metadata.
printf '# headplan-trace: rows=correction\nt_s,x_mm,y_mm,z_mm,pitch_deg,roll_deg,yaw_deg\n0,0,0,0,0,0,0\n0,1,0,0,0,0,0\n' \
    > "$TMP/same_t.csv"
run horizon "$S/default.yaml" "$TMP/same_t.csv" --mode greedy
expect_exit 65 "horizon, repeated time"
expect_stderr_has "same_t.csv:4: t_s: 0 s is not after the previous row's 0 s" "horizon time"
head -41 "$S/traces/step.csv" > "$TMP/step40.csv"
run horizon "$S/horizon/step.yaml" "$TMP/step40.csv" --rows deviation --mode greedy --json \
    -o "$TMP/h.csv"
expect_exit 0 "horizon rows kind"
expect_stdout_has '"rows_kind": "deviation", "rows_from": "--rows"' "horizon JSON rows kind"
grep -qx "# rows: deviation, rows_from: --rows" "$TMP/h.csv" && ok || bad "horizon CSV rows kind"

# plot: --scene and --trace are checked against the hashes in the result's metadata. A
# result of one trace, drawn with a scene that names another, used to take its "errors"
# from that other trace (matched by line numbers alone) and exit 0.
"$HP_BIN" batch "$S/default.yaml" "$S/traces/nodding.csv" -o "$TMP/nod.csv" 2>/dev/null
run plot "$TMP/nod.csv" --scene "$S/default.yaml" --dry-run
expect_exit 0 "plot, scene naming another trace"
awk '/^\$rows/{f=1;next} /^EOD/{f=0} f && !/^#/' "$TMP/out" | python3 -c '
import sys
for l in sys.stdin:
    assert all(float(v) == 0 for v in l.split()[1:7]), l
' && ok || bad "plot draws the result's own errors (all 0: every row reached)"
"$HP_BIN" batch "$S/default.yaml" - --format csv < "$S/traces/nodding.csv" > "$TMP/nod_stdin.csv" 2>/dev/null
run plot "$TMP/nod_stdin.csv" --scene "$S/default.yaml" --dry-run
expect_exit 0 "plot, a result of a stream, with a scene naming another trace"
awk '/^\$rows/{f=1;next} /^EOD/{f=0} f && !/^#/' "$TMP/out" | python3 -c '
import sys
for l in sys.stdin:
    assert all(float(v) == 0 for v in l.split()[1:7]), l
' && ok || bad "plot of a stream's result keeps its own errors"
run plot "$TMP/nod.csv" --scene "$S/saturation.yaml" --dry-run
expect_exit 65 "plot, another scene"; expect_stderr_has "not the scene" "plot scene hash"
run plot "$TMP/nod.csv" --trace "$S/traces/drift_10hz.csv" --dry-run
expect_exit 65 "plot, another trace"; expect_stderr_has "not the trace" "plot trace hash"
run plot "$TMP/nod.csv" --trace "$S/traces/nodding.csv" --rows correction --dry-run
expect_exit 65 "plot, --rows against the trace"
expect_stderr_has "states rows=deviation but --rows says correction" "plot names --rows"
run plot "$TMP/nod.csv" --scene "$S/default.yaml" --trace "$S/traces/nodding.csv" --dry-run
expect_exit 0 "plot, the right scene and trace"

# An empty output name (an unset variable in "-o $OUT") is refused before any work; it ran
# the whole job and failed renaming "OUT.partial-XXXXXX" to "", exit 74 with four lines.
cd "$TMP"
for cmd in "batch $S/default.yaml $TMP/c.csv --format csv -o" "horizon $S/default.yaml $TMP/c.csv -o" \
           "fit layout $S/default.yaml $HP_SRC/examples/calibration/layout_rows.csv -o" \
           "render $S/default.yaml -o $TMP/r.svg --script-out" \
           "fit material $HP_SRC/examples/calibration/material_ri.csv --Ri-mm 27 --Ro-mm 30 --plot"; do
    run $cmd ''
    expect_exit 73 "$cmd ''"; expect_stderr_has "'': an empty file name" "$cmd ''"
    [ "$(wc -l < "$TMP/err")" -eq 1 ] && ok || bad "$cmd '': one line"
done
ls -a "$TMP" | grep -q '^\.partial-' && bad "a temporary file was left" || ok
cd - > /dev/null

# render refuses a correction solve refuses (it drew the safe output, labelled, exit 0).
run render "$S/default.yaml" --correction 0,0,0,100,0,0 -o "$TMP/r.svg"
expect_exit 65 "render, correction outside the identifiable range"
expect_stderr_has "--correction: desired rotation: angle 100.0 deg is outside" "render names it"
[ ! -e "$TMP/r.svg" ] && ok || bad "render wrote a picture of a refused correction"
run solve "$S/default.yaml" --correction 0,0,0,100,0,0
expect_exit 65 "solve, the same correction"

# gnuplot exits 0 when writing its picture fails (full disk, file-size limit): the cut
# picture was renamed into place, exit 0. With XFSZ ignored, a 64 KiB limit makes its
# writes fail with EFBIG as a full disk would.
for ext in svg png; do
    (trap '' XFSZ; ulimit -f 64; "$HP_BIN" render "$S/default.yaml" -o "$TMP/cut.$ext" \
        --size 3000x3000 > "$TMP/out" 2> "$TMP/err"); rc=$?
    expect_exit 74 "render .$ext past a file-size limit"
    expect_stderr_has "cannot write $TMP/cut.$ext: gnuplot's picture is cut short" "cut $ext"
    [ ! -e "$TMP/cut.$ext" ] && ok || bad "a cut .$ext picture was left as complete"
done
(trap '' XFSZ; ulimit -f 64; "$HP_BIN" plot "$TMP/nod.csv" -o "$TMP/cut.svg" \
    > "$TMP/out" 2> "$TMP/err"); rc=$?
expect_exit 74 "plot past a file-size limit"
run render "$S/default.yaml" -o "$TMP/whole.png"
expect_exit 0 "render, a whole picture passes the check"

# The same number is refused by the CSV and the JSON Lines reader alike: jansson read
# 1e-400 as 0 and kept subnormals, where CSV says "too small for a double".
printf '{"headplan_trace": 1, "rows": "correction"}\n{"t_s":0,"x_mm":0,"y_mm":0,"z_mm":0,"pitch_deg":0,"roll_deg":0,"yaw_deg":-1e-310}\n{"t_s":1,"x_mm":1e-400,"y_mm":0,"z_mm":0,"pitch_deg":0,"roll_deg":0,"yaw_deg":0}\n' \
    > "$TMP/under.jsonl"
run batch "$S/default.yaml" "$TMP/under.jsonl" --format csv --no-times
expect_exit 65 "JSON Lines underflow"
expect_stderr_has "under.jsonl:2:74: yaw_deg: too small for a double" "JSON subnormal"
expect_stderr_has "under.jsonl:3:17: x_mm: too small for a double" "JSON underflow to 0"
printf '# headplan-trace: rows=correction\nt_s,x_mm,y_mm,z_mm,pitch_deg,roll_deg,yaw_deg\n0,0,0,0,0,0,-1e-310\n' > "$TMP/under.csv"
run batch "$S/default.yaml" "$TMP/under.csv" --format csv --no-times
expect_exit 65 "CSV subnormal"; expect_stderr_has "yaw_deg: too small for a double" "CSV subnormal"

# fit layout -o: a write that fails (full disk, file-size limit) is 74 like every output's;
# it was 73, the status of an output refused or that cannot be created.
(trap '' XFSZ; ulimit -f 1; cd "$TMP" && "$HP_BIN" fit layout "$S/default.yaml" \
    "$HP_SRC/examples/calibration/layout_rows.csv" -o "$TMP/cal.yaml" > "$TMP/out" 2> "$TMP/err"); rc=$?
expect_exit 74 "fit layout -o past a file-size limit"; expect_stderr_has "cannot write" "fit -o"
[ ! -e "$TMP/cal.yaml" ] && ok || bad "fit layout left a cut scene"
# render does not read the scene's trace, but --script-out or -o never write over it (the
# script replaced the trace file, exit 0).
mkdir -p "$TMP/rt/traces"; cp "$S/nodding.yaml" "$TMP/rt/"; cp "$S/traces/nodding.csv" "$TMP/rt/traces/"
before=$(sha256sum < "$TMP/rt/traces/nodding.csv")
run render "$TMP/rt/nodding.yaml" --dry-run --script-out "$TMP/rt/traces/nodding.csv"
expect_exit 73 "render --script-out onto the scene's trace"
expect_stderr_has "is the scene's trace" "render names the trace"
[ "$(sha256sum < "$TMP/rt/traces/nodding.csv")" = "$before" ] && ok || bad "render wrote over the scene's trace"
run render "$TMP/rt/nodding.yaml" --dry-run --script-out "$TMP/rt/r.gp"
expect_exit 0 "render --script-out elsewhere"
(cd "$TMP/rt" && "$HP_BIN" fit layout nodding.yaml "$HP_SRC/examples/calibration/layout_rows.csv" \
    -o traces/nodding.csv > "$TMP/out" 2> "$TMP/err"); rc=$?
expect_exit 73 "fit layout -o onto the scene's trace"
[ "$(sha256sum < "$TMP/rt/traces/nodding.csv")" = "$before" ] && ok || bad "fit layout wrote over the scene's trace"
(cd "$TMP/rt" && "$HP_BIN" fit layout nodding.yaml "$HP_SRC/examples/calibration/layout_rows.csv" \
    --plot r.svg --plot-script traces/nodding.csv > "$TMP/out" 2> "$TMP/err"); rc=$?
expect_exit 73 "fit layout --plot-script onto the scene's trace"
[ "$(sha256sum < "$TMP/rt/traces/nodding.csv")" = "$before" ] && ok || bad "fit layout --plot-script wrote over the scene's trace"
# batch and horizon planning another trace: the scene's own trace is still never written over.
cp "$S/traces/nodding.csv" "$TMP/rt/other.csv"
run batch "$TMP/rt/nodding.yaml" "$TMP/rt/other.csv" -o "$TMP/rt/traces/nodding.csv" --format csv
expect_exit 73 "batch -o onto the scene's trace, another trace planned"
expect_stderr_has "is the scene's trace" "batch names the scene's trace"
run horizon "$TMP/rt/nodding.yaml" "$TMP/rt/other.csv" --rows deviation -o "$TMP/rt/traces/nodding.csv"
expect_exit 73 "horizon -o onto the scene's trace, another trace planned"
[ "$(sha256sum < "$TMP/rt/traces/nodding.csv")" = "$before" ] && ok || bad "batch or horizon wrote over the scene's trace"
finish
