# The GNU parallel recipe of docs/batch.md ("One long recording, split"), run as written on
# a split trace: the joined output equals one run of the whole trace, row for row (every
# column but `line`, which counts lines of each piece). Needs GNU parallel (Debian package
# `parallel`); skipped with a note when it is missing.
source "$2/tests/cli_lib.sh"
command -v parallel >/dev/null || { echo "SKIP: GNU parallel not installed"; exit 0; }
HP_BIN=$(realpath "$HP_BIN"); HP_SRC=$(realpath "$HP_SRC")
S="$HP_SRC/scenarios"
cd "$TMP" || exit 1
headplan() { "$HP_BIN" "$@"; }
export -f headplan; export HP_BIN
cp "$S/default.yaml" study.yaml
sed -i 's#^trace:.*#trace: {file: '"$S"'/traces/drift_10hz.csv, rows: deviation}#' study.yaml
cp "$S/traces/drift_10hz.csv" recording.csv

# ---- the recipe (docs/batch.md), with headplan the binary under test ----
mkdir -p pieces results
head -n 2 recording.csv > header.csv
tail -n +3 recording.csv | split -l 400 -d -a 3 --additional-suffix=.csv \
  --filter='cat header.csv - > "$FILE"' - pieces/part_
parallel --jobs 2 --halt now,fail=1 \
  headplan batch study.yaml {} --no-progress --no-times -o results/{/.}.csv ::: pieces/*.csv
rc=$?
for f in results/part_*.csv; do grep -v '^#' "$f" | tail -n +2; done > joined.csv
# ---- end of the recipe ----

expect_exit 0 "parallel recipe"
[ "$(ls pieces | wc -l)" -eq 5 ] && ok || bad "the trace was not split in 5 pieces"
"$HP_BIN" batch study.yaml recording.csv --no-progress --no-times -o one.csv 2>/dev/null
grep -v '^#' one.csv | tail -n +2 > one_rows.csv
[ "$(wc -l < joined.csv)" -eq 1800 ] && ok || bad "joined output has $(wc -l < joined.csv) rows"
cmp -s <(cut -d, -f2- joined.csv) <(cut -d, -f2- one_rows.csv) && ok \
  || bad "joined pieces differ from one run"
finish
