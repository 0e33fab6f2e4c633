"""examples/python/dask_study.py on a two-worker Dask LocalCluster over TCP on 127.0.0.1
(docs/batch.md, "Studies on Dask"): many traces, and one long trace in chunks, give the
arrays of one-process run_trace bit for bit (every key but the measured ones, as
headplan.columns() names them);
each worker builds its planner once; a worker killed while it holds a task changes nothing.
Skipped, saying why, without Debian's python3-distributed. Waits are generous and polled
(the CI machine is loaded on purpose); nothing asserts a time."""
import os
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

distributed = pytest.importorskip("distributed", reason="Dask distributed not installed "
                                  "(Debian package python3-distributed)")
import headplan  # noqa: E402

SRC = os.environ.get("HEADPLAN_SRC", os.path.join(os.path.dirname(__file__), "..", ".."))
HERE = os.path.dirname(os.path.abspath(__file__))
EXAMPLES = os.path.join(SRC, "examples", "python")
# The workers import dask_study and dask_hold by name: put their folders on the path the
# worker processes inherit, and on this one's.
for d in (EXAMPLES, HERE):
    sys.path.insert(0, d)
os.environ["PYTHONPATH"] = os.pathsep.join(
    [EXAMPLES, HERE] + [p for p in [os.environ.get("PYTHONPATH")] if p])
import dask_study  # noqa: E402
import dask_hold  # noqa: E402

SCENE = os.path.join(SRC, "scenarios", "default.yaml")
# The measured columns (a time: not a function of the inputs), from the one column table:
# their keys in run_trace's dict, their names in batch's files.
MEASURED_KEYS = {c["numpy"] for c in headplan.columns() if c["measured"] and c["numpy"]}
MEASURED_NAMES = {c["name"] for c in headplan.columns() if c["measured"] and c["rows"]}
TRACES = [os.path.join(SRC, "scenarios", "traces", n)
          for n in ("drift_10hz.csv", "nodding.csv", "breathing.csv", "step.csv")]
WAIT_S = 300  # a bound for a loaded machine, not a time the test expects


def rows_kind(path):
    with open(path) as f:
        return None if f.readline().startswith("# headplan-trace:") else "deviation"


def assert_same(got, want):
    assert got.keys() == want.keys()
    for k in want:
        if k in MEASURED_KEYS:
            continue
        if k == "messages":
            assert got[k] == want[k]
        else:
            assert got[k].dtype == want[k].dtype and got[k].shape == want[k].shape, k
            assert np.array_equal(got[k], want[k], equal_nan=got[k].dtype.kind == "f"), k


@pytest.fixture(scope="module")
def client():
    from distributed import Client, LocalCluster
    cluster = LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                           protocol="tcp", host="127.0.0.1", dashboard_address=None,
                           silence_logs=40)
    c = Client(cluster)
    try:
        c.wait_for_workers(2, timeout=WAIT_S)
        yield c
    finally:
        c.close()
        cluster.close()


@pytest.fixture(scope="module")
def one_process():
    p = headplan.Planner(headplan.load_scene(SCENE))
    return {tr: p.run_trace(tr, rows=rows_kind(tr)) for tr in TRACES}


def test_traces_equal_one_process(client, one_process):
    runs = [dask_study.plan_traces(client, SCENE, [tr], rows=rows_kind(tr))[0]
            for tr in TRACES]
    for tr, run in zip(TRACES, runs):
        assert_same(run, one_process[tr])
    # One planner per worker process for this scene, however many tasks it ran.
    builds = client.run(lambda: dask_study.builds)
    assert len(builds) == 2 and all(b <= 1 for b in builds.values()), builds
    assert sum(builds.values()) >= 1


def test_chunks_equal_one_process(client):
    a = np.loadtxt(TRACES[0], delimiter=",", comments="#", skiprows=2)
    t, poses = a[:, 0], a[:, 1:]
    want = headplan.Planner(headplan.load_scene(SCENE)).run_trace(poses, t=t, rows="deviation")
    got = dask_study.plan_chunks(client, SCENE, poses, t=t, rows="deviation", chunk_rows=250)
    assert len(got["line"]) == 1800
    assert_same(got, want)


def blank_times(path):
    """The file's lines with the measured columns blanked."""
    out, cols = [], None
    with open(path) as f:
        for line in f:
            if line.startswith("#"):
                out.append(line)
            elif cols is None:
                cols = [i for i, n in enumerate(line.rstrip("\n").split(","))
                        if n in MEASURED_NAMES]
                assert cols, "no measured column in the header"
                out.append(line)
            else:
                fields = line.split(",")
                for i in cols:
                    fields[i] = ""
                out.append(",".join(fields))
    return out


def test_batch_files_equal_one_process(client, tmp_path):
    hp = os.environ.get("HEADPLAN_BIN", os.path.join(SRC, "build", "headplan"))
    env = dict(os.environ)
    env.pop("LD_PRELOAD", None)  # the program is a plain (or fully instrumented) binary
    files = dask_study.batch_files(client, SCENE, TRACES[:2], str(tmp_path / "results"), hp,
                                   ("--rows", "deviation"))
    assert [os.path.basename(f) for f in files] == ["drift_10hz.csv", "nodding.csv"]
    for tr, f in zip(TRACES[:2], files):
        one = str(tmp_path / "one.csv")
        subprocess.run([hp, "batch", SCENE, tr, "--no-progress", "--rows", "deviation",
                        "-o", one], check=True, capture_output=True, env=env)
        assert blank_times(f) == blank_times(one)


def test_worker_killed_mid_study(client, one_process, tmp_path):
    flag = str(tmp_path / "held")
    futures = [client.submit(dask_hold.hold_then_plan, flag, SCENE, TRACES[0],
                             rows=rows_kind(TRACES[0]), pure=False)]
    futures += [client.submit(dask_study.plan_one, SCENE, tr, rows=rows_kind(tr), pure=False)
                for tr in TRACES[1:]]
    end = time.monotonic() + WAIT_S
    while not (os.path.exists(flag) and os.path.getsize(flag) > 0):
        assert time.monotonic() < end, "the held task never started"
        time.sleep(0.2)
    with open(flag) as f:
        pid = int(f.read())
    assert pid in client.run(os.getpid).values()  # a worker of this cluster
    os.kill(pid, signal.SIGKILL)
    distributed.wait(futures, timeout=WAIT_S)
    runs = client.gather(futures)
    for tr, run in zip(TRACES, runs):
        assert_same(run, one_process[tr])
    assert pid not in client.run(os.getpid).values()  # the task ran again elsewhere
