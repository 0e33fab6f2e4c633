# The load level from the command line (docs/load.md): solve on the load scenes (reached,
# closest with the binding limit named, refused with the unsupported direction), the JSON
# answer's equilibrium residual, auto's stated choice, and analyze's load section.
source "$2/tests/cli_lib.sh"
S="$HP_SRC/scenarios"

run solve "$S/load_supine.yaml"
expect_exit 0 "supine load scene reached"
expect_stdout_has "level       load" "says the load level"
expect_stdout_has "why         auto chose load by model error" "says why auto chose it"
expect_stdout_has "equilibrium residual" "reports the residual"
expect_stdout_has "compliance" "reports the compliance"

run solve "$S/load_supine.yaml" --json
expect_exit 0 "supine --json"
python3 - "$TMP/out" <<'PY' && ok || bad "load JSON: residual, forces, round trip"
import json, sys
d = json.load(open(sys.argv[1]))
assert d["status"] == "reached" and d["level"] == "load", d["status"]
assert d["residual_force_n"] < 1e-9 and d["residual_moment_nm"] < 1e-10
# the base carries its share of the weight (40 % of 4.5 kg = 17.65 N vertically; its forces
# lean outward, so their magnitudes add to more)
base = sum(b["force_n"] for b in d["bladders"][:4])
assert 17.65 < base < 25.0, base
for b in d["bladders"]:
    assert b["pressure_pa"] <= 10000.0 and b["pressure_pa"] >= -5000.0
PY

# The tilted scene's correction is not held inside the pressure limits (a base bladder and
# both chin bladders at pressure_max): closest on every backend, the same pose (the
# closest-pose program is shared) and the same pressures, inside the indentation range.
for b in realtime ipopt nlopt-slsqp; do
    run solve "$S/load_tilted.yaml" --backend "$b" --json
    expect_exit 1 "tilted on $b"
    cp "$TMP/out" "$TMP/$b.json"
done
python3 - "$TMP" <<'PY' && ok || bad "backends agree on the load level (1e-6 Pa, 1e-9 mm/deg)"
import json, sys
d = {b: json.load(open(f"{sys.argv[1]}/{b}.json")) for b in ("realtime", "ipopt", "nlopt-slsqp")}
for b in ("ipopt", "nlopt-slsqp"):
    for x, y in zip(d["realtime"]["bladders"], d[b]["bladders"]):
        assert abs(x["pressure_pa"] - y["pressure_pa"]) <= 1e-6, (b, x, y)
    for k, v in d["realtime"]["achieved"].items():
        assert abs(v - d[b]["achieved"][k]) <= 1e-9, (b, k)
for b in d.values():
    for x in b["bladders"]:
        assert x["indent"] <= 0.26 + 1e-9, x
    assert "pressure_max" in sum((x["binding"] for x in b["bladders"]), [])
PY

# The option is at fault, not the scene (whose own backend the load level takes): 64, as an
# unknown --backend or --level load without a load section.
run solve "$S/load_tilted.yaml" --backend nlopt-cobyla
expect_exit 64 "cobyla refused at the load level"
expect_stderr_has "not available at the load level" "says why"

# The minimum-holding-stiffness tie-breaker (scene load.tiebreak: stiffness): refused by name
# on the realtime backend; on Ipopt the supine correction is held stably. Least squeeze
# holds it stably too: its plain pick is a saddle (a side bladder at 0 kPa), so HOLD takes
# the least squeeze among the stable holds, and the forward statics confirms it.
sed 's/tiebreak: least-squeeze/tiebreak: stiffness/' "$S/load_supine.yaml" >"$TMP/stiff.yaml"
run solve "$TMP/stiff.yaml"
expect_exit 65 "stiffness refused on realtime"
expect_stderr_has "tie-breaker stiffness needs the ipopt backend" "names the tie-breaker and the backend"
run solve "$S/load_supine.yaml"
expect_exit 0 "least squeeze: reached"
expect_stdout_has "holding               at the answer: stable" "least squeeze: a stable hold"
run solve "$S/load_supine.yaml" --json
python3 - "$TMP/out" <<'PY' && ok || bad "least squeeze: the forward statics confirms the hold"
import json, sys
d = json.load(open(sys.argv[1]))
assert d["status"] == "reached" and d["stable"] is True
assert d["rest_error"] <= 1e-6  # mm/deg: the tolerance a REACHED answer is confirmed to
PY
run solve "$TMP/stiff.yaml" --backend ipopt
expect_exit 0 "stiffness on ipopt"
expect_stdout_has "tie-breaker stiffness" "says the tie-breaker"
expect_stdout_has "holding               at the answer: stable" "stiffness: stable hold"

run solve "$S/load_tilted.yaml"
expect_exit 1 "tilted load scene: closest"
expect_stdout_has "holding               at the answer: stable" "the tilted hold is stable"
expect_stdout_has "pressure_max" "names the binding limit"
expect_stdout_has "cannot_pull" "names the bladders that carry nothing"

# Too heavy for the limits: the closest held pose (every base bladder at pressure_max) is
# held only at a saddle; the answer is the stable hold found lower along gravity, CLOSEST,
# what limits it named "stability" on the bladders that carry, and the status line says it
# is the nearest stable hold the search found, not a proven nearest stable pose.
run solve "$S/load_heavy.yaml"
expect_exit 1 "too heavy for the limits: the stable hold found instead of the saddle"
expect_stdout_has "status      closest" "closest"
expect_stdout_has "holding               at the answer: stable" "the hold returned is stable"
expect_stdout_has "base_neck_left" "the table"
awk '$1 == "base_neck_left" && $NF ~ /(^|,)stability(,|$)/ { f = 1 } END { exit !f }' "$TMP/out" \
  && ok || bad "a carrying base bladder is named stability"
expect_stdout_has "the nearest stable hold the search found" "says what the answer is"
expect_stdout_has "not a proven nearest stable pose" "and what it is not"
# The JSON output carries the same words (a "message" key, as the kinematic levels' JSON).
run solve "$S/load_heavy.yaml" --json
expect_exit 1 "too heavy, --json: closest"
python3 - "$TMP/out" <<'PY' && ok || bad "load JSON message says what the closest answer is"
import json, sys
d = json.load(open(sys.argv[1]))
assert d["status"] == "closest", d["status"]
assert "the nearest stable hold the search found" in d["message"], d.get("message")
PY

run solve "$S/load_prone.yaml"
expect_exit 65 "prone: refused"
expect_stderr_has "along -z" "names the unsupported direction"
expect_stdout_empty "prone: nothing on stdout"

run solve "$S/load_supine.yaml" --level load
expect_exit 0 "--level load on a load scene"
expect_stdout_has "why         load: asked for by --level" "the command line names its flag"

run solve "$S/default.yaml" --level load
expect_exit 64 "--level load without a load section"
expect_stderr_has "needs a scene with a 'load' section" "says what is missing"

run analyze "$S/default.yaml"
expect_exit 0 "analyze default"
expect_stdout_has "kinematic sag unbounded" "analyze reports the sag it ignores"
expect_stdout_has "plans stay kinematic" "and that the plans stay kinematic"

# A correction outside the identifiable range is refused at the load level as at the
# kinematic ones, with the same message (it was "reached" beside "rest inf mm/deg"). With
# level auto it is refused before, as the pose auto would measure at (tests/cli/auto_pose.sh).
for lv in "--level load" "--level surface"; do
    run solve "$S/load_supine.yaml" --correction 0,0,0,100,0,0 $lv
    expect_exit 65 "100 deg pitch refused $lv"
    expect_stdout_empty "100 deg pitch $lv: no answer"
    expect_stderr_has "headplan solve: --correction: desired rotation: angle 100.0 deg is outside the identifiable range" "names the limit $lv"
done
# 89.9 deg pitch is inside the range; pressures inside the limits hold the head there (an
# exact equilibrium), but only at a saddle: no stable hold, so no answer (the safe output),
# and the message says why.
run solve "$S/load_supine.yaml" --correction 0,0,0,89.9,0,0
expect_exit 70 "89.9 deg pitch: held only at a saddle"
expect_stderr_has "only at an unstable equilibrium (no stable hold found" "the saddle named"
# Through a panel (side_chin_left's centre 11.6 mm inside the head) it was CLOSEST with
# a Newton-Euler residual of 2.74 N; the closest-pose program (started from the held pose
# nearest the nominal one) answers a held pose with every centre outside the head.
run solve "$S/load_supine.yaml" --correction 20,0,0,0,0,40 --json
expect_exit 1 "20 mm + 40 deg yaw: closest"
python3 - "$TMP/out" <<'PY' && ok || bad "20 mm + 40 deg yaw: an equilibrium"
import json, sys
d = json.load(open(sys.argv[1]))
assert d["status"] == "closest"
assert d["residual_force_n"] < 1e-9 and d["residual_moment_nm"] < 1e-9
PY
run solve "$S/load_heavy.yaml" --correction 0,0,80,0,0,0
expect_exit 65 "80 mm lift refused at the load level"
expect_stderr_has "80.0 mm is outside the identifiable range (<= 77.5 mm" "names the semi-axis"

run analyze "$S/load_tilted.yaml"
expect_exit 0 "analyze tilted"
expect_stdout_has "holding       stable" "analyze reports the holding"
finish
