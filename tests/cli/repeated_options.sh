# Options given twice and outputs that collide: the same request reaching the program by
# another path (an option given twice, two outputs naming one file, a byte-order mark, a
# result cut short) must get the same honest answer. Each case here was once answered wrongly (see the commit).
source "$2/tests/cli_lib.sh"
HP_BIN=$(realpath "$HP_BIN"); HP_SRC=$(realpath "$HP_SRC") # some cases run in $TMP
S=$(patient_scenes) || exit 1 # time budgets of 60 s (tests/cli_lib.sh)
E="$HP_SRC/examples/calibration"

# fit material took the last of two --Ri-mm (--Ro-mm, --plot, --fit-ref) silently, exit 0;
# every other subcommand, fit layout included, refuses an option given twice.
for o in "--Ri-mm 28" "--Ro-mm 31" "--fit-ref Ri --fit-ref Ro" "--plot $TMP/a.svg --plot $TMP/b.svg"; do
    run fit material "$E/material_ri.csv" --Ri-mm 27 --Ro-mm 30 $o
    expect_exit 64 "fit material $o"; expect_stderr_has "given more than once" "fit material $o"
    expect_stdout_empty "fit material $o"
done

# Two outputs naming one file by two spellings ("x.svg" and "./x.svg", a link to the folder):
# the second rename replaced the first output, exit 0 (render kept the picture and lost the
# script; fit layout's calibrated scene replaced its plot). Refused before any work.
"$HP_BIN" batch "$S/default.yaml" "$S/traces/nodding.csv" -o "$TMP/nod.csv" 2>/dev/null
mkdir -p "$TMP/d"; ln -s "$TMP/d" "$TMP/dl"
cd "$TMP/d"
for cmd in "render $S/default.yaml -o x.svg --script-out ./x.svg" \
           "render $S/default.yaml -o $TMP/dl/x.svg --script-out x.svg" \
           "plot $TMP/nod.csv -o x.svg --script-out ../d/x.svg" \
           "fit layout $S/default.yaml $E/layout_rows.csv -o x.svg --plot ./x.svg" \
           "fit layout $S/default.yaml $E/layout_rows.csv -o x.gp --plot y.svg --plot-script $TMP/d/x.gp" \
           "fit layout $S/default.yaml $E/layout_rows.csv --plot x.svg --plot-script $TMP/dl/x.svg"; do
    run $cmd
    expect_exit 64 "$cmd"; expect_stderr_has "name the same file" "$cmd"
    [ -z "$(ls -A "$TMP/d")" ] && ok || bad "$cmd: wrote $(ls "$TMP/d")"
done
run fit layout "$S/default.yaml" "$E/layout_rows.csv" --plot x.svg --plot-script x.svg
expect_stderr_has "--plot-script x.svg and --plot x.svg" "fit layout names its own options"
cd - > /dev/null
# plot drew a result whose last line was cut short (no end of line) with the cut number
# (the last bladder's -38.09 Pa drawn as -3 Pa), exit 0; the trace and calibration readers
# refuse such a file. A byte-order mark made the whole result "not a headplan batch CSV".
python3 - "$TMP/nod.csv" "$TMP/cut.csv" <<'PY'
import sys
lines = open(sys.argv[1]).read().split("\n")
hdr = [l for l in lines if l.startswith("line,")][0].split(",")
i = hdr.index("side_chin_right_pressure_pa")
last = lines[-2].split(",")
open(sys.argv[2], "w").write("\n".join(lines[:-2] + [",".join(last[:i] + [last[i][:2]])]))
PY
n=$(wc -l < "$TMP/cut.csv")
run plot "$TMP/cut.csv" --dry-run
expect_exit 65 "plot, result cut short"; expect_stdout_empty "plot, result cut short"
expect_stderr_has "cut.csv:$((n + 1)): truncated: the last line has no end of line" "plot names the cut line"
printf '\xef\xbb\xbf' > "$TMP/bom.csv"; cat "$TMP/nod.csv" >> "$TMP/bom.csv"
run plot "$TMP/bom.csv" --dry-run
expect_exit 0 "plot, result with a byte-order mark"
grep -v "bom.csv" "$TMP/out" > "$TMP/a.gp"
"$HP_BIN" plot "$TMP/nod.csv" --dry-run | grep -v "nod.csv" > "$TMP/b.gp"
cmp -s "$TMP/a.gp" "$TMP/b.gp" && ok || bad "plot with a byte-order mark draws the same"
# horizon planned a correction solve and batch refuse (a 100 deg pitch: outside the
# identifiable range) with exit 0: greedy and receding as invalid-input rows, offline as
# closest. Refused before any planning, with batch's words and the trace's line.
printf '# headplan-trace: rows=correction\nt_s,x_mm,y_mm,z_mm,pitch_deg,roll_deg,yaw_deg\n0,1,0,0,0,0,0\n1,0,0,0,100,0,0\n2,1,0,0,0,0,0\n' \
    > "$TMP/inv.csv"
run batch "$S/default.yaml" "$TMP/inv.csv" --format csv --no-times
expect_exit 65 "batch, a row outside the identifiable range"
want=$(grep -m1 "inv.csv:4: desired rotation" "$TMP/err" | sed 's/^headplan batch: //')
[ -n "$want" ] && ok || bad "batch names the row"
for m in greedy receding offline compare; do
    run horizon "$S/default.yaml" "$TMP/inv.csv" --mode $m -o "$TMP/h.csv"
    expect_exit 65 "horizon --mode $m, a row outside the identifiable range"
    expect_stderr_has "headplan horizon: $want" "horizon --mode $m says what batch says"
    expect_stdout_empty "horizon --mode $m"
    [ ! -e "$TMP/h.csv" ] && ok || bad "horizon --mode $m wrote a result"
done
# A row stopped by its budget (iteration-limit) is a failure in batch (70) but horizon exited
# 0 with it inside the summary. Now 70 after the outputs, naming the first such row.
sed 's/backend: realtime, tolerance: 1e-9, max_iter: 200/backend: ipopt, tolerance: 1e-9, max_iter: 3/' \
    "$S/default.yaml" > "$TMP/it.yaml"
printf '# headplan-trace: rows=correction\nt_s,x_mm,y_mm,z_mm,pitch_deg,roll_deg,yaw_deg\n0,1,0,0,0,0,0\n1,5,5,5,3,3,3\n2,1,0,0,0,0,0\n' \
    > "$TMP/big.csv"
run batch "$TMP/it.yaml" "$TMP/big.csv" --format csv --no-times
expect_exit 70 "batch, a row at the iteration limit"
grep -q "^4,1,iteration-limit," "$TMP/out" && ok || bad "batch: row 4 at the iteration limit"
run horizon "$TMP/it.yaml" "$TMP/big.csv" --mode greedy -o "$TMP/hf.csv"
expect_exit 70 "horizon, a row at the iteration limit"
expect_stderr_has "greedy: 1 of 3 rows failed (first $TMP/big.csv:4: iteration-limit)" "horizon names it"
grep -q "^greedy,1,.*,iteration-limit," "$TMP/hf.csv" && ok || bad "horizon -o states the row's status"
# fit layout's --plot and --plot-script refusals named -o and --script-out, options the user
# did not give (fit layout's -o is the calibrated scene).
cp "$S/default.yaml" "$TMP/fl.yaml"; ln -s "$TMP/none.svg" "$TMP/lnk.svg"
run fit layout "$TMP/fl.yaml" "$E/layout_rows.csv" --plot "$TMP/lnk.svg"
expect_exit 73 "fit layout --plot onto a link"
expect_stderr_has "headplan fit: --plot $TMP/lnk.svg is a symbolic link" "fit layout names --plot"
run fit layout "$TMP/fl.yaml" "$E/layout_rows.csv" --plot "$TMP/p.svg" --plot-script "$TMP/fl.yaml"
expect_exit 73 "fit layout --plot-script onto the scene"
expect_stderr_has "headplan fit: --plot-script $TMP/fl.yaml is the scene" "fit layout names --plot-script"
cmp -s "$TMP/fl.yaml" "$S/default.yaml" && ok || bad "fit layout wrote over its scene"
run fit layout "$TMP/fl.yaml" "$E/layout_rows.csv" --plot "$TMP/no/p.svg"
expect_exit 73 "fit layout --plot into a missing folder"
expect_stderr_has "headplan fit: --plot $TMP/no/p.svg: cannot create" "fit layout names --plot"
# render and plot took the last of two --size silently (every other option given twice is
# refused).
run render "$S/default.yaml" --size 300x300 --size 400x400 --dry-run
expect_exit 64 "render --size twice"; expect_stderr_has "--size: given more than once" "render --size"
run plot "$TMP/nod.csv" --size 300x300 --size 400x400 --dry-run
expect_exit 64 "plot --size twice"; expect_stderr_has "--size: given more than once" "plot --size"
expect_stdout_empty "plot --size twice"
# plot's --help said its default size was 1500x700 (render's); it draws 1400x900.
for c in render plot; do
    if [ $c = plot ]; then run plot "$TMP/nod.csv" --dry-run; else run render "$S/default.yaml" --dry-run; fi
    size=$(grep -m1 -o "size [0-9]*,[0-9]*" "$TMP/out" | sed 's/size //; s/,/x/')
    "$HP_BIN" $c --help | grep -q -- "--size .*$c $size" && ok || bad "$c --help states the default size $size"
done
# '-' is standard input for batch's TRACE; horizon said "-: cannot open: No such file".
printf '# headplan-trace: rows=correction\nt_s,x_mm,y_mm,z_mm,pitch_deg,roll_deg,yaw_deg\n0,1,0,-0.5,0.3,0,-0.2\n0.1,1.2,0,-0.5,0.3,0,-0.2\n' \
    > "$TMP/c.csv"
"$HP_BIN" horizon "$S/default.yaml" "$TMP/c.csv" -o "$TMP/h_file.csv" > "$TMP/file_out" 2>/dev/null
"$HP_BIN" horizon "$S/default.yaml" - -o "$TMP/h_pipe.csv" < <(cat "$TMP/c.csv") > "$TMP/out" 2> "$TMP/err"; rc=$?
expect_exit 0 "horizon, trace on standard input"
cmp -s "$TMP/out" "$TMP/file_out" && ok || bad "horizon from standard input prints what the file gives"
diff <(sed 1d "$TMP/h_file.csv") <(sed 1d "$TMP/h_pipe.csv") > /dev/null && ok || bad "horizon -o from standard input"
cp "$TMP/c.csv" "$TMP/c2.csv"
"$HP_BIN" horizon "$S/default.yaml" - -o "$TMP/c2.csv" < "$TMP/c2.csv" > "$TMP/out" 2> "$TMP/err"; rc=$?
expect_exit 73 "horizon -o onto the file on standard input"
cmp -s "$TMP/c.csv" "$TMP/c2.csv" && ok || bad "horizon replaced the trace it read from standard input"
# Standard output appended to an input (">> scene.yaml"): the result was written into the
# scene, the trace, the result or the data file, exit 0. Refused before anything is written.
mkdir -p "$TMP/app"; cd "$TMP/app"
cp "$S/default.yaml" s.yaml; cp "$TMP/c.csv" t.csv; cp "$TMP/nod.csv" r.csv
cp "$E/material_ri.csv" m.csv; cp "$E/layout_rows.csv" l.csv
cp s.yaml s.orig; cp t.csv t.orig; cp r.csv r.orig; cp m.csv m.orig; cp l.csv l.orig
for c in "solve s.yaml >> s.yaml" "analyze s.yaml >> s.yaml" "render s.yaml --dry-run >> s.yaml" \
         "batch s.yaml t.csv --format csv >> t.csv" "batch s.yaml - --format csv < t.csv >> t.csv" \
         "horizon s.yaml t.csv >> t.csv" "plot r.csv --dry-run >> r.csv" \
         "fit material m.csv --Ri-mm 27 --Ro-mm 30 >> m.csv" "fit layout s.yaml l.csv >> l.csv"; do
    eval "\"\$HP_BIN\" $c" 2> "$TMP/err"; rc=$?
    expect_exit 73 "$c"; expect_stderr_has "standard output is the" "$c"
done
for f in s.yaml t.csv r.csv m.csv l.csv; do cmp -s "$f" "${f%.*}.orig" && ok || bad "$f was written into"; done
"$HP_BIN" solve s.yaml >> other.txt 2> "$TMP/err"; rc=$?
expect_exit 0 "solve appending to another file"
cd - > /dev/null
# solve --backend nlopt-cobyla on a scene planned at the load level blamed the scene (65,
# 'load_supine.yaml: load planner: backend ...'); the scene is fine, the option is not: 64.
run solve "$S/load_supine.yaml" --backend nlopt-cobyla
expect_exit 64 "solve --backend cobyla at the load level"
expect_stderr_has "headplan solve: --backend nlopt-cobyla: nlopt-cobyla is not available at the load level" "names --backend"
sed "s/backend: [a-z-]*/backend: nlopt-cobyla/; s#file: traces/#file: $S/traces/#" "$S/load_supine.yaml" > "$TMP/lc.yaml"
run solve "$TMP/lc.yaml"
expect_exit 65 "a load scene that asks for cobyla itself"; expect_stderr_has "lc.yaml: backend: nlopt-cobyla" "names the scene"
run solve "$TMP/lc.yaml" --backend realtime
expect_exit 0 "--backend realtime overrides the scene's cobyla"
# A JSON Lines trace reads every number as the CSV reader does: an integer beyond 64 bits was a
# bad row ("too big integer") where CSV reads the number (then refused as out of range). -0
# is kept as a guard: both read it as -0.
for v in 123456789012345678901234567890 -0; do
    printf '{"headplan_trace": 1, "rows": "correction"}\n{"t_s":0,"x_mm":%s,"y_mm":0,"z_mm":0,"pitch_deg":0,"roll_deg":0,"yaw_deg":-0}\n' $v > "$TMP/n.jsonl"
    printf '# headplan-trace: rows=correction\nt_s,x_mm,y_mm,z_mm,pitch_deg,roll_deg,yaw_deg\n0,%s,0,0,0,0,-0\n' $v > "$TMP/n.csv"
    "$HP_BIN" batch "$S/default.yaml" "$TMP/n.jsonl" --format csv --no-times 2>/dev/null | grep -v '^#' | cut -d, -f2- > "$TMP/a"
    "$HP_BIN" batch "$S/default.yaml" "$TMP/n.csv" --format csv --no-times 2>/dev/null | grep -v '^#' | cut -d, -f2- > "$TMP/b"
    cmp -s "$TMP/a" "$TMP/b" && ok || bad "JSON Lines and CSV differ on $v: $(diff "$TMP/a" "$TMP/b" | head -3)"
done
finish
