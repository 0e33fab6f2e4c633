# Seams between calibration, scenes and the command line: each block states what the
# command did wrong and checks the behaviour it has now (exit status, one-line message).
source "$2/tests/cli_lib.sh"
HP_BIN=$(realpath "$HP_BIN"); HP_SRC=$(realpath "$HP_SRC")
S="$HP_SRC/scenarios"

# render draws the plan's message: a closest answer names its binding limits (the note),
# as solve prints them.
run render "$S/default.yaml" --correction 30,0,0,0,0,0 --dry-run
expect_exit 0 "render --dry-run of a closest plan"
expect_stdout_has "closest: binding side_fore_left pressure_min" "render shows the closest note"

# A trace of quaternions as a tracker prints them (five decimals: a 1 degree pitch is
# 0.99996, 0.00873) was refused by a 1e-6 norm check. Accepted within 1e-3 and normalised;
# a quaternion off by more (0.5, 0.5, 0, 0: norm 0.71) is still no rotation.
DIR='# headplan-trace: rows=deviation'
printf '%s\nt_s,x_mm,y_mm,z_mm,qw,qx,qy,qz\n0,0,0,0,0.99996,0.00873,0,0\n' "$DIR" >"$TMP/q5.csv"
run batch "$S/default.yaml" "$TMP/q5.csv" --format csv --no-progress
expect_exit 0 "batch, a five-decimal quaternion"
printf '%s\nt_s,x_mm,y_mm,z_mm,qw,qx,qy,qz\n0,0,0,0,0.5,0.5,0,0\n' "$DIR" >"$TMP/qbad.csv"
run batch "$S/default.yaml" "$TMP/qbad.csv" --format csv --no-progress
expect_exit 65 "batch, a quaternion of norm 0.71"
expect_stderr_has "qbad.csv:3: quaternion: norm 0.707106781 is not 1 (within 0.001): not a rotation" "quaternion refused by name"

# solve printed an error of 0 on an axis the layout cannot command (a sphere head nodding):
# achieved 0, desired 2 deg. The error is achieved - desired, marked uncommanded; --json
# carries the same error.
run solve "$S/sphere_head.yaml" --correction 1,0,0,2,0,0
expect_exit 2 "solve, an uncommanded pitch"
grep -Eq '^pitch_deg +2\.000000 +0\.000000 +-2 +2\.000000  \(uncommanded\)$' "$TMP/out" && ok || bad "solve: the pitch row shows error -2, marked uncommanded"
grep -Eq '^x_mm +1\.000000 +1\.000000 +0 +0\.000000$' "$TMP/out" && ok || bad "solve: a met axis has no mark"
run solve "$S/sphere_head.yaml" --correction 1,0,0,2,0,0 --json
expect_exit 2 "solve --json, an uncommanded pitch"
python3 - "$TMP/out" <<'PY' && ok || bad "solve --json: error = achieved - desired"
import json, sys
o = json.load(open(sys.argv[1]))
for k in o["desired"]:
    assert abs(o["error"][k] - (o["achieved"][k] - o["desired"][k])) < 1e-12, k
assert abs(o["error"]["pitch_deg"] + 2) < 1e-12, o["error"]
assert o["uncommanded_directions"] == ["pitch_deg"], o
PY

# fit layout --plot without gnuplot hinted at --dry-run, an option fit refuses: the hint
# names only what fit has.
E="$HP_SRC/examples/calibration"
mkdir -p "$TMP/nognuplot"
PATH="$TMP/nognuplot" "$HP_BIN" fit layout "$S/default.yaml" "$E/layout_rows.csv" \
    --plot "$TMP/n.png" >"$TMP/out" 2>"$TMP/err"; rc=$?
expect_exit 69 "fit layout --plot without gnuplot"
expect_stderr_has "gnuplot not found on PATH (install gnuplot-nox)" "fit: gnuplot named"
grep -q -- '--dry-run' "$TMP/err" && bad "fit's message names --dry-run, which fit refuses" || ok
run fit layout "$S/default.yaml" "$E/layout_rows.csv" --dry-run
expect_exit 64 "fit has no --dry-run"
# render and plot have --dry-run, and their hint still names it.
PATH="$TMP/nognuplot" "$HP_BIN" render "$S/default.yaml" -o "$TMP/r.png" >"$TMP/out" 2>"$TMP/err"; rc=$?
expect_exit 69 "render without gnuplot"; expect_stderr_has "--dry-run writes the script without it" "render's hint"

# fit material on radii written in cm under an ri_mm header answered exit 0 with a fit
# 1.28 m RMS off the data. A fit that does not fit is refused (65), naming the unit.
awk -F, '/^#/ || /^pressure/ {next} {printf "%s,%.5f\n", $1, $2 / 10}' "$E/material_ri.csv" > "$TMP/body"
{ echo "pressure_pa,ri_mm"; cat "$TMP/body"; } > "$TMP/cm.csv"
run fit material "$TMP/cm.csv" --Ri-mm 27 --Ro-mm 30
expect_exit 65 "fit material, radii in cm"; expect_stdout_empty "fit material, radii in cm"
expect_stderr_has "the fit misses the data: residual RMS" "misfit named"
expect_stderr_has "check their unit (mm; a radius in cm reads 10x too small)" "unit hinted"

# fit material - and fit layout SCENE - did not read DATA from standard input ("-: cannot
# open"). They do now, as the other commands read '-', naming it <stdin>; the answers equal
# those from the file, and both of layout's inputs cannot be standard input at once.
run fit material "$E/material_ri.csv" --Ri-mm 27 --Ro-mm 30 --json
expect_exit 0 "fit material FILE"; cp "$TMP/out" "$TMP/mat_file.json"
"$HP_BIN" fit material - --Ri-mm 27 --Ro-mm 30 --json < "$E/material_ri.csv" >"$TMP/out" 2>"$TMP/err"; rc=$?
expect_exit 0 "fit material -"
python3 - "$TMP/mat_file.json" "$TMP/out" <<'PY' && ok || bad "fit material - differs from the file's fit"
import json, sys
a, b = (json.load(open(p)) for p in sys.argv[1:])
assert b["data"] == "<stdin>", b["data"]
for k in ("C1_pa", "C2_pa"):
    assert a[k] == b[k], (k, a[k], b[k])
PY
printf 'pressure_pa,ri_mm\n1000,27.5\n2000,x\n' | "$HP_BIN" fit material - --Ri-mm 27 --Ro-mm 30 >"$TMP/out" 2>"$TMP/err"; rc=$?
expect_exit 65 "fit material - with a bad row"; expect_stderr_has "<stdin>:3:" "bad row named on <stdin>"
run fit layout "$S/default.yaml" "$E/layout_rows.csv" --json
expect_exit 0 "fit layout FILE"; cp "$TMP/out" "$TMP/lay_file.json"
"$HP_BIN" fit layout "$S/default.yaml" - --json < "$E/layout_rows.csv" >"$TMP/out" 2>"$TMP/err"; rc=$?
expect_exit 0 "fit layout SCENE -"
python3 - "$TMP/lay_file.json" "$TMP/out" <<'PY' && ok || bad "fit layout - differs from the file's fit"
import json, sys
a, b = (json.load(open(p)) for p in sys.argv[1:])
assert b["data"] == "<stdin>", b["data"]
assert a["parameters"] == b["parameters"]
PY
"$HP_BIN" fit layout - - < "$S/default.yaml" >"$TMP/out" 2>"$TMP/err"; rc=$?
expect_exit 64 "fit layout - -"; expect_stdout_empty "fit layout - -"

# fit layout printed the standard error along the weakest combination in "mm" when that
# combination is the carried mass: 1.899 "mm" for 0.0019 kg. The unit follows the direction.
sed 's/carried_fraction: 0.8/carried_fraction: 0.68/' "$E/load_supine_cap.yaml" > "$TMP/load.yaml"
run fit layout "$TMP/load.yaml" "$E/load_rows.csv" --fit mass --sigma-mm 0.05 --sigma-deg 0.05
expect_exit 0 "fit layout, the mass alone"
grep -Eq 'weakest combination \(SE 0\.00[0-9]+ kg along it\): \+1\.00 mass' "$TMP/out" && ok || bad "the mass's SE in kg"
run fit layout "$TMP/load.yaml" "$E/load_rows.csv" --fit mass --sigma-mm 0.05 --sigma-deg 0.05 --json
python3 - "$TMP/out" <<'PY' && ok || bad "JSON: weakest SE in kg equals the mass's SE"
import json, sys
o = json.load(open(sys.argv[1]))
assert o["weakest_se_unit"] == "kg", o["weakest_se_unit"]
assert abs(o["weakest_se"] - o["carried_mass"]["se_kg"]) <= 1e-9 * o["weakest_se"], o
PY
run fit layout "$S/default.yaml" "$E/layout_rows.csv" --json
python3 - "$TMP/out" <<'PY' && ok || bad "JSON: a direction of lengths keeps mm"
import json, sys
o = json.load(open(sys.argv[1]))
assert o["weakest_se_unit"] == "mm" and o["weakest_se"] > 0, o
PY

# A scene without model: planned at linear, saying nothing. It is planned at auto, and
# solve says which level auto chose and why (the error bounds against the tolerance); a
# stated level gets no such line.
grep -v '^model:' "$S/default.yaml" | sed "s#traces/#$S/traces/#" > "$TMP/nomodel.yaml"
run solve "$TMP/nomodel.yaml"
expect_exit 0 "solve, a scene without model"
expect_stdout_has "(contact level surface)" "planned at auto's level"
expect_stdout_has "level choice: auto chose surface: the error bounds of linear (" "the choice and why"
expect_stdout_has "exceed model.tolerance_mm 0.01 for corrections up to 10 mm, 5 deg" "the tolerance and range named"
run solve "$TMP/nomodel.yaml" --json
python3 - "$TMP/out" <<'PY' && ok || bad "solve --json: level_choice"
import json, sys
o = json.load(open(sys.argv[1]))
assert o["level"] == "surface" and o["level_choice"].startswith("auto chose surface"), o["level_choice"]
PY
run solve "$TMP/nomodel.yaml" --level plane
expect_exit 0 "solve --level plane"
grep -q 'level choice' "$TMP/out" && bad "a stated level explained as auto's choice" || ok

finish
