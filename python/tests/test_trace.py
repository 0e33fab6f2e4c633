"""run_trace against `headplan batch --no-times`: same rows, same statuses, same numbers bit
for bit (the batch CSV prints the shortest text that reads back to the same double)."""
import csv
import io

import numpy as np
import pytest

import headplan
import subprocess

from conftest import BIN, DEFAULT, cli, scenario, patient_scene

KEYS = headplan.POSE_KEYS


def batch_csv(*args):
    rc, out, err = cli("batch", *args, "--format", "csv", "--no-times", "--no-progress", check=False)
    assert rc in (0, 1, 65), err
    # The metadata record is the leading '#' lines; then the header and one row per row.
    body = "".join(l for l in io.StringIO(out) if not l.startswith("#"))
    return list(csv.DictReader(io.StringIO(body)))


def assert_same_as_batch(r, rows, names):
    assert len(rows) == len(r["status"])
    for i, row in enumerate(rows):
        assert r["status"][i] == row["status"], i
        if row["status"] == "bad-row":
            assert np.all(np.isnan(r["pressure_pa"][i]))
            continue
        assert r["line"][i] == int(row["line"])
        assert r["t_s"][i] == float(row["t_s"])
        for c, k in enumerate(KEYS):
            assert r["achieved"][i, c] == float(row["achieved_" + k]), (i, k)
        for b, name in enumerate(names):
            assert r["pressure_pa"][i, b] == float(row[name + "_pressure_pa"]), (i, name)
        assert r["iterations"][i] == int(row["iterations"])
        bind = ";".join(f"{names[b]}:" + "|".join(headplan.binding_names(int(f)))
                        for b, f in enumerate(r["binding"][i]) if f)
        assert bind == row["binding"], i


@pytest.mark.parametrize("name,extra", [("default.yaml", []), ("nodding.yaml", []),
                                        ("saturation.yaml", ["traces/nodding.csv"]),
                                        ("default.yaml", ["--backend", "nlopt-slsqp"])])
def test_trace_equals_batch(name, extra, tmp_path):
    path = patient_scene(scenario(name), tmp_path)
    sc = headplan.load_scene(path)
    kw = {}
    if "--backend" in extra:
        kw["backend"] = extra[extra.index("--backend") + 1]
    p = headplan.Planner(sc, **kw)
    args = [path]
    trace = None
    if extra and not extra[0].startswith("--"):
        trace = scenario(extra[0])
        args.append(trace)
        extra = extra[1:]
    rows = batch_csv(*args, *extra)
    r = p.run_trace(trace)
    assert_same_as_batch(r, rows, p.bladder_names)


def test_rate_limits_carry_over_like_batch(tmp_path):
    # Jumps of 3 mm each cycle need more than the saturation scene's 2 kPa per cycle.
    sat = patient_scene(scenario("saturation.yaml"), tmp_path)
    sc = headplan.load_scene(sat)
    poses = np.zeros((12, 6))
    poses[:, 2] = np.where(np.arange(12) % 2, 3.0, -3.0)
    r = headplan.Planner(sc).run_trace(poses, rows="correction")
    flags = np.bitwise_or.reduce(r["binding"].ravel())
    assert flags & 0x30, "the rate limits were never exercised"
    f = tmp_path / "jumps.csv"
    np.savetxt(f, np.column_stack([np.arange(12) * 0.1, poses]), delimiter=",", fmt="%.17g",
               header="t_s,x_mm,y_mm,z_mm,pitch_deg,roll_deg,yaw_deg", comments="")
    rows = batch_csv(sat, str(f), "--rows", "correction")
    rf = headplan.Planner(sc).run_trace(str(f), rows="correction")
    assert_same_as_batch(rf, rows, sc.bladder_names)
    assert np.array_equal(rf["pressure_pa"], r["pressure_pa"])
    # Without carrying the rate limits over, no rate limit binds.
    free = headplan.Planner(sc).run_trace(poses, rows="correction", rate_limits=False)
    assert not np.bitwise_or.reduce(free["binding"].ravel()) & 0x30


def test_array_trace_equals_file(default_scene, default_planner):
    # Line 1 is the rows-kind directive, line 2 the header.
    text = np.genfromtxt(default_scene.trace, delimiter=",", names=True, skip_header=1)
    poses = np.column_stack([text[k] for k in KEYS])
    a = default_planner.run_trace(poses, t=text["t_s"], rows="deviation")
    f = default_planner.run_trace()  # the scene's trace, rows: deviation
    for key in ("pressure_pa", "achieved", "desired", "t_s", "binding", "pose_error"):
        assert np.array_equal(a[key], f[key]), key
    assert a["line"][:3].tolist() == [0, 1, 2] and f["line"][:3].tolist() == [3, 4, 5]
    # A deviation row asks for its exact inverse rigid motion about the pivot (the default
    # scene's pivot is the origin), checked here with numpy: R = Rz(yaw) Ry(roll) Rx(pitch),
    # correction ∘ deviation = identity to rounding (1e-12 mm / rad).
    def rot(deg):
        px, ry, yz = np.radians(deg)
        cx, sx, cy, sy, cz, sz = np.cos(px), np.sin(px), np.cos(ry), np.sin(ry), np.cos(yz), np.sin(yz)
        Rx = np.array([[1, 0, 0], [0, cx, -sx], [0, sx, cx]])
        Ry = np.array([[cy, 0, sy], [0, 1, 0], [-sy, 0, cy]])
        Rz = np.array([[cz, -sz, 0], [sz, cz, 0], [0, 0, 1]])
        return Rz @ Ry @ Rx
    for dev, cor in zip(poses[::97], a["desired"][::97]):
        Rd, Rc = rot(dev[3:]), rot(cor[3:])
        assert np.abs(Rc @ Rd - np.eye(3)).max() < 1e-12
        assert np.abs(Rc @ dev[:3] + cor[:3]).max() < 1e-12


def test_array_rows_never_guessed(default_planner):
    poses = np.array([[0.5, 0, 0, 0, 0, 0], [0, 0.5, 0, 0, 0, 0]])
    with pytest.raises(headplan.Error, match="rows="):
        default_planner.run_trace(poses)  # an array states no kind: the caller must
    r = default_planner.run_trace(poses, rows="correction")
    assert np.array_equal(r["desired"], poses)
    assert r["t_s"].tolist() == [0.0, 0.1]


def test_bad_rows_reported_and_skipped(tmp_path, default_planner):
    f = tmp_path / "t.csv"
    f.write_text("t_s,x_mm,y_mm,z_mm,pitch_deg,roll_deg,yaw_deg\n"
                 "0,0.1,0,0,0,0,0\n0.1,zzz,0,0,0,0,0\n0.2,0.2,0,0,0,0,0\n")
    r = default_planner.run_trace(str(f), rows="correction")
    assert r["status"].tolist() == ["reached", "bad-row", "reached"]
    assert len(r["messages"]) == 1 and r["messages"][0].startswith(f"{f}:3:")
    rows = batch_csv(DEFAULT, str(f), "--rows", "correction")
    assert_same_as_batch(r, rows, default_planner.bladder_names)
    x = np.zeros((2, 6))
    x[1, 3] = np.nan  # the reader refuses non-finite numbers, as in a file
    r = default_planner.run_trace(x, rows="correction")
    assert r["status"].tolist() == ["reached", "bad-row"]


def test_trace_errors(tmp_path, default_planner):
    with pytest.raises(headplan.Error, match="nope.csv"):
        default_planner.run_trace(str(tmp_path / "nope.csv"))
    with pytest.raises(headplan.Error, match="rows"):
        default_planner.run_trace(np.zeros((2, 6)), rows="sideways")
    with pytest.raises(headplan.Error, match="t: expected 2 time stamps"):
        default_planner.run_trace(np.zeros((2, 6)), t=[0.0], rows="correction")
    with pytest.raises(headplan.Error, match="t: element 1 is NaN"):
        default_planner.run_trace(np.zeros((2, 6)), t=[0.0, np.nan], rows="correction")
    with pytest.raises(headplan.Error, match="expected shape"):
        default_planner.run_trace(np.zeros((2, 7)), rows="correction")
    with pytest.raises(TypeError):
        default_planner.run_trace(np.zeros((2, 6), complex), rows="correction")
    with pytest.raises(headplan.Error, match="time stamps come from the trace file"):
        default_planner.run_trace(DEFAULT, t=[0.0])
    nt = headplan.Planner(headplan.load_scene(scenario("saturation.yaml")))
    with pytest.raises(headplan.Error, match="names no trace"):
        nt.run_trace()


def test_every_path_gives_the_same_answer(tmp_path):
    """One trace through every path a user can take: a file, a pipe on standard input, a
    FIFO, bash process substitution, the same rows as JSON Lines, and the Python module
    reading the file and the FIFO. The command line's rows are byte-identical (only the
    metadata names the input differently) and the module's numbers are bit-identical."""
    import json
    import os
    import threading
    scene = DEFAULT
    src = headplan.load_scene(scene).trace
    lines = open(src).read().splitlines()
    assert lines[0] == "# headplan-trace: rows=deviation"
    trace = tmp_path / "trace.csv"
    trace.write_text("\n".join(lines[:62]) + "\n")  # directive, header, 60 rows
    header = lines[1].split(",")
    jsonl = tmp_path / "trace.jsonl"
    with open(jsonl, "w") as f:
        f.write('{"headplan_trace": 1, "rows": "deviation"}\n')
        for l in lines[2:62]:
            f.write(json.dumps({k: float(v) for k, v in zip(header, l.split(","))}) + "\n")

    def rows_of(out):
        return [l for l in out.splitlines() if not l.startswith("#")]

    def run(args, **kw):
        env = dict(os.environ, LC_ALL="C")
        env.pop("LD_PRELOAD", None)
        p = subprocess.run(args, capture_output=True, text=True, env=env, **kw)
        assert p.returncode == 0, (args, p.stderr)
        return rows_of(p.stdout)

    base = [BIN, "batch", scene]
    opts = ["--format", "csv", "--no-times", "--no-progress"]
    by_file = run(base + [str(trace)] + opts)
    assert len(by_file) == 61  # header + 60 rows
    assert run(base + ["-"] + opts, input=trace.read_text()) == by_file
    fifo = tmp_path / "fifo.csv"
    os.mkfifo(fifo)

    def feed():
        with open(fifo, "w") as f:
            f.write(trace.read_text())
    t = threading.Thread(target=feed, daemon=True)  # a failure cannot hang on the FIFO
    t.start()
    assert run(base + [str(fifo)] + opts) == by_file
    t.join()
    cmd = " ".join(f"'{a}'" for a in base) + f" <(cat '{trace}') " + " ".join(opts)
    assert run(["bash", "-c", cmd]) == by_file
    # JSON Lines in, CSV out: the rows' text differs only in the line numbers (one record
    # per line there, against directive + header + rows in the CSV).
    by_jsonl = run(base + [str(jsonl)] + opts)
    strip_line = lambda rows: [r.split(",", 1)[1] for r in rows]
    assert strip_line(by_jsonl) == strip_line(by_file)

    rows = list(csv.DictReader(io.StringIO("\n".join(by_file))))
    p = headplan.Planner(headplan.load_scene(scene))
    assert_same_as_batch(p.run_trace(str(trace)), rows, p.bladder_names)
    t = threading.Thread(target=feed, daemon=True)  # a failure cannot hang on the FIFO
    t.start()
    r = headplan.Planner(headplan.load_scene(scene)).run_trace(str(fifo))
    t.join()
    assert_same_as_batch(r, rows, p.bladder_names)


def test_rows_must_agree_with_the_scenes_trace_rows():
    """rows= against the scene's own trace.rows is refused, as batch and horizon refuse
    --rows: step.csv states nothing, and rows='correction' planned its deviations with every
    sign flipped."""
    p = headplan.Planner(headplan.load_scene(scenario("horizon/step.yaml")))
    with pytest.raises(headplan.Error, match="trace.rows says deviation"):
        p.run_trace(None, rows="correction")
    a, b = p.run_trace(None), p.run_trace(None, rows="deviation")
    assert np.array_equal(a["achieved"], b["achieved"])


def test_array_bad_rows_named_by_their_index(default_planner):
    # An array's `line` is its row index; a bad row's message named the line and column of
    # the CSV text the array is written as ('<array>:3:23' for row 1), another row.
    rows = np.tile([1, 0, -0.5, 0.3, 0, -0.2], (4, 1))
    rows[1, 1] = np.nan
    rows[3, 0] = 1e-310
    r = default_planner.run_trace(rows, rows="correction")
    assert list(r["line"]) == [0, 1, 2, 3]
    assert list(r["status"]) == ["reached", "bad-row", "reached", "bad-row"]
    assert r["messages"] == ["<array> row 1: y_mm: not a number",
                             "<array> row 3: x_mm: too small for a double"]
    # Over a horizon the refusal names the same number as `line`.
    with pytest.raises(headplan.Error, match=r"^line 2: t_s: 1 s is not after"):
        default_planner.run_trace(rows[[0, 2, 2, 0]], t=[0, 2, 1, 3], rows="correction",
                                  mode="greedy")


def test_refused_rows_carry_the_planners_reason(tmp_path, default_planner):
    # A row the planner refused (invalid-input: an 89.9 deg pitch, whose closest pose the
    # round trip refutes) had no message, where batch prints the planner's reason for it
    # ("FILE:LINE: reason") and plan() returns it. Now in `messages`, in row order with the
    # bad rows' messages, word for word batch's.
    f = tmp_path / "t.csv"
    f.write_text("# headplan-trace: rows=correction\n"
                 "t_s,x_mm,y_mm,z_mm,pitch_deg,roll_deg,yaw_deg\n"
                 "0,1,0,0,0,0,0\n1,0,0,0,89.9,0,0\n2,zzz,0,0,0,0,0\n3,0,0,0,20,0,0\n")
    r = default_planner.run_trace(str(f))
    assert r["status"].tolist() == ["reached", "invalid-input", "bad-row", "closest"]
    rc, _, err = cli("batch", DEFAULT, str(f), "--format", "csv", "--no-times",
                     "--no-progress", check=False)
    assert rc == 65
    said = [l[len("headplan batch: "):] for l in err.splitlines()
            if l.startswith(f"headplan batch: {f}:")]
    refusal = [m for m in said if m.startswith(f"{f}:4: ")]
    assert len(said) == 2 and len(refusal) == 1 and "identifiable range" in refusal[0], err
    # batch prints a bad row when it reads it and a refusal after planning: compared as sets,
    # and messages is in row order.
    assert sorted(r["messages"]) == sorted(said) and r["messages"][0] == refusal[0]
    one = default_planner.plan([0, 0, 0, 89.9, 0, 0])
    assert one["status"] == "invalid-input" and "identifiable range" in one["message"]
    # An array's refused row is named by its index, as its bad rows are.
    a = default_planner.run_trace(np.array([[1, 0, 0, 0, 0, 0], [0, 0, 0, 89.9, 0, 0]]),
                                  rows="correction")
    assert a["status"].tolist() == ["reached", "invalid-input"]
    assert a["messages"] == ["<array> row 1: " + refusal[0].split(": ", 1)[1]]


def test_three_front_ends_agree(tmp_path):
    """One trace through the three front-ends of the library's trace call (hp_trace_plan_run):
    `headplan batch`, `headplan horizon --mode greedy` and run_trace in batch and greedy mode.
    Without a per-second limit greedy is batch's plan, so all four agree bit for bit: the
    pressures of the horizon CSV are printed in kPa, compared as batch's Pa * 1e-3."""
    trace = tmp_path / "step80.csv"
    with open(scenario("traces/step.csv")) as f:
        trace.write_text("".join(f.readlines()[:81]))  # header + 80 rows
    scene = scenario("horizon/step.yaml")
    p = headplan.Planner(headplan.load_scene(scene))
    names = p.bladder_names
    rows = batch_csv(scene, str(trace), "--rows", "deviation")
    batch = p.run_trace(str(trace), rows="deviation")
    greedy = p.run_trace(str(trace), rows="deviation", mode="greedy")
    assert_same_as_batch(batch, rows, names)
    for k in ("pressure_pa", "ri_mm", "achieved", "desired"):
        assert np.array_equal(batch[k], greedy[k]), k
    assert list(batch["status"]) == list(greedy["status"])
    out = tmp_path / "greedy.csv"
    rc, _, err = cli("horizon", scene, str(trace), "--rows", "deviation", "--mode", "greedy",
                     "-o", str(out), check=False)
    assert rc in (0, 1), err
    body = "".join(l for l in open(out) if not l.startswith("#"))
    hz = list(csv.DictReader(io.StringIO(body)))
    assert len(hz) == len(rows) == 80
    for i, (h, b) in enumerate(zip(hz, rows)):
        assert h["status"] == b["status"], i
        for k in KEYS:
            assert h["achieved_" + k] == b["achieved_" + k], (i, k)
        for n in names:
            assert float(h[n + "_kpa"]) == float(b[n + "_pressure_pa"]) * 1e-3, (i, n)
