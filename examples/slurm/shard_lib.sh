# Sourced by split_trace.sh, resume.sh and join.sh (docs/batch.md, "One long recording on
# Slurm"): what a shard is, where its result goes, and when that result is complete. CSV
# traces only.

# shard_header_lines PIECE: how many lines open the trace before its first row (the
# `# headplan-trace:` directive, comments, the column header): every line up to and
# including the first one that is not blank and not a `#` comment.
shard_header_lines() {
    awk '!/^[[:space:]]*$/ && !/^#/ { print NR; found = 1; exit } END { if (!found) print 0 }' "$1"
}
# shard_rows PIECE: the rows batch plans in it (one output row each, bad rows included):
# the lines after the header that are neither blank nor `#` comments.
shard_rows() {
    awk -v h="$(shard_header_lines "$1")" \
        'NR > h && !/^[[:space:]]*$/ && !/^#/ { n++ } END { print n + 0 }' "$1"
}
# shard_result RESULTS PIECE: the result file of a piece, as batch_array.sh names it.
shard_result() { printf '%s/%s.csv\n' "$1" "$(basename -- "$2" .csv)"; }
# shard_incomplete RESULTS PIECE: prints why the piece's result is missing or incomplete,
# nothing when it is complete: it exists, ends with an end of line, records the SHA-256 of
# this piece (not of an older split), and has a header and one row per row of the piece.
shard_incomplete() {
    local r; r=$(shard_result "$1" "$2")
    if [ ! -f "$r" ]; then echo "$r: missing"; return; fi
    if [ -n "$(tail -c 1 -- "$r")" ]; then echo "$r: incomplete (no end of line at the end)"; return; fi
    local sha; sha=$(sha256sum -- "$2" | cut -d' ' -f1)
    if ! grep -qxF "# trace_sha256: $sha" -- "$r"; then
        echo "$r: not a result of $2 (no '# trace_sha256: $sha')"; return
    fi
    local want got
    want=$(shard_rows "$2")
    got=$(grep -vc '^#' -- "$r")
    if [ "$got" -ne $((want + 1)) ]; then
        echo "$r: incomplete ($((got > 0 ? got - 1 : 0)) rows after the header, $2 has $want)"
    fi
}
# shard_read_list LIST: fills the array `pieces` with the lines of LIST (exit 66/65 with a
# message naming LIST when it cannot be read or is empty).
shard_read_list() {
    if ! [ -r "$1" ] || ! mapfile -t pieces < "$1"; then echo "$me: $1: cannot open" >&2; exit 66; fi
    if [ ${#pieces[@]} -eq 0 ]; then echo "$me: $1: no shard in it (empty)" >&2; exit 65; fi
    local i
    for i in "${!pieces[@]}"; do
        [ -n "${pieces[i]}" ] || { echo "$me: $1:$((i + 1)): empty line, no shard" >&2; exit 65; }
        [ -r "${pieces[i]}" ] || { echo "$me: $1:$((i + 1)): ${pieces[i]}: cannot open" >&2; exit 66; }
    done
}
