# examples/slurm/split_trace.sh, resume.sh and join.sh without Slurm (docs/batch.md, "One
# long recording on Slurm"; tests/services/slurm_study.sh runs them on a real Slurm): the
# tasks run by hand, sbatch a stand-in that records its arguments. What counts as missing or
# incomplete (no file, no end of line, another shard's result, rows missing), that resume
# submits exactly those and join refuses naming them, every refused input named with its
# exit status, and the joined result equal to one run byte for byte (the measured columns
# blanked, as `headplan batch --columns` names them) with the modes batch gives its results.
source "$2/tests/cli_lib.sh"
HP_BIN=$(realpath "$HP_BIN"); HP_SRC=$(realpath "$HP_SRC")
E="$HP_SRC/examples/slurm"
cd "$TMP" || exit 1
mkdir bin && ln -s "$HP_BIN" bin/headplan
printf '#!/bin/sh\necho "$@" >> "%s/sbatch.args"\necho "Submitted batch job 7"\n' "$TMP" > bin/sbatch
chmod +x bin/sbatch
export PATH="$TMP/bin:$PATH"
S=$(patient_scenes) || exit 1 # time budgets of 60 s: runs compared plan alike (tests/cli_lib.sh)
cp "$S/default.yaml" study.yaml
cp "$HP_SRC/scenarios/traces/drift_10hz.csv" recording.csv
sh_run() { "$@" >"$TMP/out" 2>"$TMP/err"; rc=$?; }
task() { SLURM_ARRAY_TASK_ID=$1 bash "$E/batch_array.sh" study.yaml shards.txt res 2>/dev/null; }

sh_run "$E/split_trace.sh" recording.csv 0 shards
expect_exit 64 "ROWS 0"; expect_stderr_has "ROWS '0' is not a whole number" "ROWS named"
sh_run "$E/split_trace.sh" nothere.csv 500 shards
expect_exit 66 "no recording"; expect_stderr_has "nothere.csv: cannot open" "recording named"
[ ! -e shards ] && ok || bad "a refused split made its folder"
"$E/split_trace.sh" recording.csv 500 shards > shards.txt 2>"$TMP/err"; rc=$?
expect_exit 0 "split"
[ "$(cat shards.txt)" = "$(printf 'shards/part_%04d.csv\n' 0 1 2 3)" ] && ok || bad "list: $(cat shards.txt)"
for f in shards/part_*.csv; do
    [ "$(head -n 2 "$f")" = "$(head -n 2 recording.csv)" ] && ok || bad "$f lacks the directive and header"
done
[ "$(cat shards/part_*.csv | grep -vc '^[#t]')" -eq 1800 ] && ok || bad "shards do not hold the 1800 rows"
sh_run "$E/split_trace.sh" recording.csv 500 shards
expect_exit 73 "existing folder"; expect_stderr_has "shards: exists" "folder named"

task 0; task 1; task 3
printf '%s' "$(cat res/part_0000.csv)" > cut && mv cut res/part_0000.csv   # no end of line
cp res/part_0003.csv res/part_0001.csv                                   # another shard's
before=$(stat -c '%i %s' res/part_0003.csv)
sh_run "$E/join.sh" recording.csv shards.txt res joined.csv
expect_exit 66 "join with shards not complete"
expect_stderr_has "res/part_0000.csv: incomplete (no end of line at the end)" "cut result"
expect_stderr_has "res/part_0001.csv: not a result of shards/part_0001.csv" "stale result"
expect_stderr_has "res/part_0002.csv: missing" "missing result"
expect_stderr_has "3 of 4 shard results not complete" "count"
[ ! -e joined.csv ] && ok || bad "a refused join wrote its output"
sh_run "$E/resume.sh" study.yaml shards.txt res
expect_exit 0 "resume"
[ "$(cat sbatch.args)" = "--array=0,1,2 $E/batch_array.sh study.yaml shards.txt res" ] && ok \
    || bad "resume submitted: $(cat sbatch.args)"
task 0; task 1; task 2
head -n -1 res/part_0002.csv > cut && mv cut res/part_0002.csv          # a row short
rm sbatch.args
sh_run "$E/resume.sh" study.yaml shards.txt res
expect_stderr_has "res/part_0002.csv: incomplete (499 rows after the header, shards/part_0002.csv has 500)" "short result"
[ "$(cat sbatch.args)" = "--array=2 $E/batch_array.sh study.yaml shards.txt res" ] && ok \
    || bad "resume submitted: $(cat sbatch.args)"
task 2; rm sbatch.args
[ "$before" = "$(stat -c '%i %s' res/part_0003.csv)" ] && ok || bad "a complete result was re-planned"
sh_run "$E/resume.sh" study.yaml shards.txt res
expect_exit 0 "resume with nothing to do"
expect_stderr_has "all 4 results in res are complete; nothing to re-run" "nothing to do"
[ ! -e sbatch.args ] && ok || bad "resume submitted with nothing to do"

sh_run "$E/join.sh" recording.csv shards.txt res res/part_0001.csv
expect_exit 73 "join onto an input"; expect_stderr_has "is one of the inputs" "input named"
(umask 022; "$E/join.sh" recording.csv shards.txt res joined.csv) 2>"$TMP/err"; rc=$?
expect_exit 0 "join"
[ "$(stat -c %a joined.csv)" = 644 ] && ok || bad "joined.csv mode $(stat -c %a joined.csv), want 644"
"$HP_BIN" batch study.yaml recording.csv --no-progress -o one.csv 2>/dev/null
cmp -s <(drop_measured joined.csv) <(drop_measured one.csv) && ok || bad "joined differs from one run"
sh_run "$E/join.sh" recording.csv shards.txt
expect_exit 64 "join usage"
printf 'shards/part_0000.csv\nshards/gone.csv\n' > bad.txt
sh_run "$E/resume.sh" study.yaml bad.txt res
expect_exit 66 "list naming a missing shard"; expect_stderr_has "bad.txt:2: shards/gone.csv: cannot open" "shard named"
finish
