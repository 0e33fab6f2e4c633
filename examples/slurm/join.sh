#!/bin/bash
# Joins the results of a recording's shards into one result (docs/batch.md, "One long
# recording on Slurm"):
#
#   examples/slurm/join.sh RECORDING LIST RESULTS OUT
#
# OUT gets the first shard's metadata record with `trace` and `trace_sha256` naming the
# whole RECORDING, one header, and every shard's rows in the order of LIST with `line`
# counted in the recording: the bytes one `headplan batch SCENE RECORDING -o OUT` writes,
# timing column aside, wherever the rate limits do not bind (a shard starts from the nominal
# answer). A missing or incomplete shard result stops the join (exit 66, each one named;
# resume.sh re-runs them); OUT is written beside itself and renamed only when complete.
set -u
me=join.sh
source "$(dirname -- "${BASH_SOURCE[0]}")/shard_lib.sh"
if [ $# -ne 4 ]; then echo "usage: $me RECORDING LIST RESULTS OUT" >&2; exit 64; fi
rec=$1 list=$2 out=$3 joined=$4
[ -r "$rec" ] && [ -f "$rec" ] || { echo "$me: $rec: cannot open (a regular CSV file)" >&2; exit 66; }
shard_read_list "$list"
missing=0
for p in "${pieces[@]}"; do
    why=$(shard_incomplete "$out" "$p")
    if [ -n "$why" ]; then echo "$me: $why" >&2; missing=$((missing + 1)); fi
done
if [ "$missing" -gt 0 ]; then
    echo "$me: $missing of ${#pieces[@]} shard results not complete (examples/slurm/resume.sh re-runs them); $joined not written" >&2
    exit 66
fi
for p in "${pieces[@]}"; do
    if [ "$(shard_result "$out" "$p")" -ef "$joined" ] || [ "$p" -ef "$joined" ] || [ "$rec" -ef "$joined" ]; then
        echo "$me: $joined: is one of the inputs; name a new file" >&2; exit 73
    fi
done
sha=$(sha256sum -- "$rec" | cut -d' ' -f1)
tmp=$(mktemp -- "$joined.partial-XXXXXX") || { echo "$me: $joined: cannot create" >&2; exit 73; }
trap 'rm -f -- "$tmp"' EXIT
off=0 first=1
for p in "${pieces[@]}"; do
    h=$(shard_header_lines "$p")
    # Line L of a piece (after its h header lines, which repeat the recording's) is line
    # L + off of the recording, off the lines of the pieces before it.
    awk -v off="$off" -v first="$first" -v rec="$rec" -v sha="$sha" '
        /^# / && !body { if (!first) next
                         if (/^# trace: /) { print "# trace: " rec; next }
                         if (/^# trace_sha256: /) { print "# trace_sha256: " sha; next }
                         print; next }
        !body { body = 1; if (first) print; next }
        { i = index($0, ","); print (substr($0, 1, i - 1) + off) substr($0, i) }
    ' "$(shard_result "$out" "$p")" >> "$tmp" || { echo "$me: $joined: write failed" >&2; exit 74; }
    off=$((off + $(wc -l < "$p") - h))
    first=0
done
# mktemp made it private; the result gets the modes batch's results get (the umask's).
chmod "$(printf '%o' $(( 0666 & ~8#$(umask) )))" -- "$tmp"
mv -f -- "$tmp" "$joined" || { echo "$me: $joined: cannot rename into place" >&2; exit 74; }
trap - EXIT
