# headplan render and headplan plot: the gnuplot script and data they write (--dry-run,
# --script-out) checked against headplan solve --json and headplan batch on the same scene,
# and the pictures: a PNG of the stated size (its IHDR header), an SVG of the stated size.
# Without gnuplot on PATH both fail with 69 while the rest of the program works.
source "$2/tests/cli_lib.sh"
S="$HP_SRC/scenarios"

# ---- render: script and data against solve --------------------------------------------
"$HP_BIN" solve "$S/saturation.yaml" --json >"$TMP/sat.json"; src=$?
[ "$src" -eq 1 ] && ok || bad "saturation solve: exit $src, want 1 (closest)"
run render "$S/saturation.yaml" --dry-run
expect_exit 0 "render --dry-run"
cp "$TMP/out" "$TMP/sat.gp"
python3 - "$TMP/sat.gp" "$TMP/sat.json" <<'PY' && ok || bad "render script: data equal solve's plan"
import json, math, re, sys
gp = open(sys.argv[1]).read()
sol = json.load(open(sys.argv[2]))
bl = sol["bladders"]
# One commented grid per bladder: its pressure (kPa) and outer radius as solve gives them.
heads = re.findall(r"^# (\d+) (\S+): pressure (\S+) kPa, outer radius (\S+) mm$", gp, re.M)
assert [h[1] for h in heads] == [b["name"] for b in bl], heads
for (k, name, kpa, ro), b in zip(heads, bl):
    assert float(kpa) == float("%.6g" % (b["pressure_pa"] / 1000)), (name, kpa)
    assert float(ro) == float("%.6g" % b["ro_mm"]), (name, ro)
# Every grid point lies on its sphere (4 decimals printed: 1e-3 mm) and carries the colour.
block = gp.split("$bladders << EOD\n")[1].split("EOD\n")[0]
pts = {}
for line in block.splitlines():
    if line and not line.startswith("#"):
        x, y, z, c, k = line.split()
        pts.setdefault(int(k), []).append((float(x), float(y), float(z), float(c)))
assert sorted(pts) == list(range(1, len(bl) + 1))
for k, b in enumerate(bl, 1):
    cx, cy, cz = b["center_mm"]
    for x, y, z, c in pts[k]:
        assert abs(math.dist((x, y, z), (cx, cy, cz)) - b["ro_mm"]) < 2e-3, (k, x, y, z)
        assert c == float("%.6g" % (b["pressure_pa"] / 1000))
    assert len(pts[k]) == 13 * 25
# Binding bladders are circled in red; the others are not.
circles = sorted(int(m) for m in re.findall(r"^set object (\d+) circle", gp, re.M))
assert circles == [k for k, b in enumerate(bl, 1) if b["binding"]], circles
assert circles, "saturation binds a limit"
# The colour scale spans the pressure limits in kPa, white at zero.
lo = min(b["pressure_min_pa"] for b in bl) / 1000
hi = max(b["pressure_max_pa"] for b in bl) / 1000
assert "set cbrange [%g:%g]" % (lo, hi) in gp
assert "set cblabel 'pressure [kPa]'" in gp
assert gp.count("\nsplot ") == 2          # two views
PY

# ---- render: PNG and SVG of the stated size --------------------------------------------
png_size() { python3 -c "
import struct, sys
b = open(sys.argv[1], 'rb').read(24)
assert b[:8] == b'\x89PNG\r\n\x1a\n' and b[12:16] == b'IHDR', 'not a PNG'
print('%dx%d' % struct.unpack('>II', b[16:24]))" "$1"; }
run render "$S/default.yaml" -o "$TMP/d.png" --size 900x500 --script-out "$TMP/d.gp"
expect_exit 0 "render png"
expect_stdout_empty "render png"
[ "$(png_size "$TMP/d.png")" = "900x500" ] && ok || bad "render png size: $(png_size "$TMP/d.png")"
[ "$(stat -c %s "$TMP/d.png")" -gt 20000 ] && ok || bad "render png: too small to hold a picture"
grep -q "set terminal pngcairo size 900,500" "$TMP/d.gp" && ok || bad "script-out lacks the terminal"
run render "$S/default.yaml" --correction 0,0,2,0,0,0 -o "$TMP/d.svg" --size 800x600
expect_exit 0 "render svg"
grep -q 'width="800"' "$TMP/d.svg" && grep -q 'height="600"' "$TMP/d.svg" && ok || bad "svg size"
grep -Eq "z_mm +2\.0000 +2\.0000" "$TMP/d.svg" && ok || bad "svg: the desired z of --correction"

# ---- plot: script and data against the batch result ------------------------------------
"$HP_BIN" batch --format csv "$S/saturation.yaml" "$HP_SRC/tests/cli/render_plot_jumps.csv" --no-times \
  --no-progress -o "$TMP/jumps.csv" 2>/dev/null
run plot "$TMP/jumps.csv" --scene "$S/saturation.yaml" --trace "$HP_SRC/tests/cli/render_plot_jumps.csv" --dry-run
expect_exit 0 "plot --dry-run"
cp "$TMP/out" "$TMP/jumps.gp"
python3 - "$TMP/jumps.gp" "$TMP/jumps.csv" "$HP_SRC/tests/cli/render_plot_jumps.csv" <<'PY' && ok || bad "plot script: data equal the batch result"
import csv, sys
gp = open(sys.argv[1]).read()
res = list(csv.DictReader(l for l in open(sys.argv[2]) if not l.startswith("#")))
trace = list(csv.DictReader(l for l in open(sys.argv[3]) if not l.startswith("#")))
keys = ["x_mm", "y_mm", "z_mm", "pitch_deg", "roll_deg", "yaw_deg"]
rows = [l.split() for l in gp.split("$rows << EOD\n")[1].split("EOD\n")[0].splitlines()
        if not l.startswith("#")]
assert len(rows) == len(res) == len(trace)
names = [k[:-len("_pressure_pa")] for k in res[0] if k.endswith("_pressure_pa")]
for r, o, t in zip(rows, res, trace):
    assert float(r[0]) == float(o["t_s"])
    for i, k in enumerate(keys):   # achieved - desired, printed with 10 digits
        assert abs(float(r[1 + i]) - (float(o["achieved_" + k]) - float(t[k]))) <= 1e-9 * max(1, abs(float(o["achieved_" + k]))), (o["line"], k)
    for j, n in enumerate(names):
        assert abs(float(r[7 + j]) - float(o[n + "_pressure_pa"]) / 1000) <= 1e-12 * 1e4
closest = [float(o["t_s"]) for o in res if o["status"] == "closest"]
marks = [float(l) for l in gp.split("$status1 << EOD\n")[1].split("EOD\n")[0].split()]
assert marks == closest and closest, (marks, closest)
assert "rect from graph 0, first -0.5 to graph 1, first 0.5" in gp      # the tolerance band
assert "-5 with lines dt 2" in gp and "10 with lines dt 2" in gp         # the limits, kPa
assert "%d rows: %d closest" % (len(res), len(closest)) in gp
PY
run plot "$TMP/jumps.csv" --scene "$S/saturation.yaml" --trace "$HP_SRC/tests/cli/render_plot_jumps.csv" -o "$TMP/j.png"
expect_exit 0 "plot png"
[ "$(png_size "$TMP/j.png")" = "1400x900" ] && ok || bad "plot png default size: $(png_size "$TMP/j.png")"
# Without a scene or trace: the per-axis errors come from the result's error_* columns (the
# same numbers), the limits are unknown.
run plot "$TMP/jumps.csv" --dry-run
expect_exit 0 "plot without scene"
grep -q "limits unknown" "$TMP/out" && grep -q "pose error \[mm or deg\]" "$TMP/out" && ok || bad "plot without scene: labels"

# ---- bad input ----------------------------------------------------------------------------
run render "$S/default.yaml" -o "$TMP/x.jpg";   expect_exit 64 "render .jpg"; expect_stderr_has "-o: '" ".jpg"
run render "$S/default.yaml";                   expect_exit 64 "render no -o"; expect_stderr_has "-o: missing" "no -o"
run render "$S/default.yaml" -o "$TMP/x.png" --size 10x10; expect_exit 64 "render --size"; expect_stderr_has "--size" "size"
run render "$S/default.yaml" -o "$TMP/x.png" --correction 1,2; expect_exit 64 "render --correction"
run render "$S/paper_expansion.yaml" -o "$TMP/x.png"; expect_exit 65 "render bladder scene"
run render "$TMP/none.yaml" -o "$TMP/x.png";    expect_exit 66 "render missing scene"
run render "$S/default.yaml" -o "$TMP/no/such/dir/x.png"; expect_exit 73 "render unwritable"
expect_stderr_has "x.png: cannot create: No such file or directory" "unwritable"
expect_stdout_empty "render unwritable"
run plot "$TMP/none.csv" -o "$TMP/x.png";       expect_exit 66 "plot missing result"
run plot "$S/default.yaml" -o "$TMP/x.png";     expect_exit 65 "plot not a CSV"; expect_stderr_has "not a headplan batch CSV" "plot yaml"
sed 's/base_neck_left/neck_l/' "$S/saturation.yaml" >"$TMP/renamed.yaml"
run plot "$TMP/jumps.csv" --scene "$TMP/renamed.yaml" -o "$TMP/x.png"; expect_exit 65 "plot wrong scene"
expect_stderr_has "not the scene $TMP/jumps.csv was planned with" "wrong scene by hash"
head -n 10 "$HP_SRC/tests/cli/render_plot_jumps.csv" >"$TMP/short.csv"
run plot "$TMP/jumps.csv" --trace "$TMP/short.csv" -o "$TMP/x.png"; expect_exit 65 "plot wrong trace"
expect_stderr_has "not the trace $TMP/jumps.csv was planned from" "wrong trace by hash"
# A result that states no hashes (a trace on a pipe; edited by hand) is still matched by
# bladder names and lines.
grep -v '_sha256: ' "$TMP/jumps.csv" > "$TMP/nohash.csv"
run plot "$TMP/nohash.csv" --scene "$TMP/renamed.yaml" -o "$TMP/x.png"; expect_exit 65 "plot wrong scene"
expect_stderr_has "has no bladder 'base_neck_left'" "wrong scene"
run plot "$TMP/nohash.csv" --trace "$TMP/short.csv" -o "$TMP/x.png"; expect_exit 65 "plot wrong trace"
expect_stderr_has "is it the trace the result was planned from" "wrong trace"

# ---- numbers at the ends of double: never "inf" in a script ---------------------------------
# A finite error of 1e308 and one of -1e308 made the axis range overflow to inf, written as
# "set yrange [-inf:inf]" (gnuplot: undefined variable, exit 70). Numbers beyond 1e300 in
# magnitude are refused by file:line; 1e300 itself draws.
edge() { # edge VALUE OUT: the first two rows' error_x_mm and error_y_mm set to VALUE, -VALUE
  python3 - "$1" "$TMP/jumps.csv" "$2" <<'PY2'
import sys
v, src, out = sys.argv[1:]
lines = open(src).read().split("\n")
h = next(i for i, l in enumerate(lines) if l and not l.startswith("#"))
cols = lines[h].split(",")
for k, (c, x) in enumerate([("error_x_mm", v), ("error_y_mm", "-" + v), ("t_s", v)]):
    row = lines[h + 1 + k].split(",")
    row[cols.index(c)] = x
    lines[h + 1 + k] = ",".join(row)
open(out, "w").write("\n".join(lines))
PY2
}
if command -v gnuplot >/dev/null; then
  edge 1e308 "$TMP/huge.csv"
  run plot "$TMP/huge.csv" -o "$TMP/huge.png" --size 400x300; expect_exit 65 "plot 1e308"
  expect_stderr_has "huge.csv:" "plot 1e308 names the file"
  expect_stderr_has "beyond 1e300" "plot 1e308 says why"
  [ ! -e "$TMP/huge.png" ] && ok || bad "plot 1e308: a picture was written"
  # a line number no long holds ((long)1e20 is undefined behaviour): refused, not cast
  python3 -c 'import sys; l = open(sys.argv[1]).read().split("\n"); h = next(i for i, x in enumerate(l) if x and x[0] != "#"); l[h + 1] = "1e20" + l[h + 1][l[h + 1].index(","):]; open(sys.argv[2], "w").write("\n".join(l))' "$TMP/jumps.csv" "$TMP/line.csv"
  run plot "$TMP/line.csv" -o "$TMP/line.png" --size 400x300; expect_exit 65 "plot line 1e20"
  expect_stderr_has "malformed row" "plot line 1e20"
  edge 1e300 "$TMP/edge.csv"
  run plot "$TMP/edge.csv" -o "$TMP/edge.png" --size 400x300; expect_exit 0 "plot 1e300"
  [ ! -s "$TMP/err" ] && ok || bad "plot 1e300 wrote to stderr"
fi

# ---- without gnuplot: 69 for render and plot, nothing else affected ------------------------
mkdir -p "$TMP/nognuplot"
PATH="$TMP/nognuplot" "$HP_BIN" render "$S/default.yaml" -o "$TMP/n.png" >"$TMP/out" 2>"$TMP/err"; rc=$?
expect_exit 69 "render without gnuplot"; expect_stderr_has "gnuplot not found" "no gnuplot"
[ ! -e "$TMP/n.png" ] && ok || bad "a picture appeared without gnuplot"
PATH="$TMP/nognuplot" "$HP_BIN" plot "$TMP/jumps.csv" -o "$TMP/n.png" >"$TMP/out" 2>"$TMP/err"; rc=$?
expect_exit 69 "plot without gnuplot"
PATH="$TMP/nognuplot" "$HP_BIN" render "$S/default.yaml" --dry-run >"$TMP/out" 2>"$TMP/err"; rc=$?
expect_exit 0 "render --dry-run without gnuplot"
PATH="$TMP/nognuplot" "$HP_BIN" solve "$S/default.yaml" >"$TMP/out" 2>"$TMP/err"; rc=$?
expect_exit 0 "solve without gnuplot"
# In the C locale (what scripts and CI often run in) a drawing prints nothing on stderr:
# gnuplot's "set encoding utf8" would otherwise warn about its degree sign.
if command -v gnuplot >/dev/null; then
  LC_ALL=C "$HP_BIN" render "$S/default.yaml" -o "$TMP/c_locale.png" >"$TMP/out" 2>"$TMP/err"; rc=$?
  expect_exit 0 "render in the C locale"
  [ ! -s "$TMP/err" ] && ok || bad "render in the C locale wrote to stderr"
fi
finish
