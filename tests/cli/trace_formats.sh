# Trace and result formats: the same request reaching the program by another path (a JSON
# Lines trace instead of CSV, a result in the other format, standard input, '--') must get the
# same honest answer. Each case here was once answered wrongly (see the commit).
source "$2/tests/cli_lib.sh"
HP_BIN=$(realpath "$HP_BIN"); HP_SRC=$(realpath "$HP_SRC")
S=$(patient_scenes) || exit 1 # time budgets of 60 s: runs compared plan alike (tests/cli_lib.sh)
E="$HP_SRC/examples/calibration"

# A JSON Lines number beyond a double's range was refused in jansson's words, naming no key
# ("o.jsonl:2:21: real number overflow near '1e400'"); CSV names the column. Now the key at
# the number's own line and column, as an underflow already was.
printf '{"headplan_trace": 1, "rows": "correction"}\n{"t_s":0,"x_mm":1e400,"y_mm":0,"z_mm":0,"pitch_deg":0,"roll_deg":0,"yaw_deg":0}\n' > "$TMP/o.jsonl"
run batch "$S/default.yaml" "$TMP/o.jsonl" --format csv --no-times
expect_exit 65 "batch, a JSON Lines number that overflows"
expect_stderr_has "o.jsonl:2:17: x_mm: overflows a double" "JSON Lines overflow names the key"
printf '{"headplan_trace": 1, "rows": "correction"}\n{"t_s":0,"x_mm":0,"y_mm":0,"z_mm":0,"pitch_deg":0,"roll_deg":0,"yaw_deg":-1e999}\n' > "$TMP/o2.jsonl"
run horizon "$S/default.yaml" "$TMP/o2.jsonl"
expect_exit 65 "horizon, a JSON Lines number that overflows"
expect_stderr_has "o2.jsonl:2:74: yaw_deg: overflows a double" "horizon names the key"
# plot given batch's JSON Lines result said "not a headplan batch CSV: no column 'line'";
# now it says which format it was given and which it reads. Nothing is drawn.
"$HP_BIN" batch "$S/default.yaml" "$S/traces/nodding.csv" --format jsonl -o "$TMP/nod.jsonl" 2>/dev/null
for extra in "--dry-run" "-o $TMP/p.svg"; do
    run plot "$TMP/nod.jsonl" $extra
    expect_exit 65 "plot, a JSON Lines result ($extra)"; expect_stdout_empty "plot jsonl $extra"
    expect_stderr_has "nod.jsonl:1:1: a JSON Lines result; plot reads the CSV result" "plot names the format"
done
[ ! -e "$TMP/p.svg" ] && ok || bad "plot drew a JSON Lines result"
# fit material --json printed measured_mm 25.530300000000004 for the data's 25.5303 (the
# reader's metres times 1e3); every --json prints %.17g of the double, so a number echoed
# from the data must be the data's own double. Compared with the file's numbers as Python
# reads them.
run fit material "$E/material_ri.csv" --Ri-mm 27 --Ro-mm 30 --json
expect_exit 0 "fit material --json"
python3 - "$TMP/out" "$E/material_ri.csv" <<'PY' && ok || bad "fit material --json measured_mm is not the data's number"
import csv, json, sys
got = [r["measured_mm"] for r in json.load(open(sys.argv[1]))["residuals"]]
rows = [l for l in open(sys.argv[2]) if not l.startswith("#")]
want = [float(r["ri_mm"]) for r in csv.DictReader(rows)]
bad = [(g, w) for g, w in zip(got, want) if g != w]
if bad or len(got) != len(want):
    sys.exit("measured_mm differs from the data: %s %d %d" % (bad[:3], len(got), len(want)))
PY
# horizon named a row the planner refused by its status alone ("first t.csv:4:
# invalid-input)"), where batch prints the planner's reason; greedy plans what batch plans,
# so its reason is batch's word for word. Receding plans another target: the planner's
# reason all the same.
H='# headplan-trace: rows=correction\nt_s,x_mm,y_mm,z_mm,pitch_deg,roll_deg,yaw_deg\n'
printf "$H"'0,1,0,0,0,0,0\n1,0,0,0,89.9,0,0\n2,1,0,0,0,0,0\n3,0,0,0,20,0,0\n' > "$TMP/t.csv"
run batch "$S/default.yaml" "$TMP/t.csv" --format csv --no-times
expect_exit 65 "batch, a refused row"
want=$(grep -m1 "t.csv:4: " "$TMP/err" | sed "s#^headplan batch: $TMP/t.csv:4: ##")
case "$want" in desired:*identifiable*) ok ;; *) bad "batch's reason is '$want'" ;; esac
run horizon "$S/default.yaml" "$TMP/t.csv" --mode greedy
expect_exit 65 "horizon greedy, a refused row"
expect_stderr_has "greedy: 1 of 4 rows refused (first $TMP/t.csv:4: invalid-input: $want)" "horizon greedy gives batch's reason"
run horizon "$S/default.yaml" "$TMP/t.csv" --mode receding
expect_exit 65 "horizon receding, a refused row"
expect_stderr_has "receding: 1 of 4 rows refused (first $TMP/t.csv:4: invalid-input: desired: outside the identifiable range" "horizon receding gives the planner's reason"
# '--' (end of options, POSIX) was an unknown option for every subcommand, so a file whose
# name starts with '-' could not be given. Now every subcommand reads each argument after the
# first '--' as a file, and the same bytes give the same answer by either name.
mkdir -p "$TMP/dd"; cd "$TMP/dd"
cp "$S/default.yaml" ./-s.yaml; cp "$S/default.yaml" s.yaml
cp "$S/traces/nodding.csv" ./-t.csv; cp "$E/material_ri.csv" ./-m.csv; cp "$E/layout_rows.csv" ./-l.csv
"$HP_BIN" batch s.yaml -t.csv 2>/dev/null; [ $? -eq 64 ] && ok || bad "-t.csv was taken for an option before"
"$HP_BIN" batch s.yaml -- -t.csv -o r.csv 2>/dev/null; [ $? -eq 64 ] && ok || bad "-o after -- is a file"
cp ./-t.csv t.csv; "$HP_BIN" batch s.yaml t.csv --no-times -o r.csv 2>/dev/null
cp r.csv ./-r.csv
cp "$S/paper_expansion.yaml" ./-p.yaml; cp "$S/paper_expansion.yaml" p.yaml
for pair in "solve --json -- -s.yaml|solve --json s.yaml" \
            "analyze -- -s.yaml|analyze s.yaml" \
            "batch --format csv --no-times -- -s.yaml -t.csv|batch --format csv --no-times s.yaml t.csv" \
            "horizon --mode greedy -- -s.yaml -t.csv|horizon --mode greedy s.yaml t.csv" \
            "render --dry-run -- -s.yaml|render --dry-run s.yaml" \
            "plot --dry-run -- -r.csv|plot --dry-run r.csv" \
            "fit material --Ri-mm 27 --Ro-mm 30 --json -- -m.csv|fit material --Ri-mm 27 --Ro-mm 30 --json m.csv" \
            "fit layout --json -- -s.yaml -l.csv|fit layout --json s.yaml l.csv" \
            "paper -- -p.yaml|paper p.yaml"; do
    dashed=${pair%%|*}; plain=${pair#*|}
    [ -e m.csv ] || cp ./-m.csv m.csv; [ -e l.csv ] || cp ./-l.csv l.csv
    run $dashed; rc_d=$rc; sed 's/-\([strmlp]\)\.\(yaml\|csv\)/\1.\2/g; s/"solve_time_us": [-0-9.e]*//' "$TMP/out" > "$TMP/dashed"
    run $plain
    [ "$rc_d" -eq "$rc" ] && [ "$rc" -le 1 ] && ok || bad "$dashed: exit $rc_d, '$plain' exits $rc"
    sed 's/-\([strmlp]\)\.\(yaml\|csv\)/\1.\2/g; s/"solve_time_us": [-0-9.e]*//' "$TMP/out" | grep -v '^# trace\|^# scene\|"trace\|"scene\|^# result\|sha256' > "$TMP/plain"
    grep -v '^# trace\|^# scene\|"trace\|"scene\|^# result\|sha256' "$TMP/dashed" > "$TMP/dashed2"
    cmp -s "$TMP/dashed2" "$TMP/plain" && ok || bad "$dashed prints otherwise than $plain: $(diff "$TMP/dashed2" "$TMP/plain" | head -3)"
done
# After '--' nothing is an option: --help is a file name, --json a second scene.
run solve -- --help
expect_exit 66 "solve -- --help"; expect_stderr_has "headplan solve: --help: cannot open" "--help after -- is a file"
run solve s.yaml -- --json
expect_exit 64 "solve s.yaml -- --json"; expect_stderr_has "'--json': only one scene file may be given" "--json after -- is a file"
run ik -- --json
expect_exit 64 "ik -- --json"; expect_stderr_has "unexpected argument '--json'" "ik takes no files"
run fit -- material
expect_exit 64 "fit -- material"
cd - > /dev/null
# SCENE '-' was a file named '-' ("-: cannot open") while TRACE '-' is standard input. Now
# every subcommand that reads a scene reads '-' from standard input, with the file's answer;
# the parser's messages name it <stdin>, as the trace reader names its standard input.
mkdir -p "$TMP/si"; cd "$TMP/si"
cp "$S/default.yaml" s.yaml; cp s.yaml s.orig; cp "$S/traces/nodding.csv" t.csv
cp "$E/layout_rows.csv" l.csv
"$HP_BIN" batch s.yaml t.csv --no-times -o r.csv 2>/dev/null
mask() { sed 's/"solve_time_us": [-0-9.e]*//; s/<stdin>/s.yaml/g' "$1" | grep -v '^# scene_sha256\|^# trace_sha256'; }
for c in "solve --json" "analyze --json" "batch --format csv --no-times SCENE t.csv" \
         "horizon --mode greedy SCENE t.csv" "render --dry-run" "fit layout --json SCENE l.csv" \
         "plot r.csv --dry-run --scene"; do
    case "$c" in *SCENE*) file=${c/SCENE/s.yaml}; std=${c/SCENE/-} ;; *) file="$c s.yaml"; std="$c -" ;; esac
    run $file; rc_f=$rc; mask "$TMP/out" > "$TMP/file_out"
    "$HP_BIN" $std < s.yaml > "$TMP/out" 2> "$TMP/err"; rc=$?
    [ "$rc" -eq "$rc_f" ] && [ "$rc" -le 1 ] && ok || bad "$std < s.yaml: exit $rc, the file's $rc_f"
    mask "$TMP/out" > "$TMP/std_out"
    [ -s "$TMP/std_out" ] && cmp -s "$TMP/std_out" "$TMP/file_out" && ok || bad "$std < s.yaml prints otherwise: $(diff "$TMP/std_out" "$TMP/file_out" | head -4)"
done
printf 'headplan_scene: 1\nlayout:\n  bogus: 1\n' > bad.yaml
run solve bad.yaml; want=$(sed "s#bad.yaml#<stdin>#" "$TMP/err")
"$HP_BIN" solve - < bad.yaml > "$TMP/out" 2> "$TMP/err"; rc=$?
expect_exit 65 "solve -, a bad scene"; expect_stderr_has "$want" "the parser names <stdin>"
expect_stderr_has "headplan solve: <stdin>:" "the parser names <stdin>"
for c in "batch - - --format csv" "horizon - -"; do
    "$HP_BIN" $c < s.yaml > "$TMP/out" 2> "$TMP/err"; rc=$?
    expect_exit 64 "$c"; expect_stderr_has "'-' given twice: standard input can be read only once" "$c"
done
# The scene on standard input is an input like any other: no output may replace it.
for c in "batch - t.csv --format csv -o s.yaml" "fit layout - l.csv -o s.yaml" \
         "horizon - t.csv -o s.yaml" "render - -o x.svg --script-out s.yaml"; do
    "$HP_BIN" $c < s.yaml > "$TMP/out" 2> "$TMP/err"; rc=$?
    expect_exit 73 "$c < s.yaml"; expect_stderr_has "s.yaml" "$c names the file"
    cmp -s s.yaml s.orig && ok || bad "$c replaced the scene it read from standard input"
done
# plot's RESULT '-' was a file named '-' too: now standard input (batch ... | plot -); its
# --trace is read twice (hash, then rows), so '-' there is refused by name, not "cannot open".
run plot r.csv --dry-run; sed 's/r\.csv/<stdin>/g' "$TMP/out" > "$TMP/file_out"
"$HP_BIN" plot - --dry-run < r.csv > "$TMP/out" 2> "$TMP/err"; rc=$?
expect_exit 0 "plot - < r.csv"; cmp -s "$TMP/out" "$TMP/file_out" && ok || bad "plot - draws otherwise"
"$HP_BIN" plot - --scene - --dry-run < r.csv > "$TMP/out" 2> "$TMP/err"; rc=$?
expect_exit 64 "plot - --scene -"; expect_stderr_has "'-' given twice" "plot - --scene -"
run plot r.csv --trace - --dry-run
expect_exit 64 "plot --trace -"; expect_stderr_has "--trace -: the trace must be a file" "plot --trace -"
"$HP_BIN" solve - < s.yaml >> s.yaml 2> "$TMP/err"; rc=$?
expect_exit 73 "solve - < s.yaml >> s.yaml"; cmp -s s.yaml s.orig && ok || bad "solve - appended to its scene"
cd - > /dev/null
finish
