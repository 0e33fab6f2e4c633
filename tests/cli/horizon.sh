# headplan horizon: the comparison of greedy, receding-horizon and offline plans, its outputs
# (summary, JSON, CSV with the summary in its header), and every bad input refused.
source "$2/tests/cli_lib.sh"
S=$(patient_scenes) || exit 1 # time budgets of 60 s (tests/cli_lib.sh)

# A short step trace: the first shift (5 s) and its settling, rate-limited.
head -81 "$S/traces/step.csv" > "$TMP/step.csv"
run horizon "$S/horizon/step.yaml" "$TMP/step.csv" --rows deviation --json -o "$TMP/out.csv"
expect_exit 0 "compare"
python3 - "$TMP/out" "$TMP/out.csv" <<'PY' && ok || bad "compare outputs"
import csv, json, sys
j = json.load(open(sys.argv[1]))
p = j["plans"]
assert set(p) == {"greedy", "receding", "offline"}, p.keys()
assert j["rows"] == 80 and j["tolerance_mm"] == 0.5 and j["tolerance_deg"] == 0.5
# the offline plan is the optimum of the common problem: no larger cost, strictly smaller here
assert p["offline"]["cost"] <= p["greedy"]["cost"] * (1 + 1e-4)
assert p["offline"]["cost"] <= p["receding"]["cost"] * (1 + 1e-4)
assert p["offline"]["pose_cost"] < 0.5 * p["greedy"]["pose_cost"]
assert p["offline"]["windows"] == 1 and p["offline"]["iterations"] > 0
lines = open(sys.argv[2]).read().splitlines()
meta = [l for l in lines if l.startswith("#")]
assert any(l.startswith("# offline,rms,") for l in meta), meta
assert any(l.startswith("# plan,time_outside_s,") for l in meta), meta
rows = list(csv.DictReader(l for l in lines if not l.startswith("#")))
assert len(rows) == 3 * 80, len(rows)
assert [r["plan"] for r in rows[::80]] == ["greedy", "receding", "offline"]
# the CSV's pose error column is the largest |achieved - desired| of the row
for r in rows:
    e = max(abs(float(r["achieved_" + a]) - float(r["desired_" + a]))
            for a in ("x_mm", "y_mm", "z_mm", "pitch_deg", "roll_deg", "yaw_deg"))
    assert abs(e - float(r["pose_error"])) <= 1e-12 * max(1, e), (r, e)
PY
# The summary table names every plan; one mode alone; the same run gives the same bytes.
run horizon "$S/horizon/step.yaml" "$TMP/step.csv" --rows deviation --mode greedy
expect_exit 0 "greedy only"; expect_stdout_has "greedy,rms," "greedy summary"
grep -q "offline" "$TMP/out" && bad "greedy mode printed offline" || ok
run horizon "$S/horizon/step.yaml" "$TMP/step.csv" --rows deviation --mode receding \
    --horizon 3 --prediction velocity -o "$TMP/a.csv"
expect_exit 0 "receding velocity"
run horizon "$S/horizon/step.yaml" "$TMP/step.csv" --rows deviation --mode receding \
    --horizon 3 --prediction velocity -o "$TMP/b.csv"
cmp -s "$TMP/a.csv" "$TMP/b.csv" && ok || bad "two runs differ"
# Windows and a per-second rate limit on irregular time stamps.
head -301 "$S/traces/drift_long.csv" > "$TMP/drift.csv"
run horizon "$S/horizon/drift_long.yaml" "$TMP/drift.csv" --rows deviation --mode offline \
    --window 120 --overlap 30 --rate-kpa-per-s 1.5 --json
expect_exit 0 "windows"; expect_stdout_has '"windows": 3' "three windows"
# The scene's own trace is the default.
run horizon "$S/horizon/step.yaml" --mode greedy; expect_exit 0 "scene trace"
# Greedy is what batch computes, bit for bit (docs/horizon.md): each plan starts from the
# previous row's result alone. Greedy kept the realtime backend's own last point and
# multipliers, and 113 of the 300 rows differed (1e-10 Pa, 1e-14 mm). kPa = Pa * 1e-3 in both.
run horizon "$S/horizon/step.yaml" --mode greedy -o "$TMP/greedy.csv"
expect_exit 0 "greedy, scene trace"
run batch "$S/horizon/step.yaml" --no-times --no-progress -o "$TMP/batch.csv"
expect_exit 0 "batch, scene trace"
python3 - "$TMP/greedy.csv" "$TMP/batch.csv" <<'PY' && ok || bad "greedy is not batch"
import csv, sys
def rows(p):
    return list(csv.DictReader(l for l in open(p) if not l.startswith("#")))
g, b = rows(sys.argv[1]), rows(sys.argv[2])
assert len(g) == len(b) == 300, (len(g), len(b))
names = [k[:-12] for k in b[0] if k.endswith("_pressure_pa")]
assert len(names) == 8, names
for r, s in zip(g, b):
    assert r["t_s"] == s["t_s"] and r["status"] == s["status"], (r["t_s"], s["t_s"])
    for a in ("x_mm", "y_mm", "z_mm", "pitch_deg", "roll_deg", "yaw_deg"):
        assert r["desired_" + a] == s["desired_" + a], (r["t_s"], a)
        assert r["achieved_" + a] == s["achieved_" + a], (r["t_s"], a)
    for n in names:
        assert float(r[n + "_kpa"]) == float(s[n + "_pressure_pa"]) * 1e-3, (r["t_s"], n)
PY
# A per-second limit of 1e-300 kPa/s allows no change: every plan holds the start pressures
# and answers every row (the realtime backend left greedy and receding rows solver-error,
# exit 70, when its window was a point).
run horizon "$S/horizon/step.yaml" "$TMP/step.csv" --rows deviation --rate-kpa-per-s 1e-300 \
    -o "$TMP/hold.csv"
expect_exit 0 "1e-300 kPa/s"
python3 - "$TMP/hold.csv" <<'PY' && ok || bad "1e-300 kPa/s holds"
import csv, sys
rows = list(csv.DictReader(l for l in open(sys.argv[1]) if not l.startswith("#")))
assert len(rows) == 3 * 80, len(rows)
kpa = [k for k in rows[0] if k.endswith("_kpa")]
for r in rows:
    assert r["status"] in ("reached", "closest"), (r["plan"], r["t_s"], r["status"])
    assert [r[k] for k in kpa] == [rows[0][k] for k in kpa], (r["plan"], r["t_s"])
PY

# Bad inputs: usage 64, data 65, no input 66.
run horizon; expect_exit 64 "no scene"
run horizon "$S/horizon/step.yaml" "$TMP/step.csv" --mode best; expect_exit 64 "bad mode"
expect_stderr_has "--mode" "bad mode named"
run horizon "$S/horizon/step.yaml" "$TMP/step.csv" --horizon 0; expect_exit 64 "horizon 0"
run horizon "$S/horizon/step.yaml" "$TMP/step.csv" --horizon 65; expect_exit 64 "horizon 65"
run horizon "$S/horizon/step.yaml" "$TMP/step.csv" --overlap 5; expect_exit 64 "overlap alone"
run horizon "$S/horizon/step.yaml" "$TMP/step.csv" --window 10 --overlap 10; expect_exit 64 "overlap = window"
run horizon "$S/horizon/step.yaml" "$TMP/step.csv" --rate-kpa-per-s nan; expect_exit 64 "rate nan"
run horizon "$S/horizon/step.yaml" "$TMP/step.csv" --rate-kpa-per-s -1; expect_exit 64 "rate < 0"
run horizon "$S/horizon/step.yaml" "$TMP/step.csv" --smooth 2; expect_exit 64 "smooth > 1"
run horizon "$S/horizon/step.yaml" "$TMP/step.csv" --tolerance-mm 0; expect_exit 64 "tolerance 0"
run horizon "$S/horizon/step.yaml" "$TMP/step.csv" --tolerance-deg inf; expect_exit 64 "tolerance inf"
run horizon "$S/horizon/step.yaml" "$TMP/step.csv" --prediction psychic; expect_exit 64 "prediction"
run horizon "$S/horizon/step.yaml" "$TMP/step.csv" --rows sideways; expect_exit 64 "rows"
run horizon "$S/horizon/step.yaml" "$TMP/step.csv" --bogus; expect_exit 64 "unknown option"
run horizon "$S/horizon/step.yaml" "$TMP/missing.csv"; expect_exit 66 "missing trace"
printf 't_s,x_mm,y_mm,z_mm,pitch_deg,roll_deg,yaw_deg\n0.0,0,0,0,0,0,0\n0.1,1,0,0,0,0,0\n0.1,2,0,0,0,0,0\n' > "$TMP/dup.csv"
run horizon "$S/horizon/step.yaml" "$TMP/dup.csv" --rows deviation --mode greedy
expect_exit 65 "time not increasing"; expect_stderr_has "dup.csv:4: t_s: 0.1 s is not after the previous row's 0.1 s" "time line named"
printf 't_s,x_mm,y_mm,z_mm,pitch_deg,roll_deg,yaw_deg\n0.0,0,0,0,0,0,0\n0.1,abc,0,0,0,0,0\n' > "$TMP/badrow.csv"
run horizon "$S/horizon/step.yaml" "$TMP/badrow.csv" --rows deviation; expect_exit 65 "bad row"
printf 't_s,x_mm,y_mm,z_mm,pitch_deg,roll_deg,yaw_deg\n' > "$TMP/empty.csv"
run horizon "$S/horizon/step.yaml" "$TMP/empty.csv" --rows deviation; expect_exit 65 "no rows"
run horizon "$S/horizon/step.yaml" "$TMP/step.csv" --rows deviation --mode greedy -o /nonexistent/dir/x.csv
expect_exit 73 "cannot write"
# Options no selected plan reads are refused, not ignored (the window of a greedy plan, the
# horizon of an offline one); subnormal tolerances are refused like zero.
run horizon "$S/horizon/step.yaml" "$TMP/step.csv" --rows deviation --mode greedy --window 10
expect_exit 64 "window in greedy"; expect_stderr_has "--window: only the offline plan reads it (--mode offline or compare), not --mode greedy" "window named"
run horizon "$S/horizon/step.yaml" "$TMP/step.csv" --rows deviation --mode receding --window 10 --overlap 2
expect_exit 64 "window in receding"
run horizon "$S/horizon/step.yaml" "$TMP/step.csv" --rows deviation --mode offline --horizon 3
expect_exit 64 "horizon in offline"; expect_stderr_has "--horizon: only the receding plan reads it" "horizon named"
run horizon "$S/horizon/step.yaml" "$TMP/step.csv" --rows deviation --mode greedy --prediction velocity
expect_exit 64 "prediction in greedy"; expect_stderr_has "--prediction: only the receding plan reads it" "prediction named"
run horizon "$S/horizon/step.yaml" "$TMP/step.csv" --rows deviation --mode greedy --tolerance-deg 1e-310
expect_exit 64 "subnormal tolerance"; expect_stderr_has "--tolerance-deg: must be > 0 (and not subnormal)" "subnormal named"
# An offline row whose planned pose its pressures do not hold (the fit from the nominal pose,
# the strict round trip every hp_plan answer passes, stalls 43 mm/deg away with distances
# 1.2 mm off the pressures'): a pitch ramped to
# 89.9 deg with the rate limit lifted. Before, offline stated those poses, exit 0.
{ printf '# headplan-trace: rows=correction\nt_s,x_mm,y_mm,z_mm,pitch_deg,roll_deg,yaw_deg\n'
  for i in $(seq 0 30); do p=$((i * 6)); [ $p -gt 89 ] && p=89.9; echo "$((i * 10)).0,0,0,0,$p,0,0"; done
} > "$TMP/pitch.csv"
run horizon "$S/default.yaml" "$TMP/pitch.csv" --mode offline --rate-kpa-per-s 1000
expect_exit 65 "offline pose not confirmed"
expect_stderr_has "headplan horizon: offline: line 15: the planned pose is not where its pressures hold the head: forward contact kinematics from the nominal pose stalled at (" "offline round trip named"
expect_stderr_has "mm/deg away, where its contact distances miss these pressures' by 1.2" "offline stall measured"
[ "$(wc -l < "$TMP/err")" -eq 1 ] && ok || bad "offline round trip: one line"
finish
