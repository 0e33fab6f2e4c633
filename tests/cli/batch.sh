# headplan batch: output per row, identical output for any --jobs, bad rows, atomic output,
# the rows kind never guessed, exact deviation inverse, pose forms, safe -o, streams, signals,
# columns and metadata, exit statuses (issue 9).
source "$2/tests/cli_lib.sh"
S=$(patient_scenes) || exit 1 # time budgets of 60 s: runs compared plan alike (tests/cli_lib.sh)
DRIFT="$S/traces/drift_10hz.csv"
HDR='t_s,x_mm,y_mm,z_mm,pitch_deg,roll_deg,yaw_deg'
COR='# headplan-trace: rows=correction'
DEV='# headplan-trace: rows=deviation'
data() { grep -v '^#' "$1"; }   # an output without its metadata record

# The drift trace (1800 rows at 10 Hz): one job and two jobs give byte-identical output.
run batch "$S/default.yaml" --no-times -o "$TMP/j1.csv"; expect_exit 0 "drift jobs 1"
expect_stdout_empty "batch -o writes nothing to stdout"
run batch "$S/default.yaml" --no-times --jobs 2 -o "$TMP/j2.csv"; expect_exit 0 "drift jobs 2"
cmp -s "$TMP/j1.csv" "$TMP/j2.csv" && ok || bad "jobs 1 and jobs 2 outputs differ"
run batch "$S/default.yaml" --no-times --jobs 3 -o "$TMP/j3.csv"; expect_exit 0 "drift jobs 3"
cmp -s "$TMP/j1.csv" "$TMP/j3.csv" && ok || bad "jobs 1 and jobs 3 outputs differ"
rows=$(grep -vc '^t_s\|^#' "$DRIFT")
[ "$(data "$TMP/j1.csv" | wc -l)" -eq "$((rows + 1))" ] && ok || bad "one output row per input row"
ls "$TMP" | grep -q partial && bad "a .partial file was left behind" || ok
# With the time column, everything but that column is still identical.
run batch "$S/default.yaml" --jobs 2 -o "$TMP/t2.csv"; expect_exit 0 "drift with times"
python3 - "$TMP/t2.csv" "$TMP/j1.csv" <<'PY' && ok || bad "times column changes other columns"
import csv, sys
a = [r for r in csv.DictReader(l for l in open(sys.argv[1]) if not l.startswith('#'))]
b = [r for r in csv.DictReader(l for l in open(sys.argv[2]) if not l.startswith('#'))]
assert len(a) == len(b)
for x, y in zip(a, b):
    del x['solve_time_us']
    assert x == y
PY
expect_stderr_has "1800 rows: 1800 reached" "summary counts"
expect_stderr_has "time per plan: median" "summary time"
expect_stderr_has "(0 at the time budget)" "summary counts rows stopped by the time budget"

# ---- the kind of rows is never guessed (the sign flip of issue 9) ----
# The scene's own trace and the same file named on the command line: the same rows.
run batch "$S/default.yaml" "$S/traces/drift_10hz.csv" --no-times -o "$TMP/named.csv"
expect_exit 0 "drift named"
cmp -s "$TMP/j1.csv" "$TMP/named.csv" && ok || bad "naming the scene's trace changes the output"
grep -qx '# rows: deviation' "$TMP/j1.csv" && ok || bad "metadata names the rows kind"
grep -qx '# rows_from: trace' "$TMP/j1.csv" && ok || bad "metadata names where the kind came from"
# A trace that states nothing: an error asking for --rows; with --rows it is planned.
{ echo "$HDR"; echo "0,0.1,0,0,0,0,0"; } >"$TMP/plain.csv"
run batch --format csv "$S/default.yaml" "$TMP/plain.csv"; expect_exit 65 "kind not stated"
expect_stderr_has "or give --rows" "kind asked for"; expect_stdout_empty "kind not stated"
run batch --format csv "$S/default.yaml" "$TMP/plain.csv" --rows correction --no-times; expect_exit 0 "--rows"
expect_stdout_has "# rows_from: --rows" "--rows recorded"

# ---- a deviation's correction is the exact inverse rigid motion ----
# 5 mm lateral and 3 deg yaw: correction t = -R^T t = (-5 cos 3°, +5 sin 3°, 0), yaw -3°.
{ echo "$DEV"; echo "$HDR"; echo "0,5,0,0,0,0,3"; } >"$TMP/dev.csv"
# The same deviation as a quaternion (w, x, y, z) = (cos 1.5°, 0, 0, sin 1.5°).
python3 - "$TMP/devq.csv" <<'PY'
import math, sys
h = math.radians(1.5)
open(sys.argv[1], "w").write("# headplan-trace: rows=deviation\nt_s,x_mm,y_mm,z_mm,qw,qx,qy,qz\n"
                             "0,5,0,0,%r,0,0,%r\n" % (math.cos(h), math.sin(h)))
PY
run batch "$S/default.yaml" "$TMP/dev.csv" --no-times -o "$TMP/dev_out.csv"; expect_exit 0 "deviation"
run batch "$S/default.yaml" "$TMP/devq.csv" --no-times -o "$TMP/devq_out.csv"; expect_exit 0 "quaternion"
python3 - "$TMP/dev_out.csv" "$TMP/devq_out.csv" <<'PY' && ok || bad "deviation not inverted exactly"
import csv, math, sys
for path in sys.argv[1:]:
    row = next(csv.DictReader(l for l in open(path) if not l.startswith('#')))
    a = math.radians(3)
    want = {'x': -5 * math.cos(a), 'y': 5 * math.sin(a), 'z': 0, 'pitch': 0, 'roll': 0, 'yaw': -3}
    for k, v in want.items():
        unit = 'mm' if k in 'xyz' else 'deg'
        got = float(row['desired_%s_%s' % (k, unit)])
        assert abs(got - v) < 1e-12, (path, k, got, v)   # a few ulps of 5 mm
    # The old rule (negate) would ask for y = 0: 0.26 mm off.
    assert abs(float(row['desired_y_mm'])) > 0.1
PY

# ---- output never destroys anything ----
cp "$TMP/dev.csv" "$TMP/dev_keep.csv"
run batch "$S/default.yaml" "$TMP/dev.csv" -o "$TMP/dev.csv"; expect_exit 73 "-o is the trace"
cmp -s "$TMP/dev.csv" "$TMP/dev_keep.csv" && ok || bad "-o the trace changed the trace"
ln -s "$TMP/dev.csv" "$TMP/alias.csv"
run batch "$S/default.yaml" "$TMP/alias.csv" -o "$TMP/dev.csv"; expect_exit 73 "-o is the trace via a link"
cmp -s "$TMP/dev.csv" "$TMP/dev_keep.csv" && ok || bad "-o the linked trace changed it"
ln -s "$TMP/nowhere.csv" "$TMP/link.csv"
run batch "$S/default.yaml" "$TMP/dev.csv" -o "$TMP/link.csv"; expect_exit 73 "-o a symlink"
[ ! -e "$TMP/nowhere.csv" ] && [ -L "$TMP/link.csv" ] && ok || bad "-o a symlink wrote through it"
mkfifo "$TMP/fifo.csv"
# Bounded: a run that opened the FIFO to write would wait for a reader for ever (exit 124).
timeout -k 5 120 "$HP_BIN" batch "$S/default.yaml" "$TMP/dev.csv" -o "$TMP/fifo.csv" \
  >"$TMP/out" 2>"$TMP/err"; rc=$?; expect_exit 73 "-o a FIFO"
[ -p "$TMP/fifo.csv" ] && ok || bad "-o replaced a FIFO"
# A stale temporary file of an old run does not block a new one (mkstemp names).
for p in 1 2 3 $$; do : >"$TMP/fresh.csv.partial-$p"; done
run batch "$S/default.yaml" "$TMP/dev.csv" -o "$TMP/fresh.csv"; expect_exit 0 "stale partial files"
[ -s "$TMP/fresh.csv" ] && ok || bad "no output beside stale partial files"
# -o - is stdout; the format follows the extension; a conflict is an error.
run batch --format csv "$S/default.yaml" "$TMP/dev.csv" -o - --no-times; expect_exit 0 "-o -"
cmp -s "$TMP/out" "$TMP/dev_out.csv" && ok || bad "-o - differs from -o FILE"
run batch "$S/default.yaml" "$TMP/dev.csv" -o "$TMP/ext.jsonl"; expect_exit 0 "-o x.jsonl"
head -c 1 "$TMP/ext.jsonl" | grep -q '{' && ok || bad "-o x.jsonl did not write JSON Lines"
run batch "$S/default.yaml" "$TMP/dev.csv" -o "$TMP/x.jsonl" --format csv; expect_exit 64 "format conflict"
[ ! -e "$TMP/x.jsonl" ] && ok || bad "format conflict wrote a file"

# ---- streams: stdin, pipes and FIFOs lose nothing ----
"$HP_BIN" batch --format csv "$S/default.yaml" - --no-times <"$DRIFT" >"$TMP/stdin.csv" 2>"$TMP/err"
rc=$?; expect_exit 0 "trace from stdin"
diff <(grep -v '^# trace' "$TMP/stdin.csv") <(grep -v '^# trace' "$TMP/j1.csv") >/dev/null \
  && ok || bad "stdin trace output differs from the file's"
grep -qx '# trace_sha256: none (not a regular file)' "$TMP/stdin.csv" && ok || bad "stdin hash note"
# JSON Lines with its header record, through process substitution (a pipe, no extension).
python3 - "$DRIFT" "$TMP/drift.jsonl" <<'PY'
import sys
lines = [l.strip() for l in open(sys.argv[1]) if not l.startswith('#')]
keys = lines[0].split(',')
with open(sys.argv[2], 'w') as f:
    f.write('{"headplan_trace": 1, "rows": "deviation"}\n')
    for l in lines[1:]:
        f.write('{' + ','.join('"%s":%s' % (k, v) for k, v in zip(keys, l.split(','))) + '}\n')
PY
run batch "$S/default.yaml" <(cat "$TMP/drift.jsonl") --no-times -o "$TMP/pipe.csv"
expect_exit 0 "JSON Lines through a pipe"
diff <(data "$TMP/pipe.csv" | cut -d, -f2-) <(data "$TMP/j1.csv" | cut -d, -f2-) >/dev/null \
  && ok || bad "a piped JSON Lines trace lost its header or rows"

# A sanitizer build (libasan loaded) keeps freed memory in quarantine: there the RSS check
# is left to the ordinary build, where it means something.
SAN=0; ldd "$HP_BIN" 2>/dev/null | grep -q libasan && SAN=1
# The signal runs below read their rows through a FIFO held open by the test, so they are
# mid-trace however few rows it sends; few rows keep the one run that is let finish (nohup)
# a fraction of a second on any build, far inside its ~2 min cap.
LONG_ROWS=2000

# Memory is flat in the number of rows: peak RSS of 100 000 rows minus that of 10 000 rows
# (both streamed from a generator) stays under 16 MB (it grew ~60 MB before issue 9).
rss() {
  python3 - "$HP_BIN" "$S/default.yaml" "$1" <<'PY'
import resource, subprocess, sys
n = int(sys.argv[3])
gen = subprocess.Popen([sys.executable, "-c", """
import sys
w = sys.stdout.write
w("# headplan-trace: rows=correction\\nt_s,x_mm,y_mm,z_mm,pitch_deg,roll_deg,yaw_deg\\n")
for i in range(%d):
    w("%%d,%%.3f,0,0,0,0,0\\n" %% (i, (i %% 50) / 100))
""" % n], stdout=subprocess.PIPE)
p = subprocess.Popen([sys.argv[1], "batch", sys.argv[2], "-", "--no-progress", "-o", "-", "--format", "csv"],
                     stdin=gen.stdout, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
gen.stdout.close()  # only the planner holds the pipe: the generator stops if it stops
p.wait()
gen.wait()
print(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss if p.returncode == 0 else -1)
PY
}
if [ "$SAN" = 0 ]; then
  small=$(rss 10000); large=$(rss 100000)
  [ "$small" -gt 0 ] && [ "$large" -gt 0 ] && [ $((large - small)) -lt 16384 ] && ok \
    || bad "memory grows with rows: ${small} kB at 10k rows, ${large} kB at 100k rows"
fi

# ---- three jobs on a trace with rate limits binding: shard joins repaired ----
python3 - "$TMP/fast.csv" <<'PY'
import math, sys
with open(sys.argv[1], "w") as f:
    f.write("# headplan-trace: rows=correction\nt_s,x_mm,y_mm,z_mm,pitch_deg,roll_deg,yaw_deg\n")
    for i in range(300):
        s = 1.5 * math.sin(i / 7.0)
        f.write(f"{i/10:.1f},{s:.4f},0,{0.8*s:.4f},{0.5*s:.4f},0,{0.3*s:.4f}\n")
PY
run batch "$S/saturation.yaml" "$TMP/fast.csv" --no-times -o "$TMP/s1.jsonl"
s1=$rc
run batch "$S/saturation.yaml" "$TMP/fast.csv" --no-times -o "$TMP/s3.jsonl" --jobs 3
[ "$rc" -eq "$s1" ] && ok || bad "exit differs between jobs 1 ($s1) and jobs 3 ($rc)"
cmp -s "$TMP/s1.jsonl" "$TMP/s3.jsonl" && ok || bad "jsonl jobs 1 and jobs 3 differ"
python3 -c "
import json,sys
lines=open('$TMP/s1.jsonl').read().splitlines()
meta=json.loads(lines[0])
assert meta['headplan_batch']==1 and meta['rows']=='correction', meta
rows=[json.loads(l) for l in lines[1:]]
assert len(rows)==300, len(rows)
assert all(r['status'] in ('reached','closest') for r in rows)
assert all(len([k for k in r if k.endswith('_pressure_pa')])==8 for r in rows)
" && ok || bad "jsonl rows well formed"

# ---- a trace where limits bind, with rate limits, realtime at the surface level: jobs 1, 2
# and 3 byte-identical. Every row's state is set from the previous good row's output
# (hp_planner_set_previous_result); with rate limits a shard's guessed start differs from
# the true state, so the joins are repaired (rows re-planned), and equal rows there must
# mean equal states from then on. ----
python3 - "$TMP/bind.csv" <<'PY'
import math, sys
with open(sys.argv[1], "w") as f:
    f.write("# headplan-trace: rows=correction\nt_s,x_mm,y_mm,z_mm,pitch_deg,roll_deg,yaw_deg\n")
    for i in range(300):
        s = 3 * (1 + math.sin(i / 7.0))
        f.write(f"{i/10:.1f},{s:.4f},{0.6*s:.4f},{-0.75*s:.4f},{0.25*s:.4f},{0.1*s:.4f},"
                f"{-0.15*s:.4f}\n")
PY
for j in 1 2 3; do
  run batch "$S/saturation.yaml" "$TMP/bind.csv" --backend realtime --level surface --no-times \
    --no-progress --jobs $j -o "$TMP/b$j.csv"
  expect_exit 0 "binding trace jobs $j"
  cp "$TMP/err" "$TMP/b$j.err"
done
cmp -s "$TMP/b1.csv" "$TMP/b2.csv" && ok || bad "binding trace: jobs 1 and jobs 2 differ"
cmp -s "$TMP/b1.csv" "$TMP/b3.csv" && ok || bad "binding trace: jobs 1 and jobs 3 differ"
n_closest=$(grep -v '^#' "$TMP/b1.csv" | grep -c ',closest,')
[ "$n_closest" -ge 100 ] && ok || bad "binding trace: only $n_closest closest rows"
grep -qE '3 jobs, [1-9][0-9]* rows? re-planned' "$TMP/b3.err" && ok \
  || bad "binding trace: no join was repaired with 3 jobs: $(tail -n 1 "$TMP/b3.err")"

# ---- columns, metadata, numbers identical in CSV and JSON Lines ----
run batch "$S/saturation.yaml" "$TMP/fast.csv" --no-times -o "$TMP/s1.csv"
python3 - "$TMP/s1.csv" "$TMP/s1.jsonl" "$S/saturation.yaml" "$TMP/fast.csv" <<'PY' \
  && ok || bad "columns, metadata or numbers"
import csv, hashlib, json, sys
lines = open(sys.argv[1]).read().splitlines()
meta = dict(l[2:].split(': ', 1) for l in lines if l.startswith('# '))
sha = lambda p: hashlib.sha256(open(p, 'rb').read()).hexdigest()
assert meta['scene_sha256'] == sha(sys.argv[3]) and meta['trace_sha256'] == sha(sys.argv[4])
assert meta['program'].startswith('headplan ') and meta['backend'] and meta['level']
for k in ('rows', 'pose_form', 'tolerance_mm_deg', 'max_iter', 'max_time_s', 'weight_mm_per_deg',
          'restarts', 'auto_pose_mm_deg'):
    assert k in meta, k
assert meta['restarts'] == '7', meta['restarts']  # the scene states none: the default
assert meta['auto_pose_mm_deg'] == '0,0,0,0,0,0', meta['auto_pose_mm_deg']  # no load: nominal
rows = list(csv.reader(l for l in lines if not l.startswith('#')))
head = rows[0]
for col in ('desired_x_mm', 'achieved_yaw_deg', 'error_pitch_deg', 'commanded_x', 'pose_error_mm',
            'pose_error_deg', 'side_fore_left_pressure_pa', 'side_fore_left_ri_mm',
            'side_fore_left_ro_mm', 'side_fore_left_stretch', 'binding'):
    assert col in head, col
assert 'pose_error' not in head
jl = open(sys.argv[2]).read().splitlines()
jmeta = json.loads(jl[0])
for k, v in meta.items():  # JSON null is the CSV comment's "none (why)"
    assert (jmeta[k] is None and v.startswith('none (')) or str(jmeta[k]).lower() == v.lower(), \
        (k, jmeta[k], v)
# Every number has the same text in both files (JSON numbers kept as text).
for c, j in zip(rows[1:], jl[1:]):
    obj = json.loads(j, parse_float=str, parse_int=str)
    assert list(obj) == head
    for name, text in zip(head, c):
        v = obj[name]
        assert (v or '') == text or (v is None and text == ''), (name, v, text)
PY

# The restarts a scene states are the ones recorded (both files).
sed 's/^solver: {/solver: {restarts: 2, /' "$S/saturation.yaml" >"$TMP/restarts2.yaml"
run batch "$TMP/restarts2.yaml" "$TMP/fast.csv" --no-times -o "$TMP/r2.csv"
expect_exit 0 "batch with solver.restarts 2"
grep -qx '# restarts: 2' "$TMP/r2.csv" && ok || bad "CSV metadata: no '# restarts: 2'"
run batch "$TMP/restarts2.yaml" "$TMP/fast.csv" --no-times -o "$TMP/r2.jsonl"
expect_exit 0 "batch with solver.restarts 2, JSON Lines"
head -n 1 "$TMP/r2.jsonl" | grep -q '"restarts":2[,}]' && ok || bad "JSON Lines metadata: no restarts 2"

# ---- bad rows: reported with their line, the other rows go on, exit 65 ----
# The path holds ':' so a line number read back from the message would be wrong.
mkdir -p "$TMP/a:b"
printf '%s\n%s\n0,0.1,0,0,0,0,0\n0.1,abc,0,0,0,0,0\n0.2,0,0,0,0,0\n0.3,0.2,0,0,0,0,0\n0.4,0.1,0,0,0,0' \
  "$COR" "$HDR" >"$TMP/a:b/bad.csv"
run batch --format csv "$S/default.yaml" "$TMP/a:b/bad.csv" --no-times
expect_exit 65 "bad rows exit"
expect_stderr_has "bad.csv:4:5: x_mm: not a number" "bad row 4 named"
expect_stderr_has "bad.csv:5: 6 fields, expected 7" "bad row 5 named"
expect_stderr_has "bad.csv:7:16: truncated" "truncated last line named"
[ "$(grep -c ',reached,' "$TMP/out")" -eq 2 ] && ok || bad "good rows planned"
[ "$(grep -c ',bad-row,' "$TMP/out")" -eq 3 ] && ok || bad "bad rows labelled"
[ "$(grep ',bad-row,' "$TMP/out" | cut -d, -f1 | tr '\n' ' ')" = "4 5 7 " ] && ok \
  || bad "bad rows carry their own line numbers with ':' in the path"

# ---- messages: one line, control characters escaped; a BOM is skipped ----
nl_path="$TMP/new
line.csv"
run batch --format csv "$S/default.yaml" "$nl_path"; expect_exit 66 "missing trace with a newline"
[ "$(wc -l <"$TMP/err")" -eq 1 ] && ok || bad "a newline in a path split the message"
expect_stderr_has 'new\x0aline.csv: cannot open' "newline escaped"
printf '\xef\xbb\xbf%s\n%s\n0,0.1,0,0,0,0,0\n' "$COR" "$HDR" >"$TMP/bom.csv"
run batch --format csv "$S/default.yaml" "$TMP/bom.csv" --no-times; expect_exit 0 "BOM skipped"
{ printf '\xef\xbb\xbf'; cat "$S/default.yaml"; } >"$TMP/bom.yaml"
run solve "$TMP/bom.yaml"; expect_exit 0 "a scene's BOM skipped"

# ---- exit statuses: closest rows are a finished study unless --strict ----
printf '%s\n%s\n0,0.1,0,0,0,0,0\n0.1,15,0,0,0,0,10\n' "$COR" "$HDR" >"$TMP/far.csv"
run batch --format csv "$S/default.yaml" "$TMP/far.csv"; expect_exit 0 "closest rows without --strict"
expect_stderr_has "1 closest" "closest counted"
run batch --format csv "$S/default.yaml" "$TMP/far.csv" --strict; expect_exit 1 "closest rows with --strict"
run batch --help; expect_exit 0 "help"
expect_stdout_has "not reproducible" "help says the time budget is not reproducible"

# ---- signals: ignored on entry stays ignored (nohup); otherwise the partial is removed ----
python3 - "$TMP/long.csv" "$LONG_ROWS" <<'PY'
import sys
with open(sys.argv[1], "w") as f:
    f.write("# headplan-trace: rows=correction\nt_s,x_mm,y_mm,z_mm,pitch_deg,roll_deg,yaw_deg\n")
    for i in range(int(sys.argv[2])):
        f.write(f"{i/10:.1f},{(i%50)/100:.2f},0,0,0,0,0\n")
PY
# The runs below read the trace from a FIFO whose writer sends the rows and then holds the
# FIFO open until the test closes it: the run is mid-trace, blocked on its input, for as
# long as the test needs, however fast or busy the machine is (a run of a plain file used to
# finish before a fixed sleep once the batch got faster). The test waits for the run's
# temporary output to appear (it has planned and written its first rows), then signals.
feed() { # feed FIFO: starts the writer, sets wpid
  rm -f "$1"; mkfifo "$1"
  # Its stderr and stdin are not the test's: a writer left behind must not hold the pipes
  # ctest reads to the end (it would wait for them as long as the writer lives).
  ( cat "$TMP/long.csv"; exec sleep 600 ) >"$1" 2>/dev/null </dev/null &
  wpid=$!
}
unfeed() { kill $wpid 2>/dev/null; wait $wpid 2>/dev/null; wpid=; } # end of input
# Every path ends the writer and the run (a failed check, an early exit of the script).
trap 'kill $wpid $pid 2>/dev/null; rm -rf "$TMP"' EXIT
wait_partial() { # wait_partial NAME PID: 0 once NAME's temporary output exists; 1 as soon
  # as PID has ended without it (a run that failed early) or after ~2 min
  for _ in $(seq 1200); do
    ls "$TMP" | grep -q "^$1\.partial" && return 0
    kill -0 "$2" 2>/dev/null || return 1
    sleep 0.1
  done
  return 1
}
wait_run() { # wait_run PID: its exit status in rc; killed (-9) if still running after ~2 min
  for _ in $(seq 1200); do
    kill -0 "$1" 2>/dev/null || break
    sleep 0.1
  done
  kill -9 "$1" 2>/dev/null
  wait "$1"; rc=$?; pid=
}
# The test shell ignores HUP while it forks, so the child has it ignored from its first
# instruction (no race with a busy machine), as nohup does.
feed "$TMP/feed1"
trap '' HUP
"$HP_BIN" batch "$S/default.yaml" "$TMP/feed1" -o "$TMP/nohup.csv" --no-progress 2>/dev/null &
pid=$!
trap - HUP
wait_partial nohup.csv $pid && ok || bad "nohup run: no partial output appeared"
kill -HUP $pid 2>/dev/null
unfeed # end of input: the run completes
wait_run $pid
expect_exit 0 "SIGHUP ignored on entry stays ignored"
[ -s "$TMP/nohup.csv" ] && ok || bad "nohup run left no output"
feed "$TMP/feed2"
"$HP_BIN" batch "$S/default.yaml" "$TMP/feed2" -o "$TMP/hup.csv" --no-progress 2>/dev/null &
pid=$!
wait_partial hup.csv $pid && ok || bad "hup run: no partial output appeared"
kill -HUP $pid 2>/dev/null; wait_run $pid
unfeed
[ ! -e "$TMP/hup.csv" ] && ! ls "$TMP" | grep -q 'hup.csv.partial' && ok \
  || bad "SIGHUP left an output or a partial file"

# ---- usage and input errors: message, nothing on stdout ----
run batch; expect_exit 64 "no scene"; expect_stdout_empty "no scene"
run batch --format csv "$S/default.yaml" --jobs 0; expect_exit 64 "jobs 0"; expect_stderr_has "--jobs" "jobs named"
run batch "$S/default.yaml" --format xml; expect_exit 64 "format"; expect_stderr_has "--format" "format named"
run batch --format csv "$S/default.yaml" --bogus; expect_exit 64 "unknown option"
run batch --format csv "$S/default.yaml" "$TMP/none.csv"; expect_exit 66 "missing trace"; expect_stdout_empty "missing trace"
run batch --format csv "$S/paper_expansion.yaml" "$TMP/fast.csv"; expect_exit 65 "bladder scene"
run batch --format csv "$S/sphere_head.yaml"; expect_exit 64 "scene without trace"; expect_stderr_has "missing TRACE" "trace named"
run batch "$S/default.yaml" -o "$TMP/nodir/x.csv"; expect_exit 73 "unwritable output"

# A killed run leaves no file that looks complete (killed mid-trace: see feed above).
feed "$TMP/feed3"
"$HP_BIN" batch "$S/default.yaml" "$TMP/feed3" -o "$TMP/killed.csv" --no-progress 2>/dev/null &
pid=$!
wait_partial killed.csv $pid && ok || bad "killed run: no partial output appeared"
kill -9 $pid 2>/dev/null; wait $pid 2>/dev/null; pid=
unfeed
[ ! -e "$TMP/killed.csv" ] && ok || bad "killed run left $TMP/killed.csv"
# Uncommanded never reads as reached: a sphere head cannot be turned about its centre, so
# every nodding row is "uncommanded", its uncommanded_* columns carry the part dropped (the
# pitch of the row), the summary counts and names it, and --strict exits 2.
run batch "$S/sphere_head.yaml" "$S/traces/nodding.csv" --no-times -o "$TMP/sph.csv"
expect_exit 0 "sphere nodding"
expect_stderr_has "uncommanded, 0 failed" "summary counts uncommanded rows"
expect_stderr_has "not commanded (the layout cannot observe it), largest: pitch" "summary names the direction"
python3 - "$TMP/sph.csv" <<'PY' && ok || bad "uncommanded rows and columns"
import csv, sys
rows = list(csv.DictReader(l for l in open(sys.argv[1]) if not l.startswith("#")))
assert rows and all(r["status"] == "uncommanded" for r in rows[1:]), "a row not uncommanded"
for r in rows:
    if r["status"] != "uncommanded":
        continue
    # The whole desired pitch is the part not commanded (a sphere ignores rotation about
    # its centre, which is the pivot here), and the commanded components are met.
    assert abs(float(r["uncommanded_pitch_deg"]) - float(r["desired_pitch_deg"])) < 1e-9, r
    assert abs(float(r["error_x_mm"]) + float(r["uncommanded_x_mm"])) < 1e-9, r
PY
run batch "$S/sphere_head.yaml" "$S/traces/nodding.csv" --no-times --strict -o "$TMP/sph2.csv"
expect_exit 2 "--strict with uncommanded rows"
finish
