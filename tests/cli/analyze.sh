# headplan analyze: the layout analysis (conditioning, weakest direction, reach, error bounds,
# geometry) of default.yaml, sphere_head.yaml and near_degenerate.yaml, checked against
# independent references: numpy's SVD of a Jacobian rebuilt from the reported geometry, the
# ellipsoid equation, and the planner (solve) just inside and just outside each reach.
# Exit statuses 64/65/66 with stdout empty on error.
source "$2/tests/cli_lib.sh"
S="$HP_SRC/scenarios"

# ---- default.yaml, JSON ----------------------------------------------------------------
run analyze "$S/default.yaml" --json
expect_exit 0 "default --json"
cp "$TMP/out" "$TMP/default.json"
python3 - "$TMP/default.json" <<'PY' && ok || bad "default JSON: structure and values"
import json, math, sys
d = json.load(open(sys.argv[1]))
keys = list(d)
want = ["level", "singular_values", "rank", "condition", "weakest_direction",
        "rotation_commandable", "note", "reach", "error_bounds", "head", "pivot_mm", "bladders"]
assert all(k in d for k in want), keys
assert [k for k in keys if k in want] == want, keys                 # fixed order
sv = d["singular_values"]
assert d["rank"] == 6 and len(sv) == 6
assert all(a >= b for a, b in zip(sv, sv[1:])), sv                 # descending
assert sv[-1] > 0, sv
# The command divides the same two doubles: only printing (17 digits) can differ.
assert abs(d["condition"] - sv[0] / sv[-1]) <= 1e-12 * d["condition"], d["condition"]
w = d["weakest_direction"]
assert list(w)[:2] == ["vector", "phrase"] and len(w["vector"]) == 6
assert abs(math.fsum(v * v for v in w["vector"]) - 1) < 1e-12       # unit vector
# docs/model.md section 4: Y translation and pitch are the weakest directions of this layout.
assert "pitch" in w["phrase"], w["phrase"]
assert abs(w["vector"][3]) == max(abs(v) for v in w["vector"]), w["vector"]
assert abs(w["vector"][1]) >= 0.3, w["vector"]
assert d["rotation_commandable"] is True and d["note"] is None
pose = ["x_mm", "y_mm", "z_mm", "pitch_deg", "roll_deg", "yaw_deg"]
assert list(d["reach"]) == pose
for k in pose:
    lo, hi = d["reach"][k]
    assert lo <= 0 <= hi and lo < 0 < hi, (k, lo, hi)
    assert max(-lo, hi) <= (50 if k.endswith("_mm") else 30), (k, lo, hi)
# The layout is mirror-symmetric in X and Y: lateral, longitudinal and every rotation reach
# the same distance both ways (to the bisection resolution, ~1e-13 of the cap).
for k in ["x_mm", "y_mm", "pitch_deg", "roll_deg", "yaw_deg"]:
    lo, hi = d["reach"][k]
    assert abs(lo + hi) <= 1e-9, (k, lo, hi)
eb = d["error_bounds"]
assert eb["tolerance_mm"] == 0.01 and eb["translation_mm"] == 5 and eb["rotation_deg"] == 3
assert eb["range_source"] == "scene"
assert eb["linear_mm"] >= eb["plane_mm"] > 0 and eb["surface_mm"] == 0, eb
pick = ("linear" if eb["linear_mm"] <= eb["tolerance_mm"] else
        "plane" if eb["plane_mm"] <= eb["tolerance_mm"] else "surface")
assert eb["auto_level"] == pick, (eb, pick)
assert d["level_requested"] == "auto" and d["level"] == pick        # the scene says auto
h = d["head"]
assert h["shape"] == "ellipsoid" and h["semi_axes_mm"] == [77.5, 115, 97.5], h
assert h["center_mm"] == [0, 0, 0] and d["pivot_mm"] == [0, 0, 0] and h["mass_kg"] == 4.5
names = ["base_neck_left", "base_neck_right", "base_skull_left", "base_skull_right",
         "side_fore_left", "side_fore_right", "side_chin_left", "side_chin_right"]
assert [b["name"] for b in d["bladders"]] == names
bk = ["name", "center_mm", "Ri_mm", "Ro_mm", "c1_pa", "c2_pa", "pressure_min_pa",
      "pressure_max_pa"]
a = h["semi_axes_mm"]
for b in d["bladders"]:
    assert list(b)[:len(bk)] == bk, list(b)
    assert (b["Ri_mm"], b["Ro_mm"], b["c1_pa"], b["c2_pa"]) == (27, 30, 1.1e4, 2.2e4), b
    assert (b["pressure_min_pa"], b["pressure_max_pa"]) == (-5000, 10000), b
    p, n, c = b["contact_mm"], b["normal"], b["center_mm"]
    # Independent geometry: p on the ellipsoid (relative 1e-12: a few roundings of values
    # of order 1), n the normalised gradient (x/a², y/b², z/c²) there (1e-12), and with no
    # preload the centre is p + Ro·n (1e-9 mm: the 17-digit printing of ~100 mm values).
    assert abs(sum((p[i] / a[i]) ** 2 for i in range(3)) - 1) < 1e-12, p
    g = [p[i] / a[i] ** 2 for i in range(3)]
    gn = math.sqrt(sum(x * x for x in g))
    assert all(abs(n[i] - g[i] / gn) < 1e-12 for i in range(3)), (n, g)
    assert all(abs(c[i] - (p[i] + 30 * n[i])) < 1e-9 for i in range(3)), (c, p, n)
    assert abs(b["rho0_mm"] - 30) < 1e-9, b["rho0_mm"]
PY

# ---- the singular values again, by numpy from the reported geometry ---------------------
# Rows [-n, -((p - pivot) x n)·pi/180] (mm/mm and mm/deg, p in mm): docs/model.md section 4's
# Jacobian written from the reported contacts and normals, decomposed by LAPACK instead of
# Eigen's JacobiSVD. Tolerance 1e-9 of sv_max: both SVDs are backward stable (~1e-15
# relative) and the inputs are printed to 17 digits, so 1e-9 leaves a wide margin while
# catching any wrong column scale (pi/180 or 1e3) or sign by many orders of magnitude.
# The python3 first on PATH may be a private one without numpy (pyenv): try the system's too.
NUMPY_PY=""
for py in python3 /usr/bin/python3; do
    if "$py" -c "import numpy" 2>/dev/null; then NUMPY_PY=$py; break; fi
done
[ -n "$NUMPY_PY" ] || echo "SKIP: no python3 with numpy: the SVD cross-checks are not run"
svd_check() {
    [ -n "$NUMPY_PY" ] || return 0
    "$NUMPY_PY" - "$1" <<'PY'
import json, math, sys
import numpy as np
d = json.load(open(sys.argv[1]))
pv = d["pivot_mm"]
rows = []
for b in d["bladders"]:
    n, p = b["normal"], b["contact_mm"]
    l = [p[i] - pv[i] for i in range(3)]
    cr = [l[1] * n[2] - l[2] * n[1], l[2] * n[0] - l[0] * n[2], l[0] * n[1] - l[1] * n[0]]
    rows.append([-n[0], -n[1], -n[2]] + [-x * math.pi / 180 for x in cr])
ref = np.linalg.svd(np.array(rows), compute_uv=False)
got = d["singular_values"]
for r, g in zip(ref, got):
    assert abs(r - g) <= 1e-9 * ref[0], (list(ref), got)
assert d["rank"] == int(np.sum(ref > 1e-9 * ref[0])), (d["rank"], list(ref))
PY
}
svd_check "$TMP/default.json" && ok || bad "default: numpy SVD of the rebuilt Jacobian"

# ---- reach cross-checked by the planner: 1% inside is reached (exit 0), 1% beyond is not
# (exit 1). The planner is separate code (its own feasibility test on pressures and
# stretches); 1% is far above the bisection resolution and below the scan step (1/100 of
# the 50 mm / 30 deg cap is 0.5 mm / 0.3 deg, more than 1% of every reach here).
python3 - "$TMP/default.json" > "$TMP/reach_cases" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
for i, k in enumerate(["x_mm", "y_mm", "z_mm", "pitch_deg", "roll_deg", "yaw_deg"]):
    for r in d["reach"][k]:
        cap = 50 if i < 3 else 30
        if abs(r) >= cap: continue
        for f, want in ((0.99, 0), (1.01, 1)):
            c = [0.0] * 6; c[i] = f * r
            print(want, ",".join(repr(x) for x in c), d["level"])
PY
while read -r want corr level; do
    run solve "$S/default.yaml" --level "$level" --correction "$corr"
    expect_exit "$want" "solve at $corr (reach cross-check, level $level)"
done < "$TMP/reach_cases"
[ -s "$TMP/reach_cases" ] && ok || bad "no reach cases generated"

# ---- --level overrides the scene; auto resolves to what error_bounds says ---------------
run analyze "$S/default.yaml" --json --level linear
expect_exit 0 "--level linear"
python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); assert d["level"]=="linear" and d["level_source"]=="option", d["level"]' "$TMP/out" && ok || bad "--level linear is used"
run analyze "$S/near_degenerate.yaml" --json --level=auto
expect_exit 0 "--level=auto"
python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); assert d["level"]==d["error_bounds"]["auto_level"] and d["level_requested"]=="auto", d' "$TMP/out" && ok || bad "--level auto resolves"

# ---- human output -------------------------------------------------------------------------
run analyze "$S/default.yaml"
expect_exit 0 "default text"
expect_stdout_has "weakest       pitch" "default text names the weakest direction"
expect_stdout_has "rank          6 of 6" "default text rank"
expect_stdout_has "side_chin_right" "default text bladder table"
expect_stdout_has "auto picks" "default text error bounds"
python3 - "$TMP/out" "$TMP/default.json" <<'PY' && ok || bad "text condition matches JSON"
import json, sys
text = open(sys.argv[1]).read(); d = json.load(open(sys.argv[2]))
line = [l for l in text.splitlines() if l.startswith("condition")][0]
assert abs(float(line.split()[1]) - d["condition"]) <= 1e-5 * d["condition"], line  # %.6g
PY

# ---- the identifiable range (issue 10) -------------------------------------------------------
python3 - "$TMP/default.json" <<'PY' && ok || bad "default JSON: identifiable range"
import json, sys
d = json.load(open(sys.argv[1]))["identifiable"]
assert d["rank"] == 6 and d["unobservable_motions"] == [] and not d["only_centre_motion"]
assert all(d["commanded"].values()), d["commanded"]
assert d["rotation_angle_below_deg"] == 90 and d["translation_norm_max_mm"] == 77.5, d
assert d["head_symmetry"] == "half-turns about its X, Y and Z axes", d["head_symmetry"]
PY
run analyze "$S/default.yaml"
expect_stdout_has "identifiable range" "default text: identifiable range"
expect_stdout_has "angle below 90 deg" "default text: rotation bound"
expect_stdout_has "up to 77.5000 mm" "default text: translation bound"
# A pivot 1 km away only changes coordinates: still rank 6, everything commanded.
sed 's/^pivot_mm: \[0, 0, 0\]/pivot_mm: [0, 0, 1000000]/' "$S/default.yaml" >"$TMP/far.yaml"
run analyze "$TMP/far.yaml" --json
expect_exit 0 "pivot 1 km --json"
python3 - "$TMP/out" <<'PY' && ok || bad "pivot 1 km: identifiable range unchanged"
import json, sys
d = json.load(open(sys.argv[1]))
assert d["pivot_mm"][2] == 1e6, d["pivot_mm"]
assert d["rank"] == 6 and d["condition"] is not None, d["rank"]   # old main: rank 4
i = d["identifiable"]
assert i["rank"] == 6 and all(i["commanded"].values()), i
PY
# A sphere with its pivot 70 mm below the centre: rank 3; the unobservable motions are turns
# about the centre, i.e. J·v = 0 for J rebuilt here from the reported contacts and normals.
sed 's/^pivot_mm: \[0, 0, 0\]/pivot_mm: [0, 0, -70]/' "$S/sphere_head.yaml" >"$TMP/sphere_off.yaml"
run analyze "$TMP/sphere_off.yaml" --json
expect_exit 0 "sphere off-centre pivot --json"
python3 - "$TMP/out" <<'PY' && ok || bad "sphere off-centre pivot: unobservable motions"
import json, math, sys
d = json.load(open(sys.argv[1]))
i = d["identifiable"]
assert i["rank"] == 3 and i["only_centre_motion"] and i["rotation_angle_below_deg"] is None
assert [i["commanded"][k] for k in ["x_mm", "y_mm", "z_mm", "pitch_deg", "roll_deg", "yaw_deg"]] \
    == [True, True, True, False, False, False], i["commanded"]
pv = d["pivot_mm"]
assert len(i["unobservable_motions"]) == 3
for v in i["unobservable_motions"]:
    x = [v[k] for k in ["x_mm", "y_mm", "z_mm", "pitch_deg", "roll_deg", "yaw_deg"]]
    assert abs(max(x, key=abs) - 1) < 1e-12, x                      # scaled: largest is 1
    for b in d["bladders"]:
        n, p = b["normal"], b["contact_mm"]
        l = [p[j] - pv[j] for j in range(3)]
        lxn = [l[1] * n[2] - l[2] * n[1], l[2] * n[0] - l[0] * n[2], l[0] * n[1] - l[1] * n[0]]
        row = [-n[0], -n[1], -n[2]] + [-c * math.pi / 180 for c in lxn]   # mm per mm, per deg
        s = sum(r * y for r, y in zip(row, x))
        assert abs(s) < 1e-9, (b["name"], s)
PY

# ---- sphere head: translation only --------------------------------------------------------
run analyze "$S/sphere_head.yaml" --json
expect_exit 0 "sphere --json"
cp "$TMP/out" "$TMP/sphere.json"
python3 - "$TMP/sphere.json" <<'PY' && ok || bad "sphere JSON"
import json, sys
d = json.load(open(sys.argv[1]))
assert d["rank"] == 3 and d["condition"] is None, (d["rank"], d["condition"])
assert d["rotation_commandable"] is False
assert "cannot be commanded" in d["note"] and "rotation" in d["note"], d["note"]
sv = d["singular_values"]
assert sv[2] > 0.1 and sv[3] <= 1e-9 * sv[0], sv
assert d["head"]["shape"] == "sphere" and d["head"]["radius_mm"] == 90
assert "semi_axes_mm" not in d["head"] and d["head"]["mass_kg"] is None
for k in ["pitch_deg", "roll_deg", "yaw_deg"]:
    assert d["reach"][k] is None, (k, d["reach"][k])                   # not commanded
for k in ["x_mm", "y_mm", "z_mm"]:
    lo, hi = d["reach"][k]
    assert lo < 0 < hi, (k, lo, hi)
# The weakest direction lies in the rotation null space: no translation in it.
assert max(abs(v) for v in d["weakest_direction"]["vector"][:3]) < 1e-9
for b in d["bladders"]:                              # contacts on the 90 mm sphere (1e-12)
    assert abs(sum(x * x for x in b["contact_mm"]) ** 0.5 / 90 - 1) < 1e-12, b
PY
svd_check "$TMP/sphere.json" && ok || bad "sphere: numpy SVD of the rebuilt Jacobian"
run analyze "$S/sphere_head.yaml"
expect_exit 0 "sphere text"
expect_stdout_has "rank          3 of 6" "sphere text rank"
expect_stdout_has "rotation about its centre cannot be commanded" "sphere text note"
expect_stdout_has "not commanded" "sphere text reach"

# ---- near-degenerate layout: worse conditioned than the default ---------------------------
run analyze "$S/near_degenerate.yaml" --json
expect_exit 0 "near_degenerate --json"
cp "$TMP/out" "$TMP/near.json"
python3 - "$TMP/near.json" "$TMP/default.json" <<'PY' && ok || bad "near_degenerate conditioning"
import json, sys
n = json.load(open(sys.argv[1])); d = json.load(open(sys.argv[2]))
assert n["rank"] == 6
assert n["condition"] > 5 * d["condition"], (n["condition"], d["condition"])
assert "pitch" in n["weakest_direction"]["phrase"]
assert n["error_bounds"]["range_source"] == "default"     # the scene states no auto range
PY
svd_check "$TMP/near.json" && ok || bad "near_degenerate: numpy SVD of the rebuilt Jacobian"

# ---- errors: one line on stderr, nothing on stdout ----------------------------------------
run analyze "$S/paper_expansion.yaml"
expect_exit 65 "bladder-only scene"
expect_stdout_empty "bladder-only scene"
expect_stderr_has "paper_expansion.yaml: analyze needs a layout scene (head and bladders)" "bladder-only scene"

run analyze "$TMP/no_such_scene.yaml" --json
expect_exit 66 "missing file"
expect_stdout_empty "missing file"
expect_stderr_has "no_such_scene.yaml" "missing file"

run analyze "$HP_SRC/tests/scenes_bad/Ri_ge_Ro.yaml" --json
expect_exit 65 "malformed scene"
expect_stdout_empty "malformed scene"
expect_stderr_has "Ri_ge_Ro.yaml:13:45: bladders[0].Ri_mm: must be less than Ro_mm" "malformed scene: file:line:col"

run analyze "$HP_SRC/tests/scenes_bad/syntax_unclosed.yaml"
expect_exit 65 "YAML syntax error"
expect_stdout_empty "YAML syntax error"
expect_stderr_has "syntax_unclosed.yaml:4:17:" "YAML syntax error: file:line:col"

for args in "" "--bogus $S/default.yaml" "$S/default.yaml --level exact" \
            "$S/default.yaml --level" "$S/default.yaml $S/default.yaml" \
            "$S/default.yaml --level linear --level plane"; do
    # shellcheck disable=SC2086
    run analyze $args
    expect_exit 64 "usage: '$args'"
    expect_stdout_empty "usage: '$args'"
    [ "$(wc -l < "$TMP/err")" -eq 1 ] && ok || bad "usage: '$args': one line on stderr"
done
expect_stderr_has "--level: given more than once" "repeated --level"
run analyze "$TMP/no_such_scene.yaml" --level exact
expect_exit 64 "a bad option is reported before the scene is read"

run analyze --help
expect_exit 0 "--help"
expect_stdout_has "usage: headplan analyze SCENE" "--help"

finish
