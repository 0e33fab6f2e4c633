# examples/slurm/batch_array.sh (docs/batch.md, "Studies larger than one machine"): the Slurm
# job script run without Slurm, with SLURM_ARRAY_TASK_ID set by hand as sbatch would set it.
# Each index plans its line of the list into the results folder (created); an index past the
# list, or no index, is refused by name before anything is planned.
source "$2/tests/cli_lib.sh"
HP_BIN=$(realpath "$HP_BIN"); HP_SRC=$(realpath "$HP_SRC")
JOB="$HP_SRC/examples/slurm/batch_array.sh"
S="$HP_SRC/scenarios"
cd "$TMP" || exit 1
mkdir bin && ln -s "$HP_BIN" bin/headplan          # the job finds headplan on PATH
cp "$S/default.yaml" study.yaml
mkdir traces && head -n 52 "$S/traces/drift_10hz.csv" > traces/drift.csv
head -n 32 "$S/traces/nodding.csv" > traces/nod.csv
printf '%s\n' traces/drift.csv traces/nod.csv > traces.txt
job() { env "$@" PATH="$TMP/bin:$PATH" bash "$JOB" study.yaml traces.txt results \
        >"$TMP/out" 2>"$TMP/err"; rc=$?; }

job SLURM_ARRAY_TASK_ID=0
expect_exit 0 "task 0"
[ -f results/drift.csv ] && [ "$(grep -vc '^#' results/drift.csv)" -eq 51 ] && ok \
  || bad "task 0 did not write results/drift.csv with a header and 50 rows"
job SLURM_ARRAY_TASK_ID=1
expect_exit 0 "task 1"
[ -f results/nod.csv ] && ok || bad "task 1 did not write results/nod.csv"
# The array range the docs derive from the list: 0 .. lines - 1.
[ "$(( $(wc -l < traces.txt) - 1 ))" -eq 1 ] && ok || bad "array range"

job SLURM_ARRAY_TASK_ID=2
expect_exit 64 "index past the list"
expect_stderr_has "SLURM_ARRAY_TASK_ID 2 is past the end of traces.txt (2 lines: 0-1)" "past the end"
[ "$(ls results | wc -l)" -eq 2 ] && ok || bad "a refused task wrote something"
job SLURM_ARRAY_TASK_ID=one
expect_exit 64 "index not a number"; expect_stderr_has "SLURM_ARRAY_TASK_ID 'one'" "not a number"
job -u SLURM_ARRAY_TASK_ID
expect_exit 64 "no index"; expect_stderr_has "SLURM_ARRAY_TASK_ID is not set" "no index"
printf 'traces/drift.csv\n\n' > traces.txt
job SLURM_ARRAY_TASK_ID=1
expect_exit 65 "empty line"; expect_stderr_has "traces.txt:2: empty line" "empty line named"
rm traces.txt
job SLURM_ARRAY_TASK_ID=0
expect_exit 66 "no list"; expect_stderr_has "traces.txt: cannot open" "missing list named"
finish
