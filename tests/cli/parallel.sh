# The GNU parallel recipe of docs/batch.md ("One long recording, split"), taken from the
# docs (the ```sh block that splits the recording) and run as written on the 1800-row drift
# trace: the joined output is one result (one metadata record, one header) that plot reads,
# and equals one run of the whole trace, row for row (every column but `line`, which counts
# lines of each piece). Needs GNU parallel (Debian package `parallel`); skipped with a note
# when it is missing.
source "$2/tests/cli_lib.sh"
command -v parallel >/dev/null || { echo "SKIP: GNU parallel not installed"; exit 0; }
HP_BIN=$(realpath "$HP_BIN"); HP_SRC=$(realpath "$HP_SRC")
S=$(patient_scenes) || exit 1 # time budgets of 60 s: runs compared plan alike (tests/cli_lib.sh)
cd "$TMP" || exit 1
mkdir bin && ln -s "$HP_BIN" bin/headplan && export PATH="$TMP/bin:$PATH"
cp -r "$S" scenarios
cp "$S/default.yaml" study.yaml
# The recipe: the fenced sh block of docs/batch.md that contains "split -l".
awk '/^```/ { if (inb) { if (b ~ /split -l/) { printf "%s", b; exit } inb = 0; next }
              if ($0 ~ /^```sh$/) { inb = 1; b = "" } next }
     inb { b = b $0 "\n" }' "$HP_SRC/docs/batch.md" > recipe.sh
grep -q 'split -l' recipe.sh && ok || bad "no split recipe in docs/batch.md"
# plot's gnuplot step is not this test's business: only its reading of the joined file.
sed -i 's/^headplan plot \(.*\)$/headplan plot \1 --dry-run/' recipe.sh
bash -e recipe.sh >"$TMP/out" 2>"$TMP/err"; rc=$?
expect_exit 0 "the recipe as written (plot reading joined.csv)"
[ "$(ls pieces | wc -l)" -eq 5 ] && ok || bad "the trace was not split in 5 pieces"
[ "$(grep -c '^# headplan_batch:' joined.csv)" -eq 1 ] && ok || bad "joined: want one metadata record"
[ "$(grep -c '^line,' joined.csv)" -eq 1 ] && ok || bad "joined: want one header"
headplan batch study.yaml recording.csv --no-progress --no-times -o one.csv 2>/dev/null
grep -v '^#' one.csv | tail -n +2 > one_rows.csv
grep -v '^#' joined.csv | tail -n +2 > joined_rows.csv
[ "$(wc -l < joined_rows.csv)" -eq 1800 ] && ok || bad "joined output has $(wc -l < joined_rows.csv) rows"
cmp -s <(cut -d, -f2- joined_rows.csv) <(cut -d, -f2- one_rows.csv) && ok \
  || bad "joined pieces differ from one run"
finish
