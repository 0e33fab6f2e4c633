# headplan batch: output per row, identical output for any --jobs, bad rows, atomic output.
source "$2/tests/cli_lib.sh"
S="$HP_SRC/scenarios"

# The drift trace (1800 rows at 10 Hz): one job and two jobs give byte-identical output.
run batch "$S/default.yaml" --no-times -o "$TMP/j1.csv"; expect_exit 0 "drift jobs 1"
expect_stdout_empty "batch -o writes nothing to stdout"
run batch "$S/default.yaml" --no-times --jobs 2 -o "$TMP/j2.csv"; expect_exit 0 "drift jobs 2"
cmp -s "$TMP/j1.csv" "$TMP/j2.csv" && ok || bad "jobs 1 and jobs 2 outputs differ"
rows=$(grep -vc '^t_s\|^#' "$HP_SRC/scenarios/traces/drift_10hz.csv")
[ "$(($(wc -l < "$TMP/j1.csv") - 1))" -eq "$rows" ] && ok || bad "one output row per input row"
ls "$TMP" | grep -q partial && bad "a .partial file was left behind" || ok
# With the time column, everything but that column is still identical.
run batch "$S/default.yaml" --jobs 2 -o "$TMP/t2.csv"; expect_exit 0 "drift with times"
cut -d, -f1-20 "$TMP/t2.csv" | cmp -s - "$TMP/j1.csv" && ok || bad "times column changes other columns"
expect_stderr_has "1800 rows: 1800 reached" "summary counts"
expect_stderr_has "time per plan: median" "summary time"

# Three jobs on a trace with rate limits binding: shard joins are repaired to the serial answer.
cat > "$TMP/rate.yaml" <<YAML
$(sed -e 's/^trace:.*$//' "$S/default.yaml")
YAML
python3 - "$TMP/fast.csv" <<'PY'
import math, sys
with open(sys.argv[1], "w") as f:
    f.write("t_s,x_mm,y_mm,z_mm,pitch_deg,roll_deg,yaw_deg\n")
    for i in range(300):
        s = 1.5 * math.sin(i / 7.0)
        f.write(f"{i/10:.1f},{s:.4f},0,{0.8*s:.4f},{0.5*s:.4f},0,{0.3*s:.4f}\n")
PY
run batch "$S/saturation.yaml" "$TMP/fast.csv" --no-times -o "$TMP/s1.jsonl" --format jsonl
s1=$rc
run batch "$S/saturation.yaml" "$TMP/fast.csv" --no-times -o "$TMP/s3.jsonl" --format jsonl --jobs 3
[ "$rc" -eq "$s1" ] && ok || bad "exit differs between jobs 1 ($s1) and jobs 3 ($rc)"
cmp -s "$TMP/s1.jsonl" "$TMP/s3.jsonl" && ok || bad "jsonl jobs 1 and jobs 3 differ"
python3 -c "
import json,sys
rows=[json.loads(l) for l in open('$TMP/s1.jsonl')]
assert len(rows)==300, len(rows)
assert all(r['status'] in ('reached','closest') for r in rows)
assert all(len(r['pressures_pa'])==8 for r in rows)
" && ok || bad "jsonl rows well formed"

# Bad rows: reported with their line, the other rows go on, exit 65.
printf 't_s,x_mm,y_mm,z_mm,pitch_deg,roll_deg,yaw_deg\n0,0.1,0,0,0,0,0\n0.1,abc,0,0,0,0,0\n0.2,0,0,0,0,0\n0.3,0.2,0,0,0,0,0\n0.4,0.1,0,0,0,0' > "$TMP/bad.csv"
run batch "$S/default.yaml" "$TMP/bad.csv" --no-times
expect_exit 65 "bad rows exit"
expect_stderr_has "bad.csv:3: x_mm: not a number" "bad row 3 named"
expect_stderr_has "bad.csv:4: 6 fields, expected 7" "bad row 4 named"
expect_stderr_has "bad.csv:6: truncated" "truncated last line named"
[ "$(grep -c ',reached,' "$TMP/out")" -eq 2 ] && ok || bad "good rows planned"
[ "$(grep -c ',bad-row,' "$TMP/out")" -eq 3 ] && ok || bad "bad rows labelled"

# Usage and input errors: message, nothing on stdout.
run batch; expect_exit 64 "no scene"; expect_stdout_empty "no scene"
run batch "$S/default.yaml" --jobs 0; expect_exit 64 "jobs 0"; expect_stderr_has "--jobs" "jobs named"
run batch "$S/default.yaml" --format xml; expect_exit 64 "format"; expect_stderr_has "--format" "format named"
run batch "$S/default.yaml" --bogus; expect_exit 64 "unknown option"
run batch "$S/default.yaml" "$TMP/none.csv"; expect_exit 66 "missing trace"; expect_stdout_empty "missing trace"
run batch "$S/paper_expansion.yaml" "$TMP/fast.csv"; expect_exit 65 "bladder scene"
run batch "$S/sphere_head.yaml"; expect_exit 64 "scene without trace"; expect_stderr_has "missing TRACE" "trace named"
run batch "$S/default.yaml" -o "$TMP/nodir/x.csv"; expect_exit 73 "unwritable output"

# A killed run leaves no file that looks complete.
python3 - "$TMP/long.csv" <<'PY'
import sys
with open(sys.argv[1], "w") as f:
    f.write("t_s,x_mm,y_mm,z_mm,pitch_deg,roll_deg,yaw_deg\n")
    for i in range(100000):
        f.write(f"{i/10:.1f},{(i%50)/100:.2f},0,0,0,0,0\n")
PY
"$HP_BIN" batch "$S/default.yaml" "$TMP/long.csv" -o "$TMP/killed.csv" --no-progress 2>/dev/null &
pid=$!
sleep 1.5
kill -9 $pid 2>/dev/null; wait $pid 2>/dev/null
[ ! -e "$TMP/killed.csv" ] && ok || bad "killed run left $TMP/killed.csv"
finish
