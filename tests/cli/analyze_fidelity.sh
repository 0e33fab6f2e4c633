# headplan analyze: the model error line, the scene's plan (its correction at the level solve
# uses) against the finite-element reference, next to the solver's tolerance. One home with
# the benchmark lab's fidelity family (cli/cli_fidelity.c): on the same scene, level and
# correction the line's numbers are that family's case 0 row (pose_mm, pose_deg, carried),
# printed to 4 significant digits. No timing.
source "$2/tests/cli_lib.sh"
S="$HP_SRC/scenarios"
BENCH="$(dirname "$HP_BIN")/headplan-bench"

"$BENCH" --quick --only fidelity --out "$TMP/fid" --scenarios "$S" >/dev/null 2>&1 \
  && ok || bad "headplan-bench --only fidelity"
csv="$TMP/fid/fidelity.csv"

for scene in default load_supine sphere_head; do
  run analyze "$S/$scene.yaml"
  expect_exit 0 "analyze $scene"
  line=$(grep '^model error' "$TMP/out")
  [ "$(grep -c '^model error' "$TMP/out")" = 1 ] && ok || bad "$scene: one model error line"
  level=$(sed -n 's/^model error *level \([a-z]*\):.*/\1/p' <<<"$line")
  [ -n "$level" ] && ok || bad "$scene: the line names the level: $line"
  tol=$(awk -F, -v s="$scene" 'NR > 1 && $1 == s && $2 == 0 { print $8; exit }' "$csv")
  grep -q "solver tolerance $tol mm and deg" <<<"$line" && ok || bad "$scene: solver tolerance $tol: $line"
  # The same computation: the bench's row for case 0 at that level.
  want=$(awk -F, -v s="$scene" -v l="$level" 'NR > 1 && $1 == s && $2 == 0 && $3 == l {
      if ($11 == "inf") printf "unbounded (no rest under the fitted law; the pressures bear %.0f %% of the weight", 100 * $16 + 0
      else printf "%.4g mm, %.4g deg against the fitted law, up to %.4g mm, %.4g deg", $11, $12, $13, $14 }' "$csv")
  [ -n "$want" ] && grep -qF "$want" <<<"$line" && ok || bad "$scene: '$want' not in: $line"
  # Not in the JSON: its keys stay as they are.
  run analyze "$S/$scene.yaml" --json
  expect_exit 0 "analyze $scene --json"
done
# A scene whose head states no mass says the default head's weight was assumed.
run analyze "$S/sphere_head.yaml"
grep '^model error' "$TMP/out" | grep -q "default head" && ok || bad "sphere_head: default head not said"
finish
