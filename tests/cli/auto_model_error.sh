# auto on a scene that states its load picks the level by the model error (the fidelity
# measurement, planner/model_error.c), not by the predicted sag: the plan of the scene's
# correction at each level (settings auto_pose; tests/cli/auto_pose.sh checks that the pose
# decides), its pressures rested under the head's weight with the fitted contact law; a
# contact level adds its geometry's error bound over the auto range. The cheapest level within
# model.tolerance_mm (and as many degrees times solver.weight_mm_per_deg) wins, else the
# smallest error (no rest anywhere: the most weight carried). The reason's numbers are
# checked against a direct measurement: `solve --level L` of the same correction and its
# model_error. analyze's auto line is solve's reason, word for word. A scene with no load
# keeps the geometry's bounds and says so. No timing.
source "$2/tests/cli_lib.sh"
S="$HP_SRC/scenarios"
# A 0.05 kg head on bladders preloaded 2 mm: the contact levels' pressures hold it (a rest
# about 0.3 mm from the correction); the 4.5 kg head rests far from it.
light() {
  sed -e 's/mass_kg: 4.5/mass_kg: 0.05/' -e 's/Ro_mm: 45}/Ro_mm: 45, preload_mm: 2}/' \
      -e "s/tolerance_mm: 0.01/tolerance_mm: $1/" \
      -e 's/max_iter: 200/max_iter: 200, max_time_s: 60/' "$S/load_supine.yaml"
}
light 100 >"$TMP/wide.yaml"
light 0.01 >"$TMP/tight.yaml"
sed -e 's/Ro_mm: 45}/Ro_mm: 45, preload_mm: 2}/' -e 's/tolerance_mm: 0.01/tolerance_mm: 10/' \
    -e 's/max_iter: 200/max_iter: 200, max_time_s: 60/' "$S/load_supine.yaml" >"$TMP/heavy.yaml"

# direct SCENE LEVEL: the level's plan of the scene's correction measured by solve, in the
# reason's words: "LEVEL MM mm, DEG deg" (%.3g) or "LEVEL no rest (C % carried)".
direct() {
  "$HP_BIN" solve "$1" --level "$2" --json >"$TMP/d.json" 2>/dev/null
  python3 -c '
import json, sys
m = json.load(open(sys.argv[1]))["model_error"]
if m["pose_mm"] is None: print("%s no rest (%.0f %% carried)" % (sys.argv[2], 100 * m["carried"] + 0.0))
else: print("%s %.3g mm, %.3g deg" % (sys.argv[2], m["pose_mm"], m["pose_deg"]))' "$TMP/d.json" "$2"
}
# has WHY SCENE LEVEL BOUNDED: the reason holds the direct measurement, with or without a
# rest (BOUNDED 1 or 0; "-" either).
has() {
  local want
  want=$(direct "$2" "$3")
  case "$4" in
    1) [[ "$want" != *"no rest"* ]] || { bad "fixture: $2 $3 finds no rest"; return; } ;;
    0) [[ "$want" == *"no rest"* ]] || { bad "fixture: $2 $3 finds a rest"; return; } ;;
  esac
  grep -qF "$want" <<<"$1" && ok || bad "$2: '$want' not in: $1"
}
# reason SCENE: solve's level choice line ("level choice:" or the load table's "why").
reason() {
  run solve "$1"
  [ "$rc" -le 1 ] && ok || bad "solve $1: exit $rc"
  sed -n -e 's/^level choice: //p' -e 's/^why  *//p' "$TMP/out"
}
# Same reason from analyze (its load section's auto line).
same_in_analyze() {
  run analyze "$1"
  expect_exit 0 "analyze $1"
  local got
  got=$(sed -n 's/^auto  *//p' "$TMP/out" | grep -v '^picks')
  [ "$got" = "$2" ] && ok || bad "analyze $1: auto '$got', solve '$2'"
}

# wide: linear's model error (0.3 mm) plus its geometry bound is within 100 mm: linear, which
# the predicted sag (finite, within 100 mm) also kept kinematic.
why=$(reason "$TMP/wide.yaml")
grep -q '^backend .*(contact level linear)' "$TMP/out" && ok || bad "wide: not linear: $why"
grep -qF "auto chose linear by model error at the pose x 1 mm, y 0 mm, z -0.5 mm, pitch 0.3 deg, roll 0 deg, yaw -0.2 deg" <<<"$why" && ok || bad "wide: reason: $why"
has "$why" "$TMP/wide.yaml" linear 1
same_in_analyze "$TMP/wide.yaml" "$why"

# tight: no contact level meets 0.01 mm (0.3 mm); the load level's error is smaller: load.
why=$(reason "$TMP/tight.yaml")
grep -q '^level *load' "$TMP/out" && ok || bad "tight: not load: $why"
grep -qF "auto chose load by model error" <<<"$why" && ok || bad "tight: reason: $why"
has "$why" "$TMP/tight.yaml" linear 1
has "$why" "$TMP/tight.yaml" load 1
same_in_analyze "$TMP/tight.yaml" "$why"

# heavy: under the 4.5 kg head the contact levels' pressures rest the head well over 10 mm
# from the correction (about 16 mm): no contact level meets a 10 mm tolerance, and the
# load level's pressures hold it where it plans: load, by the model error.
why=$(reason "$TMP/heavy.yaml")
grep -q '^level *load' "$TMP/out" && ok || bad "heavy: not load: $why"
has "$why" "$TMP/heavy.yaml" surface 1
has "$why" "$TMP/heavy.yaml" load -
same_in_analyze "$TMP/heavy.yaml" "$why"

# A load the bladders cannot carry (load_prone.yaml, level auto): the load level cannot be
# planned and no contact level meets the tolerance, so auto takes the load level, whose
# refusal says why, rather than a contact level that leaves the weight out.
sed 's/level: load/level: auto/' "$S/load_prone.yaml" >"$TMP/prone.yaml"
run solve "$TMP/prone.yaml"
expect_exit 65 "solve prone (auto)"
expect_stderr_has "load: the bladders can carry at most" "solve prone (auto)"

# No load: the geometry's bounds, as before, and the reason says why.
why=$(reason "$S/default.yaml")
grep -q "^auto chose surface: the error bounds of linear (1.56 mm) and plane (0.969 mm) exceed model.tolerance_mm 0.01 for corrections up to 5 mm, 3 deg" <<<"$why" \
  && ok || bad "default: reason changed: $why"
grep -qF "no load stated" <<<"$why" && ok || bad "default: the reason does not say the weight is left out: $why"
finish
