# The fidelity harness (cli/cli_fidelity.c, bench/bench_fidelity.c) on scenes made for it:
# a rest that exists and leaves the fitted law's domain (named bladder and group) and one
# inside it; a scene named with a comma and a quote in fidelity.csv (RFC 4180: bladder names
# cannot hold either, the scene reader refuses them, but a file's stem can); a plan that
# stops at its iteration limit is not measured; a scene stem longer than 47 characters
# reaches the CSV whole; the law's band the command line states is the one the lab reads from
# the fitted law's error table. The scenes are load_supine.yaml with a light head (0.3 kg, 0.1 kg:
# the load level's pressures then hold a rest under the fitted law, which the 4.5 kg head's
# do not) and a 60 s budget (no row may end by time). No timing.
source "$2/tests/cli_lib.sh"
BENCH="$(dirname "$HP_BIN")/headplan-bench"
base="$HP_SRC/scenarios/load_supine.yaml"
mkdir -p "$TMP/scn"
# scene FILE MASS RI_MM [SED...]: load_supine with mass MASS kg and Ri RI_MM mm.
scene() {
  local f="$1" m="$2" ri="$3"; shift 3
  sed -e "s/mass_kg: 4.5/mass_kg: $m/" -e "s/Ri_mm: 27$/Ri_mm: $ri/" \
      -e 's/max_iter: 200/max_iter: 200, max_time_s: 60/' "$@" "$base" >"$f"
}
# outside: planned with the cap law (load.law: cap; a plan under the fitted law is refused
# when its answer leaves the law's domain, so only another law's plan can rest outside it):
# the 0.1 kg head leaves the base bladders at a low pressure, where their wall/ro (4.5 mm of
# about 45 mm) is above the tables' thickest wall (the "wall" group). inside: Ri 27.2 mm
# side bladders, wall/ro 0.093, planned with the fitted law.
scene "$TMP/outside.yaml" 0.1 27 -e 's/tiebreak: least-squeeze/tiebreak: least-squeeze, law: cap/'
scene "$TMP/inside.yaml" 0.3 27.2

# (b) analyze's model error line at the load level: a rest in each case, flagged by bladder
# and group outside the domain, "in its domain" inside it.
run analyze "$TMP/outside.yaml" --level load
expect_exit 0 "analyze outside"
line=$(grep '^model error' "$TMP/out")
grep -qE 'level load: [0-9.e+-]+ mm, [0-9.e+-]+ deg against the fitted law, up to [^(]* band \(rest outside its domain: [^)]*:wall\)' <<<"$line" \
  && ok || bad "outside: rest outside the domain by wall not said: $line"
grep -qF 'base_neck_left:wall' <<<"$line" && ok || bad "outside: bladder base_neck_left not named: $line"
run analyze "$TMP/inside.yaml" --level load
expect_exit 0 "analyze inside"
line=$(grep '^model error' "$TMP/out")
grep -qE 'level load: [0-9.e+-]+ mm, [0-9.e+-]+ deg against the fitted law, up to [^(]* band \(rest in its domain\)' <<<"$line" \
  && ok || bad "inside: rest in the domain not said: $line"

# (c) A plan stopped by its iteration limit (ipopt, one iteration, a correction it cannot
# reach in one) is not measured: its pressures are not an answer solve prints.
sed -e 's/backend: realtime, tolerance: 1e-9, max_iter: 200/backend: ipopt, tolerance: 1e-9, max_iter: 1, max_time_s: 60/' \
    -e 's/x_mm: 1.0/x_mm: 4.0/' -e 's/pitch_deg: 0.3/pitch_deg: 3/' "$base" >"$TMP/limit.yaml"
run solve "$TMP/limit.yaml" --level surface
expect_stderr_has "iteration-limit" "fixture: solve stops at the iteration limit"
run analyze "$TMP/limit.yaml" --level surface
expect_exit 0 "analyze limit"
grep -qx 'model error   level surface: not measured: plan iteration-limit' "$TMP/out" \
  && ok || bad "limit: not said: $(grep '^model error' "$TMP/out")"

# (a), (b), (d) in the benchmark lab's CSV, read by an RFC 4180 reader.
odd='out, "side"'
cp "$TMP/outside.yaml" "$TMP/scn/$odd.yaml"
cp "$TMP/inside.yaml" "$TMP/scn/inside.yaml"
long=a_scene_stem_of_seventy_characters_for_the_fidelity_harness_0123456789
[ "${#long}" = 70 ] && ok || bad "fixture: stem of ${#long} characters"
cp "$TMP/inside.yaml" "$TMP/scn/$long.yaml"
"$BENCH" --quick --only fidelity --out "$TMP/fid" --scenarios "$TMP/scn" >"$TMP/out" 2>"$TMP/err"
rc=$?
expect_exit 0 "headplan-bench --only fidelity"
# The command line's band (a constant: it is installed without fem/) is the one the lab reads
# from fem/tables/law_error.csv at run time.
run solve "$TMP/inside.yaml" --level load --json
cli_band=$(python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))["model_error"]["law_band"])' "$TMP/out")
python3 - "$TMP/fid/fidelity.csv" "$long" "$odd" "$cli_band" <<'EOF' && ok || bad "fidelity.csv"
import csv, sys
rows = list(csv.reader(open(sys.argv[1], newline="")))
head, body = rows[0], rows[1:]
bad = [r for r in body if len(r) != len(head)]
assert not bad, f"{len(bad)} rows with the wrong number of fields, e.g. {bad[0]}"
col = {n: i for i, n in enumerate(head)}
def cell(scene, level, key):
    return [r[col[key]] for r in body if r[col["scene"]] == scene and r[col["case"]] == "0"
            and r[col["level"]] == level][0]
d = cell(sys.argv[3], "load", "domain")
assert d == "base_neck_left:wall", f"outside load domain {d!r}"
assert cell("inside", "load", "domain") == "in", cell("inside", "load", "domain")
assert float(cell("inside", "load", "pose_mm")) > 0
bands = {float(r[col["law_band"]]) for r in body}
assert bands == {float(sys.argv[4])}, f"law_band {bands} in the CSV, {sys.argv[4]} in solve --json"
assert {r[col["scene"]] for r in body} == {sys.argv[3], "inside", sys.argv[2]}, \
    sorted({r[col["scene"]] for r in body})
EOF
finish
