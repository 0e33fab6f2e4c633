#!/bin/bash
# Splits one long CSV recording into shards for a Slurm array (docs/batch.md, "One long
# recording on Slurm"):
#
#   examples/slurm/split_trace.sh RECORDING ROWS PIECES > pieces.txt
#
# writes PIECES/part_0000.csv, part_0001.csv, ... (ROWS lines of the recording each, every
# one opening with the recording's directive and header, so each is a trace on its own) and
# prints their names, one a line: the list batch_array.sh, resume.sh and join.sh read.
# PIECES must not exist yet (no stale piece of an older split can slip into the list).
set -u
me=split_trace.sh
source "$(dirname -- "${BASH_SOURCE[0]}")/shard_lib.sh"
if [ $# -ne 3 ]; then
    echo "usage: $me RECORDING ROWS PIECES > LIST (ROWS lines of the recording a shard)" >&2
    exit 64
fi
rec=$1 rows=$2 dir=$3
if ! [[ $rows =~ ^[1-9][0-9]{0,8}$ ]]; then
    echo "$me: ROWS '$rows' is not a whole number of lines (1 or more)" >&2; exit 64
fi
[ -r "$rec" ] && [ -f "$rec" ] || { echo "$me: $rec: cannot open (a regular CSV file)" >&2; exit 66; }
h=$(shard_header_lines "$rec")
if [ "$h" -eq 0 ]; then echo "$me: $rec: no header line (not a CSV trace)" >&2; exit 65; fi
if [ -e "$dir" ]; then echo "$me: $dir: exists (give a new folder: pieces of an older split would mix in)" >&2; exit 73; fi
mkdir -p -- "$dir" || { echo "$me: $dir: cannot create" >&2; exit 73; }
head -n "$h" -- "$rec" > "$dir/.header"
tail -n +"$((h + 1))" -- "$rec" | HEADER="$dir/.header" split -l "$rows" -d -a 4 \
    --additional-suffix=.csv --filter='cat "$HEADER" - > "$FILE"' - "$dir/part_" \
    || { echo "$me: $dir: cannot write the pieces" >&2; exit 74; }
rm -f -- "$dir/.header"
shopt -s nullglob
set -- "$dir"/part_*.csv
if [ $# -eq 0 ]; then echo "$me: $rec: no rows after the header" >&2; exit 65; fi
printf '%s\n' "$@"
