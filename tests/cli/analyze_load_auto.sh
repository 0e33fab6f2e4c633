# headplan analyze's load section says what auto decides about the load with the planner's
# own decision (hp_planner_level_for, the code hp_planner_create runs): for a scene with a
# load section and model.level auto, its "auto" line (text and --json load.auto) is the
# reason `headplan solve` gives for the level it plans at ("level choice:" or "why"), word for
# word, whether auto takes the load level (load_supine: the contact levels' pressures find
# no rest under the head's weight) or keeps a contact level (the same scene with a 0.05 kg
# head, its base preloaded 2 mm too (its sides are), with a 100 mm tolerance: a model error
# within it).
. "$(dirname "$0")/../cli_lib.sh"
cd "$TMP" || exit 1
sed -e 's/Ro_mm: 45}/Ro_mm: 45, preload_mm: 2}/' -e 's/mass_kg: 4.5/mass_kg: 0.05/' \
    -e 's/tolerance_mm: 0.01/tolerance_mm: 100/' "$HP_SRC/scenarios/load_supine.yaml" >kept.yaml
cp "$HP_SRC/scenarios/load_supine.yaml" load.yaml
for scene in load.yaml kept.yaml; do
    run solve "$scene"
    expect_exit 0 "solve $scene"
    # The kinematic table says "level choice: REASON", the load level's table "why REASON".
    want=$(sed -n -e 's/^level choice: //p' -e 's/^why  *//p' "$TMP/out")
    [ -n "$want" ] && ok || bad "solve $scene: no level choice line"
    run analyze "$scene"
    expect_exit 0 "analyze $scene"
    got=$(sed -n 's/^auto  *//p' "$TMP/out" | grep -v '^picks')
    [ "$got" = "$want" ] && ok || bad "analyze $scene: auto line '$got', want '$want'"
    run analyze "$scene" --json
    expect_exit 0 "analyze $scene --json"
    got=$(python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))["load"]["auto"])' "$TMP/out")
    [ "$got" = "$want" ] && ok || bad "analyze $scene --json: load.auto '$got', want '$want'"
done
# The kept scene really keeps a contact level (else the test would not tell the two apart).
grep -q '^auto chose linear by model error' <<<"$want" && ok || bad "kept.yaml: auto did not keep a contact level: $want"
finish
