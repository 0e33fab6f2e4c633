# The Slurm recipe of docs/batch.md ("One long recording on Slurm") against a real Slurm:
# munged, slurmctld and slurmd started here on 127.0.0.1 (slurm_lib.sh), the doc's blocks
# taken from the file and run as written on the 1800-row drift trace in 4 shards. One task
# is cancelled with scancel while headplan plans its shard, another task's result is cut
# short; the join refuses and names both, resume re-submits exactly those two and nothing
# else, and the joined result equals one process's `headplan batch` byte for byte (the
# measured columns, as `headplan batch --columns` names them, blanked in both). Skipped,
# saying why, where the services cannot start (not root, packages missing). Every wait polls with a generous bound: the CI machine
# is loaded on purpose, and nothing here asserts a time.
source "$2/tests/cli_lib.sh"
source "$2/tests/services/slurm_lib.sh"
HP_BIN=$(realpath "$HP_BIN"); HP_SRC=$(realpath "$HP_SRC")
cleanup() {
    if [ ${#slurm_pids[@]} -gt 0 ]; then
        scancel --quiet --user="$(id -un)" 2>/dev/null
        slurm_wait 60 slurm_queue_empty
        slurm_stop
    fi
    rm -rf "$TMP"
}
trap cleanup EXIT
trap 'exit 143' TERM INT HUP
slurm_queue_empty() { [ -z "$(squeue -h -o %i 2>/dev/null)" ] && squeue >/dev/null 2>&1; }
if ! slurm_start "$TMP/slurm"; then echo "SKIP: Slurm cannot start here: $slurm_why"; exit 0; fi
cd "$TMP" || exit 1

# headplan on PATH for the jobs (sbatch passes the environment on). Its first run on shard 2
# reads the shard through a pipe that stays open, so it is mid-run (its temporary output
# created, the rows read, waiting for more) when the test cancels it.
mkdir bin
cat > bin/headplan <<WRAP
#!/bin/bash
for a; do
    case \$a in */part_0002.csv)
        if mkdir "$TMP/victim_started" 2>/dev/null; then
            args=(); for b; do [ "\$b" = "\$a" ] && b=-; args+=("\$b"); done
            { cat "\$a"; sleep 600; } | "$HP_BIN" "\${args[@]}"
            exit
        fi;;
    esac
done
exec "$HP_BIN" "\$@"
WRAP
chmod +x bin/headplan
export PATH="$TMP/bin:$PATH"
mkdir -p examples && cp -r "$HP_SRC/examples/slurm" examples/
cp "$HP_SRC/scenarios/default.yaml" study.yaml
cp "$HP_SRC/scenarios/traces/drift_10hz.csv" recording.csv
# doc_block TEXT: the ```sh block of docs/batch.md that contains TEXT (fixed string).
doc_block() {
    awk -v pat="$1" '/^```/ { if (inb) { if (index(b, pat)) { printf "%s", b; exit } inb = 0; next }
                               if ($0 ~ /^```sh( |$)/) { inb = 1; b = "" } next }
                     inb { b = b $0 "\n" }' "$HP_SRC/docs/batch.md"
}
doc_run() {   # doc_run TEXT: runs that block here; status in $rc, output in $TMP/out, err
    local blk; blk=$(doc_block "$1")
    [ -n "$blk" ] || { rc=99; echo "no block with '$1' in docs/batch.md" > "$TMP/err"; return; }
    bash -e -c "$blk" >"$TMP/out" 2>"$TMP/err"; rc=$?
}
array_done() { [ -z "$(squeue -h -j "$1" -o %i 2>/dev/null)" ] && squeue >/dev/null 2>&1; }
job_of() { sed -n 's/^Submitted batch job \([0-9][0-9]*\).*/\1/p' "$TMP/out"; }

doc_run "examples/slurm/split_trace.sh recording.csv"
expect_exit 0 "split block"
[ "$(wc -l < shards.txt)" -eq 4 ] && ok || bad "want 4 shards of 500 rows, list has $(wc -l < shards.txt)"

doc_run 'sbatch --array=0-$(( $(wc -l < shards.txt)'
expect_exit 0 "sbatch block"
job=$(job_of)
[ -n "$job" ] && ok || bad "sbatch printed no job id"
# Task 2 is mid-run once headplan has created its temporary output.
if slurm_wait 240 compgen -G "shard_results/part_0002.csv.partial-*"; then ok
else bad "task 2 never started planning: $(squeue 2>&1 | tail -n 3)"; fi
scancel "${job}_2"; rc=$?
expect_exit 0 "scancel ${job}_2"
slurm_wait 300 array_done "$job" && ok || bad "array $job did not end: $(squeue 2>&1 | tail -n 3)"
[ ! -e shard_results/part_0002.csv ] && ok || bad "the cancelled task left a result"
compgen -G "shard_results/*.partial-*" >/dev/null && bad "the cancelled task left its temporary file" || ok
for i in 0 1 3; do
    [ -f "shard_results/part_000$i.csv" ] && ok || bad "task $i wrote no result"
done
# A result cut short (a copy that stopped early): its last row gone.
head -n -1 shard_results/part_0000.csv > cut && mv cut shard_results/part_0000.csv
before=$(stat -c '%i %s' shard_results/part_0001.csv shard_results/part_0003.csv)

doc_run "examples/slurm/join.sh recording.csv"
expect_exit 66 "join with two shard results not complete"
expect_stderr_has "shard_results/part_0000.csv: incomplete (499 rows after the header" "cut result named"
expect_stderr_has "shard_results/part_0002.csv: missing" "cancelled result named"
[ ! -e joined_slurm.csv ] && ok || bad "a refused join wrote joined_slurm.csv"

doc_run "examples/slurm/resume.sh study.yaml"
expect_exit 0 "resume block"
expect_stderr_has "sbatch --array=0,2 " "resume submits exactly shards 0 and 2"
job2=$(job_of)
[ -n "$job2" ] && ok || bad "resume submitted no job"
slurm_wait 300 array_done "$job2" && ok || bad "resumed array $job2 did not end"
[ "$before" = "$(stat -c '%i %s' shard_results/part_0001.csv shard_results/part_0003.csv)" ] \
    && ok || bad "resume re-planned a complete result"
doc_run "examples/slurm/resume.sh study.yaml"
expect_exit 0 "second resume"
expect_stderr_has "all 4 results in shard_results are complete; nothing to re-run" "nothing left"
[ ! -s "$TMP/out" ] && ok || bad "the second resume submitted something"

# The join block's plot line draws with gnuplot; its reading of the file is what matters
# here, so the block runs with plot's --dry-run.
blk=$(doc_block "examples/slurm/join.sh recording.csv" | sed 's/^headplan plot \(.*\)$/headplan plot \1 --dry-run/')
bash -e -c "$blk" >"$TMP/out" 2>"$TMP/err"; rc=$?
expect_exit 0 "join block (plot reading the joined result)"
"$HP_BIN" batch study.yaml recording.csv --no-progress -o one.csv 2>/dev/null
[ "$(grep -vc '^#' joined_slurm.csv)" -eq 1801 ] && ok || bad "joined: want a header and 1800 rows"
[ "$(grep -c '^# headplan_batch:' joined_slurm.csv)" -eq 1 ] && ok || bad "joined: want one metadata record"
cmp -s <(drop_measured joined_slurm.csv) <(drop_measured one.csv) && ok \
    || bad "joined differs from one run: $(diff <(drop_measured joined_slurm.csv) <(drop_measured one.csv) | head -c 300)"
finish
