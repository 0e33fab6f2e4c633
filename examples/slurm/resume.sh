#!/bin/bash
# Re-submits the shards of a Slurm study whose result is missing or incomplete (docs/batch.md,
# "One long recording on Slurm"):
#
#   examples/slurm/resume.sh SCENE LIST RESULTS
#
# names every such result on stderr and submits one array of exactly those indices of LIST
# with batch_array.sh (sbatch options through its SBATCH_* environment variables), or says
# that every result is complete and submits nothing. A complete result is never planned
# again. Run it once the first array has ended (squeue lists none of its tasks): a task
# still running has no result yet and would be submitted twice.
set -u
me=resume.sh
here=$(dirname -- "${BASH_SOURCE[0]}")
source "$here/shard_lib.sh"
if [ $# -ne 3 ]; then echo "usage: $me SCENE LIST RESULTS" >&2; exit 64; fi
scene=$1 list=$2 out=$3
shard_read_list "$list"
todo=()
for i in "${!pieces[@]}"; do
    why=$(shard_incomplete "$out" "${pieces[i]}")
    if [ -n "$why" ]; then echo "$me: task $i: $why" >&2; todo+=("$i"); fi
done
if [ ${#todo[@]} -eq 0 ]; then
    echo "$me: all ${#pieces[@]} results in $out are complete; nothing to re-run" >&2
    exit 0
fi
array=$(IFS=,; echo "${todo[*]}")
echo "$me: sbatch --array=$array $here/batch_array.sh $scene $list $out" >&2
exec sbatch --array="$array" "$here/batch_array.sh" "$scene" "$list" "$out"
