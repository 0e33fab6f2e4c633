# headplan analyze and headplan solve agree on a layout that barely identifies rotations: a
# near-spherical head (90 / 90.01 / 90.02 mm) held by six bladders (the first six rays of the
# default scene). Along each axis, solve at 99 % of the reach analyze prints answers `reached`
# (exit 0): the reach is where solve's own test holds, every bladder inside its limits AND
# the pressures' forward contact kinematics from the nominal pose giving the pose back.
# Before, analyze printed the limits' reach alone and solve refused (exit 65, "outside the
# identifiable range") at 99 % of it on x, +y and z. Also at 50 % and 90 % (the reach is the
# first boundary along the axis, so everything short of it is reached), and on every axis
# with a reach below the search cap.
source "$2/tests/cli_lib.sh"
cat > "$TMP/ns6.yaml" <<'YAML'
headplan_scene: 1
name: near-spherical six
head: {shape: ellipsoid, semi_axes_mm: [90, 90.01, 90.02], center_mm: [0, 0, 0], mass_kg: 4.5}
pivot_mm: [0, 0, 0]
bladder_defaults:
  Ri_mm: 27
  Ro_mm: 30
  material: {convention: paper, C1_pa: 1.1e4, C2_pa: 2.2e4}
  pressure_min_kpa: -5
  pressure_max_kpa: 10
  stretch_min: 0.8
  stretch_max: 1.3
bladders:
  - {name: b0, touch_dir: [ 0.35, -0.45, -1]}
  - {name: b1, touch_dir: [-0.35, -0.45, -1]}
  - {name: b2, touch_dir: [ 0.35,  0.45, -1]}
  - {name: b3, touch_dir: [-0.35,  0.45, -1]}
  - {name: b4, touch_dir: [ 1,  0.45,  0.15]}
  - {name: b5, touch_dir: [-1,  0.45,  0.15]}
model: {level: surface}
YAML
for level in surface plane; do
    run analyze "$TMP/ns6.yaml" --json --level "$level"
    expect_exit 0 "analyze ($level)"
    python3 - "$TMP/out" > "$TMP/cases" <<'PY' || bad "reach cases ($level)"
import json, sys
d = json.load(open(sys.argv[1]))
for i, k in enumerate(["x_mm", "y_mm", "z_mm", "pitch_deg", "roll_deg", "yaw_deg"]):
    for r in d["reach"][k] or []:
        if abs(r) >= (50 if i < 3 else 30) or r == 0: continue
        for f in (0.5, 0.9, 0.99):
            c = [0.0] * 6
            c[i] = f * r
            print(",".join(repr(x) for x in c))
PY
    n=$(wc -l < "$TMP/cases")
    [ "$n" -ge 9 ] && ok || bad "$level: only $n reach cases"
    while read -r corr; do
        run solve "$TMP/ns6.yaml" --level "$level" --correction "$corr"
        expect_exit 0 "$level: solve at $corr"
    done < "$TMP/cases"
done
finish
