# headplan solve states the model error of the answer it prints (cli/cli_fidelity.c, the
# measurement analyze's `model error` line makes): the same line as analyze's for the same
# scene, level and correction, right after the solver's own error (the pose table's error
# column at the contact levels, the forward statics' rest at the load level), and the same
# numbers under "model_error" in --json. A light head (0.3 kg) on thinner walls makes the load
# level's pressures hold a rest under the fitted law (bounded, in its domain); the catalogue's
# scenes find none (unbounded). No timing.
source "$2/tests/cli_lib.sh"
S="$HP_SRC/scenarios"
sed -e 's/mass_kg: 4.5/mass_kg: 0.3/' -e 's/Ri_mm: 27$/Ri_mm: 27.2/' \
    -e 's/max_iter: 200/max_iter: 200, max_time_s: 60/' "$S/load_supine.yaml" >"$TMP/light.yaml"

# check SCENE LEVEL: solve's model error line is analyze's, and --json carries its numbers.
check() {
  local scene="$1" level="$2" line want
  run analyze "$scene" --level "$level"
  expect_exit 0 "analyze $scene --level $level"
  want=$(sed -nE 's/^model error +//p' "$TMP/out")
  run solve "$scene" --level "$level"
  [ "$rc" -le 1 ] && ok || bad "solve $scene --level $level: exit $rc"
  [ "$(grep -c '^model error' "$TMP/out")" = 1 ] && ok || bad "$scene $level: one model error line"
  line=$(sed -nE 's/^model error +//p' "$TMP/out")
  [ -n "$want" ] && [ "$line" = "$want" ] && ok || bad "$scene $level: solve '$line' != analyze '$want'"
  # Next to the solver's error: the line right after the pose table (contact levels) or the
  # forward statics' line (load level).
  awk -v lv="$level" 'BEGIN { re = lv == "load" ? "^forward statics" : "^yaw_deg " }
                      /^model error/ { exit !(prev ~ re) }
                      NF { prev = $0 }' "$TMP/out" && ok || bad "$scene $level: model error not after the solver's error"
  run solve "$scene" --level "$level" --json
  [ "$rc" -le 1 ] && ok || bad "solve --json $scene --level $level: exit $rc"
  python3 - "$TMP/out" "$line" "$level" <<'EOF' && ok || bad "$scene $level: --json model_error"
import json, re, sys
o = json.load(open(sys.argv[1]))["model_error"]
line, level = sys.argv[2], sys.argv[3]
assert o["level"] == level and o["measured"] is True and o["law"] == "fitted", o
assert o["mass"] in ("scene", "default") and o["mass_kg"] > 0, o
m = re.search(r": ([0-9.e+-]+) mm, ([0-9.e+-]+) deg against the fitted law, up to ([0-9.e+-]+) mm, "
              r"([0-9.e+-]+) deg with its ±([0-9.]+) % band \(rest (in its domain|outside its domain: (\S+))\)", line)
if o["bounded"]:
    assert m, line
    for k, g in (("pose_mm", 1), ("pose_deg", 2), ("band_mm", 3), ("band_deg", 4)):
        assert f"{o[k]:.4g}" == m.group(g), (k, o[k], m.group(g))
    assert o["band_mm"] >= o["pose_mm"] and o["band_deg"] >= o["pose_deg"], o
    assert f"{100 * o['law_band']:.3g}" == m.group(5), (o["law_band"], m.group(5))
    assert o["domain"] == ("in" if m.group(6) == "in its domain" else m.group(7)), o
else:
    assert o["pose_mm"] is None and o["domain"] == "no rest", o
    assert "unbounded (no rest under the fitted law" in line, line
assert f"solver tolerance {o['solver_tolerance']:g} mm and deg" in line, line
EOF
}
check "$TMP/light.yaml" load
check "$TMP/light.yaml" surface
check "$S/default.yaml" plane
check "$S/load_supine.yaml" load
finish
