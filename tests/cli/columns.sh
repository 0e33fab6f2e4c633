# The one table of a planned row's columns (hp_trace_columns.h) and its consumers agree:
# `headplan batch --columns` lists it; batch's CSV header and JSON Lines keys are its rows
# columns expanded for the scene's bladders, in order; the plot reader's columns are among
# its numeric ones; the jobs comparisons blank exactly its measured columns; docs/batch.md
# documents every column. Python's arrays against it: python/tests/test_columns.py.
source "$2/tests/cli_lib.sh"
S="$HP_SRC/scenarios"
TRACE="$TMP/trace.csv"
printf '# headplan-trace: rows=correction\nt_s,x_mm,y_mm,z_mm,pitch_deg,roll_deg,yaw_deg\n0,0.5,0,0,0,0,0\n0.1,nan,0,0,0,0,0\n0.2,0.2,0.1,0,0.1,0,0\n' > "$TRACE"

run batch --columns; expect_exit 0 "batch --columns"
cp "$TMP/out" "$TMP/columns.tsv"
[ "$(head -1 "$TMP/columns.tsv")" = "$(printf 'name\tunit\tformat\tshape\trows\tnumpy\tmeasured')" ] \
    && ok || bad "--columns header"
run batch --columns extra; expect_exit 64 "--columns takes no file"

# A trace with a bad row (exit 65): its line, status and message are columns too.
run batch "$S/default.yaml" "$TRACE" --format csv -o "$TMP/r.csv"; expect_exit 65 "csv"
run batch "$S/default.yaml" "$TRACE" --format jsonl -o "$TMP/r.jsonl"; expect_exit 65 "jsonl"
run solve "$S/default.yaml" --json; cp "$TMP/out" "$TMP/solve.json"
run plot "$TMP/r.csv" --scene "$S/default.yaml" --dry-run; plot_rc=$rc

HEADPLAN_BIN="$HP_BIN" python3 - "$TMP" "$S" "$HP_SRC" <<'PY' && ok || bad "the table and its consumers disagree"
import csv, json, os, re, subprocess, sys
tmp, scenes, src = sys.argv[1:4]
table = [dict(zip(["name", "unit", "format", "shape", "rows", "numpy", "measured"], l.split("\t")))
         for l in open(os.path.join(tmp, "columns.tsv")).read().splitlines()[1:]]
assert table, "empty table"
AXES = [("x", "mm"), ("y", "mm"), ("z", "mm"), ("pitch", "deg"), ("roll", "deg"), ("yaw", "deg")]
bladders = [b["name"] for b in json.load(open(os.path.join(tmp, "solve.json")))["bladders"]]

def expand(cols):
    """The rows' column names, in the rows' order: consecutive per-bladder number columns
    are written bladder by bladder; a flags column is one cell."""
    out, i = [], 0
    while i < len(cols):
        c = cols[i]
        if c["shape"] == "bladders" and c["format"] != "flags":
            j = i
            while j < len(cols) and cols[j]["shape"] == "bladders" and cols[j]["format"] != "flags":
                j += 1
            for b in bladders:
                out += [k["name"].replace("{bladder}", b) for k in cols[i:j]]
            i = j
            continue
        if c["shape"] == "axes":
            out += [c["name"].replace("{axis}", a).replace("{unit}", u) for a, u in AXES]
        else:
            out.append(c["name"])
        i += 1
    return out

rows_cols = [c for c in table if c["rows"] == "yes"]
names = expand(rows_cols)
assert len(set(names)) == len(names), "duplicate column names"
data = [l for l in open(os.path.join(tmp, "r.csv")) if not l.startswith("#")]
header = next(csv.reader(data))
assert header == names, (header, names)
for line in open(os.path.join(tmp, "r.jsonl")).read().splitlines()[1:]:
    assert list(json.loads(line)) == names, line[:200]

# The plot reader's columns: each one it needs, removed, is refused by name; all are
# numeric columns of the table.
numeric = {n for c in rows_cols if c["format"] in ("number", "integer")
           for n in expand([c])}
hp = os.environ["HEADPLAN_BIN"]
needed = []
for drop in names:
    with open(os.path.join(tmp, "d.csv"), "w") as f:
        f.write(",".join("renamed" if n == drop else n for n in header) + "\n")
        f.writelines(data[1:])
    p = subprocess.run([hp, "plot", os.path.join(tmp, "d.csv"), "--scene",
                        os.path.join(scenes, "default.yaml"), "--dry-run"],
                       capture_output=True, text=True)
    if p.returncode == 65 and ("no column '%s'" % drop in p.stderr or
                               "(NAME_pressure_pa)" in p.stderr):
        needed.append(drop)
assert "line" in needed and "achieved_yaw_deg" in needed, needed
assert set(needed) - {"status"} <= numeric, set(needed) - numeric

# docs/batch.md's "Columns" table lists the table: name, unit, in the files, Python key.
doc = open(os.path.join(src, "docs", "batch.md")).read()
body = doc[doc.index("**Columns**"):]
body = body[body.index("\n|"):].strip().split("\n\n")[0].splitlines()[2:]
cells = [[c.strip().replace("\\|", "|") for c in l.strip("|").split(" | ")] for l in body]
documented = [(c[0].strip("`"), c[1], c[2], c[3].strip("`")) for c in cells]
listed = [(c["name"], c["unit"], c["rows"], c["numpy"]) for c in table]
assert documented == listed, "\n".join(map(str, [x for x in documented if x not in listed] +
                                                ["--"] + [x for x in listed if x not in documented]))

# The jobs comparisons blank the table's measured columns, read from the program.
measured = [c["name"] for c in table if c["measured"] == "yes"]
assert measured == ["solve_time_us"], measured
PY
[ "$plot_rc" -eq 0 ] && ok || bad "plot --dry-run of the batch CSV: exit $plot_rc"
finish
