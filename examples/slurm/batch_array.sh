#!/bin/bash
# A Slurm job array of headplan batch runs, one trace per task (docs/batch.md):
#
#   sbatch --array=0-$(( $(wc -l < traces.txt) - 1 )) examples/slurm/batch_array.sh \
#          study.yaml traces.txt results
#
# Task i plans line i + 1 of the list (one trace path per line) with the scene and writes
# RESULTS/NAME.csv, NAME the trace's file name without .csv. The array range comes from the
# list, and a task whose index is past the list is refused by name (exit 64), so a stale
# range cannot plan an empty file name. Without Slurm, run a task by hand:
#   SLURM_ARRAY_TASK_ID=0 bash examples/slurm/batch_array.sh study.yaml traces.txt results
#SBATCH --cpus-per-task=2
set -u
me=batch_array.sh
if [ $# -ne 3 ]; then
    echo "usage: $me SCENE LIST RESULTS (one trace per line of LIST; task i plans line i + 1)" >&2
    exit 64
fi
scene=$1 list=$2 out=$3
i=${SLURM_ARRAY_TASK_ID-}
if [ -z "${SLURM_ARRAY_TASK_ID+set}" ]; then
    echo "$me: SLURM_ARRAY_TASK_ID is not set (sbatch --array sets it; set it by hand to run one task)" >&2
    exit 64
fi
if ! [[ $i =~ ^[0-9]+$ ]]; then
    echo "$me: SLURM_ARRAY_TASK_ID '$i' is not a task index (0, 1, ...)" >&2
    exit 64
fi
if ! [ -r "$list" ] || ! mapfile -t traces < "$list"; then
    echo "$me: $list: cannot open" >&2
    exit 66
fi
n=${#traces[@]}
if (( n == 0 )); then
    echo "$me: $list: no trace in it (empty)" >&2
    exit 65
fi
if (( 10#$i >= n )); then
    echo "$me: SLURM_ARRAY_TASK_ID $i is past the end of $list ($n lines: 0-$((n - 1)));" \
         "submit with --array=0-\$(( \$(wc -l < $list) - 1 ))" >&2
    exit 64
fi
t=${traces[10#$i]}
if [ -z "$t" ]; then
    echo "$me: $list:$((10#$i + 1)): empty line, no trace to plan" >&2
    exit 65
fi
mkdir -p -- "$out" || { echo "$me: $out: cannot create the results folder" >&2; exit 73; }
# Every task writes its own file, complete or not at all, so a failed task leaves nothing.
exec headplan batch "$scene" "$t" --jobs "${SLURM_CPUS_PER_TASK:-2}" --no-progress \
     -o "$out/$(basename -- "$t" .csv).csv"
