# Level names: every path names its level honestly. analyze takes the level names
# solve takes (one table, hp_scene_level_names), and batch states what auto chose and why in
# its metadata record, in the words solve prints ("level choice: ...").
source "$2/tests/cli_lib.sh"
HP_BIN=$(realpath "$HP_BIN"); HP_SRC=$(realpath "$HP_SRC")
S="$HP_SRC/scenarios"

# analyze --level load was "unknown level 'load'" although solve accepts it. On a scene with
# a load section it is the load level's analysis (as solve plans it); on one without, the
# refusal solve gives, word for word, exit 64.
for cmd in solve analyze; do
    run $cmd "$S/default.yaml" --level load
    expect_exit 64 "$cmd --level load without a load section"; expect_stdout_empty "$cmd --level load"
    [ "$(cat "$TMP/err")" = "headplan $cmd: --level: load needs a scene with a 'load' section ($S/default.yaml has none)" ] \
        && ok || bad "$cmd --level load: message"
    run $cmd "$S/default.yaml" --level exact
    expect_exit 64 "$cmd --level exact"
    [ "$(cat "$TMP/err")" = "headplan $cmd: --level: unknown level 'exact' (linear, plane, surface, auto, load)" ] \
        && ok || bad "$cmd --level exact: message names every level"
done
run analyze "$S/load_tilted.yaml" --level load
expect_exit 0 "analyze --level load on a load scene"
expect_stdout_has "solve plans this scene at the load level (load: asked for by --level)" "analyze --level load note"
expect_stdout_has "load at the nominal pose" "analyze --level load: the load section"
run analyze "$S/load_tilted.yaml" --level load --json
expect_exit 0 "analyze --level load --json"
python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); assert d["solve_level"]=="load", d["solve_level"]; assert d["load"] is not None' "$TMP/out" \
    && ok || bad "analyze --level load --json: solve_level load with the load object"
# --level surface on the same scene: analysed (and solved) kinematically.
run analyze "$S/load_tilted.yaml" --level surface --json
python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); assert d["solve_level"]=="surface"' "$TMP/out" \
    && ok || bad "analyze --level surface --json: solve_level surface"

# batch of a scene at level auto: its metadata record says what auto chose and why, the same
# text solve prints; a stated level has no choice to explain (null / "none").
run solve "$S/default.yaml"
want=$(sed -n 's/^level choice: //p' "$TMP/out")
[ -n "$want" ] && ok || bad "solve of the default scene states no level choice"
run batch "$S/default.yaml" --format csv --no-progress -o "$TMP/b.csv"
expect_exit 0 "batch csv"
grep -qxF "# level_choice: $want" "$TMP/b.csv" && ok || bad "batch csv: level_choice is not solve's '$want'"
run batch "$S/default.yaml" --format jsonl --no-progress -o "$TMP/b.jsonl"
expect_exit 0 "batch jsonl"
python3 -c 'import json,sys; d=json.loads(open(sys.argv[1]).readline()); assert d["level_choice"]==sys.argv[2], d.get("level_choice")' "$TMP/b.jsonl" "$want" \
    && ok || bad "batch jsonl: level_choice is not solve's"
run batch "$S/default.yaml" --level plane --format jsonl --no-progress -o "$TMP/p.jsonl"
python3 -c 'import json,sys; d=json.loads(open(sys.argv[1]).readline()); assert "level_choice" in d and d["level_choice"] is None' "$TMP/p.jsonl" \
    && ok || bad "batch --level plane jsonl: level_choice not null"
run batch "$S/default.yaml" --level plane --format csv --no-progress -o "$TMP/p.csv"
grep -qxF "# level_choice: none (the level is stated, not auto)" "$TMP/p.csv" && ok || bad "batch --level plane csv: level_choice"
# render's picture carries the same text under the panels (its script, --dry-run); none for
# a stated level.
run render "$S/default.yaml" --dry-run
expect_exit 0 "render --dry-run"
grep -qF "\"level choice: $want\"" "$TMP/out" && ok || bad "render: the picture lacks solve's level choice"
run render "$S/default.yaml" --level surface --dry-run
grep -qF "level choice" "$TMP/out" && bad "render --level surface: a level choice for a stated level" || ok
# The result stays readable by plot (plot reads CSV results, metadata comments included).
if command -v gnuplot > /dev/null; then
    for f in b.csv; do
        run plot "$TMP/$f" --scene "$S/default.yaml" -o "$TMP/$f.svg"
        expect_exit 0 "plot of a batch result with level_choice ($f)"
    done
fi
finish
