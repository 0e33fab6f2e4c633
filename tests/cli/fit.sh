# headplan fit: calibration from measurements (docs/calibration.md). The example data of
# examples/calibration/ (written by make_data.py from known parameters, stated in each file's
# comments) are fitted; the JSON is checked for its own consistency (interval = value ± t·SE
# with Student's t, C10 = C1/2) and against the truth within 4 standard errors (a 95 %
# interval misses 1 time in 20 by design; the cmocka coverage tests measure that rate, so
# here a miss beyond 4 SE, probability 6e-5, is the failure). The calibrated scene loads,
# analyses and solves. Bad inputs exit 64/65/66/73 with stdout empty and file:line:col.
source "$2/tests/cli_lib.sh"
E="$HP_SRC/examples/calibration"
S="$HP_SRC/scenarios"

# ---- material, inner and outer radius, JSON ------------------------------------------------
for f in material_ri material_ro; do
    run fit material "$E/$f.csv" --Ri-mm 27 --Ro-mm 30 --json
    expect_exit 0 "$f --json"
    python3 - "$TMP/out" <<'PY' && ok || bad "$f JSON"
import json, sys
d = json.load(open(sys.argv[1]))
assert d["points"] == 12 and d["dof"] == 10, d
t = d["t975"]
assert abs(t - 2.228138851986) < 1e-9, t            # Student's t(0.975, 10), printed tables
for k, truth in (("C1_pa", 12500.0), ("C2_pa", 19000.0)):
    p = d[k]
    lo, hi = p["ci95"]
    assert abs(lo - (p["value"] - t * p["se"])) <= 1e-9 * p["value"], (k, p)
    assert abs(hi - (p["value"] + t * p["se"])) <= 1e-9 * p["value"], (k, p)
    assert abs(p["value"] - truth) < 4 * p["se"], (k, p, truth)
assert abs(d["C10_pa"] - d["C1_pa"]["value"] / 2) <= 1e-12 * d["C10_pa"]
assert abs(d["C01_pa"] - d["C2_pa"]["value"] / 2) <= 1e-12 * d["C01_pa"]
assert -1 < d["correlation"] < -0.9, d["correlation"]   # the two moduli trade off
assert len(d["residuals"]) == 12 and d["residuals"][0]["line"] == 5
assert d["scene_fragment"]["convention"] == "paper"
assert all(0 < c["se_ratio_C1"] <= 1 for c in d["next_point"])
PY
done

run fit material "$E/material_ri.csv" --Ri-mm 27 --Ro-mm 30
expect_exit 0 "material text"
expect_stdout_has "C10 =" "text shows the FE convention"
expect_stdout_has "material: {convention: paper, C1_pa:" "text ends with a scene fragment"
expect_stdout_has "residuals (measured - fitted)" "text has the residual table"

run fit material "$E/material_ri.csv" --Ri-mm 27 --Ro-mm 30 --plot "$TMP/res.svg"
expect_exit 0 "material --plot"
python3 - "$TMP/res.svg" <<'PY' && ok || bad "residual chart: well-formed SVG, one dot per point"
import sys, xml.dom.minidom as m
d = m.parse(sys.argv[1])
assert d.documentElement.tagName == "svg"
assert len(d.getElementsByTagName("circle")) == 12
PY
run fit material "$E/material_ri.csv" --Ri-mm 27 --Ro-mm 30 --plot "$TMP/no/dir/res.svg"
expect_exit 73 "--plot unwritable"; expect_stdout_empty "--plot unwritable"
# The chart is SVG (written without gnuplot): its file starts as one, and another name is
# refused by name (64) instead of getting SVG bytes under a .png name.
[ "$(head -c 4 "$TMP/res.svg")" = "<svg" ] && ok || bad "material --plot: SVG magic"
for name in res.png res.PNG res res.svg.txt; do
  run fit material "$E/material_ri.csv" --Ri-mm 27 --Ro-mm 30 --plot "$TMP/$name"
  expect_exit 64 "material --plot $name"
  expect_stderr_has "--plot: '$TMP/$name' must end in .svg" "material --plot $name"
  [ ! -e "$TMP/$name" ] && ok || bad "material --plot $name: a file was written"
done

# ---- material with a reference radius fitted (--fit-ref) ------------------------------------
run fit material "$E/material_ro.csv" --Ri-mm 27 --Ro-mm 29.5 --fit-ref Ro --json
expect_exit 0 "--fit-ref Ro"
python3 - "$TMP/out" <<'PY' && ok || bad "--fit-ref Ro JSON: Ro within its interval, t with 9 dof"
import json, sys
d = json.load(open(sys.argv[1]))
assert d["dof"] == 9, d["dof"]
t = d["t975"]
assert abs(t - 2.262157162799) < 1e-9, t            # Student's t(0.975, 9), printed tables
R = d["fitted_Ro_mm"]
lo, hi = R["ci95"]
assert abs(lo - (R["value"] - t * R["se"])) < 1e-9 and abs(hi - (R["value"] + t * R["se"])) < 1e-9
assert lo < 30.0 < hi, R                              # the data were made with Ro = 30 mm
assert abs(R["value"] - 30.0) < 4 * R["se"] and R["se"] < 0.05, R
assert abs(d["C1_pa"]["value"] - 12500) < 4 * d["C1_pa"]["se"]
assert d["Ro_mm"] == R["value"]                       # the bladder reported is the fitted one
PY
run fit material "$E/material_ri.csv" --Ri-mm 27.5 --Ro-mm 30 --fit-ref Ri
expect_exit 0 "--fit-ref Ri text"
expect_stdout_has "Ri  = 27.00" "fitted Ri printed"; expect_stdout_has "  Ri_mm: 27.00" "Ri in the fragment"
{ echo "pressure_pa,ri_mm,sigma_mm"; for r in 29.3309 29.3409 29.3209; do echo "2363.6,$r,0.02"; done
  for r in 34.2477 34.2377 34.2577; do echo "5090.9,$r,0.02"; done; } > "$TMP/two_p.csv"
run fit material "$TMP/two_p.csv" --Ri-mm 27 --Ro-mm 30
expect_exit 0 "two pressures determine the moduli"
run fit material "$TMP/two_p.csv" --Ri-mm 27 --Ro-mm 30 --fit-ref Ro
expect_exit 65 "--fit-ref with two pressures"; expect_stdout_empty "--fit-ref two pressures"
expect_stderr_has "cannot determine Ro: the points give 2 equations for 3 unknowns" "Ro named"
run fit material "$E/material_ri.csv" --Ri-mm 27 --Ro-mm 30 --fit-ref Rx
expect_exit 64 "--fit-ref Rx"; expect_stderr_has "--fit-ref: 'Rx': use Ri or Ro" "bad --fit-ref named"

# ---- material refusals -----------------------------------------------------------------
printf 'pressure_pa,ri_mm\n2000,29\n2000,29.01\n2000,28.99\n' > "$TMP/one.csv"
run fit material "$TMP/one.csv" --Ri-mm 27 --Ro-mm 30
expect_exit 65 "one pressure"; expect_stdout_empty "one pressure"
expect_stderr_has "only one non-zero pressure" "one pressure named"
printf 'pressure_pa,ri_mm\n1000,28\n2000,nan\n3000,30\n' > "$TMP/nan.csv"
run fit material "$TMP/nan.csv" --Ri-mm 27 --Ro-mm 30
expect_exit 65 "nan radius"; expect_stderr_has "$TMP/nan.csv:3:6: ri_mm: 'nan'" "nan file:line:col"
printf 'pressure_pa,ri_mm\n1000,28\n2000,-29\n3000,30\n' > "$TMP/neg.csv"
run fit material "$TMP/neg.csv" --Ri-mm 27 --Ro-mm 30
expect_exit 65 "negative radius"; expect_stderr_has "neg.csv:3:6: ri_mm: must be > 0" "negative named"
printf 'pressure_pa,ri_mm\n1000,28\n2000\n' > "$TMP/cols.csv"
run fit material "$TMP/cols.csv" --Ri-mm 27 --Ro-mm 30
expect_exit 65 "column count"; expect_stderr_has "cols.csv:3:1: 1 columns, the header has 2" "cols"
run fit material "$E/material_ri.csv" --Ri-mm 27
expect_exit 64 "no Ro"; expect_stderr_has "--Ro-mm" "no Ro named"
run fit material "$E/material_ri.csv" --Ri-mm 31 --Ro-mm 30
expect_exit 64 "Ri > Ro"
run fit material "$TMP/missing.csv" --Ri-mm 27 --Ro-mm 30
expect_exit 66 "missing data"; expect_stdout_empty "missing data"
run fit material "$E/material_ri.csv" --Ri-mm 27 --Ro-mm 30 --bogus
expect_exit 64 "unknown option"
run fit
expect_exit 64 "fit alone"
run fit colour
expect_exit 64 "unknown fit"
run fit --help
expect_exit 0 "fit --help"; expect_stdout_has "headplan fit layout" "help text"

# ---- layout ------------------------------------------------------------------------------
run fit layout "$S/default.yaml" "$E/layout_rows.csv" --sigma-mm 0.05 --sigma-deg 0.05 \
    -o "$TMP/cal.yaml" --json
expect_exit 0 "layout -o --json"
cp "$TMP/out" "$TMP/layout.json"
python3 - "$TMP/layout.json" "$E/layout_rows.csv" <<'PY' && ok || bad "layout JSON"
import json, sys
d = json.load(open(sys.argv[1]))
truth = {}
for line in open(sys.argv[2]):
    if line.startswith("# truth: semi_axes_mm="):
        for ax, v in zip("xyz", line.split("=")[1].split()):
            truth["semi_axis_" + ax] = float(v)
    if line.startswith("# truth: offsets_mm="):
        offs = [float(v) for v in line.split("=")[1].split()]
names = ["base_neck_left", "base_neck_right", "base_skull_left", "base_skull_right",
         "side_fore_left", "side_fore_right", "side_chin_left", "side_chin_right"]
truth.update({"offset:" + n: o for n, o in zip(names, offs)})
assert d["rows"] == 24 and d["level"] == "surface" and d["rank"] == 11, d
assert d["undetermined"] == []
for p in d["parameters"]:
    assert p["status"] == "fitted", p
    lo, hi = p["ci95_mm"]
    assert abs(p["fitted_mm"] - truth[p["name"]]) < 4 * p["se_mm"], (p, truth[p["name"]])
    assert lo < p["fitted_mm"] < hi
for k in d["rms_before"]:
    assert d["rms_after"][k] < d["rms_before"][k], k
# The weakest direction: the head's size against all bladders' common offset.
assert all(w > 0.2 for w in d["weakest_direction"]), d["weakest_direction"]
assert all(0 < g["se_ratio"] < 1 for g in d["repeat_row_gain"])
PY
run fit layout "$S/default.yaml" "$E/layout_rows.jsonl" --sigma-mm 0.05 --sigma-deg 0.05 --json
expect_exit 0 "layout from JSON Lines"
python3 - "$TMP/layout.json" "$TMP/out" <<'PY' && ok || bad "JSON Lines rows fit exactly as the CSV rows"
import json, sys
a, b = json.load(open(sys.argv[1])), json.load(open(sys.argv[2]))
for d in (a, b):
    del d["data"]; d["output"] = None
    for g in d["repeat_row_gain"]:
        del g["line"]                                       # the files number lines apart
assert a == b
PY
run analyze "$TMP/cal.yaml"
expect_exit 0 "calibrated scene analyses"
run solve "$TMP/cal.yaml" --correction 0.5,0,-0.3,0.2,0,0
expect_exit 0 "calibrated scene solves (reached)"
run solve "$TMP/cal.yaml"
expect_exit 0 "calibrated scene keeps the input's correction"
grep -q "^model: {level: auto, tolerance_mm: 0.01" "$TMP/cal.yaml" && ok || bad "model section copied"
grep -q "^solver: {backend: realtime" "$TMP/cal.yaml" && ok || bad "solver section copied"

run fit layout "$S/default.yaml" "$E/layout_rows.csv" --fit offsets --level linear
expect_exit 0 "offsets only, linear"
expect_stdout_has "(not fitted)" "axes not asked for"
expect_stdout_has "not determined by these data (held at the scene's value): offset:side_chin_left offset:side_chin_right" "linear level names the two undetermined offsets"

# ---- layout at the load level: the carried mass through the forward statics ---------------
# load_rows.csv: rests of examples/calibration/load_supine_cap.yaml carrying 3.0 kg (make_load_rows.c); the
# fit starts from a scene carrying 0.68 * 4.5 = 3.06 kg.
sed 's/carried_fraction: 0.8,/carried_fraction: 0.68,/' "$E/load_supine_cap.yaml" > "$TMP/load.yaml"
run fit layout "$TMP/load.yaml" "$E/load_rows.csv" --fit mass --sigma-mm 0.05 --sigma-deg 0.05 \
    --json -o "$TMP/load_cal.yaml"
expect_exit 0 "load level, mass"
python3 - "$TMP/out" "$TMP/load_cal.yaml" <<'PY' && ok || bad "load level: the mass within its interval, written as the load"
import json, re, sys
d = json.load(open(sys.argv[1]))
assert d["model"] == "forward statics", d["model"]
m = d["carried_mass"]
assert m["status"] == "fitted" and abs(m["scene_kg"] - 3.06) < 1e-12, m
lo, hi = m["ci95_kg"]
assert lo < 3.0 < hi and abs(m["fitted_kg"] - 3.0) < 4 * m["se_kg"], m
assert hi < 3.06, m                                   # the data rule the start out
assert 0.8 < d["s_unit_weight"] < 1.25, d["s_unit_weight"]
f = float(re.search(r"carried_fraction: ([0-9.eE+-]+)", open(sys.argv[2]).read()).group(1))
assert abs(f * 4.5 - m["fitted_kg"]) < 1e-9 * 4.5, (f, m)
PY
run analyze "$TMP/load_cal.yaml"
expect_exit 0 "the calibrated load scene analyses"
run fit layout "$TMP/load.yaml" "$E/load_rows.csv" --sigma-mm 0.05 --sigma-deg 0.05
expect_exit 70 "load level, mass with offsets and axes"; expect_stdout_empty "stalled"
expect_stderr_has "the fit stalled" "a stalled search is refused, never answered with the start"
run fit layout "$S/default.yaml" "$E/layout_rows.csv" --fit offsets,mass --sigma-mm 0.05 --sigma-deg 0.05
expect_exit 0 "mass without a load"
expect_stdout_has "mass: the scene has no load section" "no load: the mass named as not determinable"
run fit layout "$S/default.yaml" "$E/layout_rows.csv" --fit offsets,mass --json
python3 - "$TMP/out" <<'PY' && ok || bad "no load: mass undetermined in JSON"
import json, sys
d = json.load(open(sys.argv[1]))
assert "mass" in d["undetermined"] and d["carried_mass"]["status"] == "undetermined", d
assert d["carried_mass"]["fitted_kg"] is None and d["carried_mass"]["ci95_kg"] is None
assert d["model"] == "contact kinematics"
PY
run fit layout "$S/default.yaml" "$E/layout_rows.csv" --fit offsets,weight
expect_exit 64 "--fit weight"; expect_stderr_has "a comma list of offsets, axes, mass" "--fit list named"

# ---- layout residual plot (gnuplot): the picture is drawn, the script redraws it and holds
# every row's residuals, whose RMS per axis is the fit's own rms_before / rms_after ----------
run fit layout "$S/default.yaml" "$E/layout_rows.csv" --sigma-mm 0.05 --sigma-deg 0.05 \
    --plot "$TMP/res.png" --plot-script "$TMP/res.gp"
expect_exit 0 "layout --plot"
[ -s "$TMP/res.png" ] && [ "$(head -c 4 "$TMP/res.png" | tail -c 3)" = PNG ] && ok || bad "layout plot: no PNG"
python3 - "$TMP/res.gp" "$TMP/layout.json" <<'PY' && ok || bad "layout plot script: data = the fit's residuals"
import json, math, re, sys
gp, fit = open(sys.argv[1]).read(), json.load(open(sys.argv[2]))
blocks = re.findall(r"\$axis(\d) << EOD\n(.*?)EOD\n", gp, re.S)
assert [int(b[0]) for b in blocks] == list(range(6)), blocks
keys = ["x_mm", "y_mm", "z_mm", "pitch_deg", "roll_deg", "yaw_deg"]
for j, body in blocks:
    rows = [list(map(float, l.split())) for l in body.splitlines() if not l.startswith("#")]
    assert len(rows) == 24 and rows[0][0] == 6 and rows[-1][0] == 29, rows
    for col, which in ((1, "rms_before"), (2, "rms_after")):
        rms = math.sqrt(sum(r[col] ** 2 for r in rows) / len(rows))
        want = fit[which][keys[int(j)]]
        assert abs(rms - want) <= 1e-6 * want, (j, which, rms, want)
assert gp.count("plot $axis") == 6 and "set multiplot layout 2,3" in gp and "unset multiplot" in gp
PY
sed "s#^set output .*#set output '$TMP/again.svg'#; s#^  set terminal pngcairo.*#  set terminal svg#" \
    "$TMP/res.gp" > "$TMP/again.gp"
LC_ALL=C.UTF-8 gnuplot "$TMP/again.gp" 2>"$TMP/err" && [ ! -s "$TMP/err" ] && [ -s "$TMP/again.svg" ] && ok || bad "the kept script does not redraw cleanly"
run fit layout "$S/default.yaml" "$E/layout_rows.csv" --plot "$TMP/res.jpg"
expect_exit 64 "--plot not png/svg"; expect_stderr_has "must end in .png or .svg" "--plot name"
run fit layout "$S/default.yaml" "$E/layout_rows.csv" --plot-script "$TMP/x.gp"
expect_exit 64 "--plot-script alone"
run fit layout "$S/default.yaml" "$E/layout_rows.csv" --plot "$TMP/no/dir/res.png"
expect_exit 73 "--plot unwritable"; expect_stdout_empty "--plot unwritable"
mkdir -p "$TMP/nognuplot"
PATH="$TMP/nognuplot" "$HP_BIN" fit layout "$S/default.yaml" "$E/layout_rows.csv" \
    --plot "$TMP/n.png" -o "$TMP/n.yaml" >"$TMP/out" 2>"$TMP/err"; rc=$?
expect_exit 69 "layout --plot without gnuplot"; expect_stderr_has "gnuplot not found" "no gnuplot named"
expect_stdout_empty "no gnuplot"
[ ! -e "$TMP/n.png" ] && [ ! -e "$TMP/n.yaml" ] && ok || bad "without gnuplot something was written"
PATH="$TMP/nognuplot" "$HP_BIN" fit layout "$S/default.yaml" "$E/layout_rows.csv" >"$TMP/out" 2>"$TMP/err"; rc=$?
expect_exit 0 "layout without gnuplot and without --plot"

# ---- layout refusals ---------------------------------------------------------------------
# -o never replaces an input, a symbolic link, a FIFO or a device: exit 73, one line on
# stderr, nothing on stdout, the target as it was (batch's -o is held to the same rule).
one_line() { [ "$(wc -l <"$TMP/err")" -eq 1 ] && ok || bad "$1: stderr is not one line"; }
cp "$E/layout_rows.csv" "$TMP/rows.csv"; cp "$S/default.yaml" "$TMP/scene.yaml"
run fit layout "$TMP/scene.yaml" "$TMP/rows.csv" -o "$TMP/rows.csv"
expect_exit 73 "-o the data"; expect_stderr_has "is an input" "over the data named"
expect_stdout_empty "-o the data"; one_line "-o the data"
cmp -s "$TMP/rows.csv" "$E/layout_rows.csv" && ok || bad "-o the data changed it"
run fit layout "$TMP/scene.yaml" "$TMP/rows.csv" -o "$TMP/scene.yaml"
expect_exit 73 "-o the scene"; one_line "-o the scene"
cmp -s "$TMP/scene.yaml" "$S/default.yaml" && ok || bad "-o the scene changed it"
ln -s "$TMP/scene.yaml" "$TMP/scene_link.yaml"
run fit layout "$TMP/scene_link.yaml" "$TMP/rows.csv" -o "$TMP/scene.yaml"
expect_exit 73 "-o the scene read through a link"
cmp -s "$TMP/scene.yaml" "$S/default.yaml" && ok || bad "-o the linked scene changed it"
ln -s "$TMP/nowhere.yaml" "$TMP/dangling.yaml"
run fit layout "$TMP/scene.yaml" "$TMP/rows.csv" -o "$TMP/dangling.yaml"
expect_exit 73 "-o a symlink"; expect_stderr_has "symbolic link" "symlink named"
expect_stdout_empty "-o a symlink"; one_line "-o a symlink"
[ ! -e "$TMP/nowhere.yaml" ] && [ -L "$TMP/dangling.yaml" ] && ok || bad "-o a symlink wrote"
ln -s "$TMP/other.yaml" "$TMP/live.yaml"; echo "keep" > "$TMP/other.yaml"
run fit layout "$TMP/scene.yaml" "$TMP/rows.csv" -o "$TMP/live.yaml"
expect_exit 73 "-o a live symlink"
[ -L "$TMP/live.yaml" ] && [ "$(cat "$TMP/other.yaml")" = keep ] && ok || bad "-o wrote through a link"
mkfifo "$TMP/fifo.yaml"
run fit layout "$TMP/scene.yaml" "$TMP/rows.csv" -o "$TMP/fifo.yaml"
expect_exit 73 "-o a FIFO"; expect_stderr_has "not a regular file" "FIFO named"
expect_stdout_empty "-o a FIFO"; one_line "-o a FIFO"
[ -p "$TMP/fifo.yaml" ] && ok || bad "-o replaced a FIFO"
run fit layout "$TMP/scene.yaml" "$TMP/rows.csv" -o /dev/null
expect_exit 73 "-o a device"; expect_stdout_empty "-o a device"; one_line "-o a device"
[ -c /dev/null ] && ok || bad "-o replaced /dev/null"
run fit layout "$TMP/scene.yaml" "$TMP/rows.csv" -o "$TMP"
expect_exit 73 "-o a directory"; one_line "-o a directory"
ls "$TMP" | grep -q '\.tmp' && bad "-o left a temporary file" || ok
run fit layout "$S/default.yaml" "$E/layout_rows.csv" -o "$TMP/no/such/dir/out.yaml"
expect_exit 73 "-o unwritable"; expect_stdout_empty "-o unwritable"
head -5 "$E/layout_rows.csv" > "$TMP/short.csv"
echo "1,2,3" >> "$TMP/short.csv"
run fit layout "$S/default.yaml" "$TMP/short.csv"
expect_exit 65 "short row"; expect_stderr_has "short.csv:6:1: 3 columns, the header has 14" "short row named"
run fit layout "$S/default.yaml" "$E/material_ri.csv"
expect_exit 65 "wrong header"; expect_stderr_has "material_ri.csv:4:1: header: unknown column 'pressure_pa'" "header named"
run fit layout "$S/missing.yaml" "$E/layout_rows.csv"
expect_exit 66 "missing scene"
run fit layout "$S/default.yaml" "$E/layout_rows.csv" --fit everything
expect_exit 64 "bad --fit"
run fit layout "$S/default.yaml" "$E/layout_rows.csv" --sigma-mm -1
expect_exit 64 "bad --sigma-mm"
run fit layout "$S/default.yaml"
expect_exit 64 "no data"
finish
