"""A headplan study on a Dask `distributed` cluster (docs/batch.md, "Studies on Dask").

Plans many traces, or one long trace in chunks, with `Planner.run_trace` on the workers of a
cluster: a `LocalCluster` on one machine, or a scheduler's address in production. Each
worker builds its planner once per (scene, planner options) and reuses it for every task it
runs (`run_trace` starts every trace from the nominal answer, so a reused planner plans a
trace exactly as a fresh one). Results come back as the NumPy arrays of `run_trace`, or,
with batch_files, as the result files `headplan batch` writes on every other route.

    from distributed import Client
    import dask_study
    client = Client("tcp://scheduler:8786")            # or Client(LocalCluster(...))
    runs = dask_study.plan_traces(client, "study.yaml", ["traces/a.csv", "traces/b.csv"])
    run = dask_study.plan_chunks(client, "study.yaml", poses, t=t, rows="deviation",
                                 chunk_rows=500)
    files = dask_study.batch_files(client, "study.yaml", ["traces/a.csv"], "results")

Paths are read by the workers, so they must name the same files there (a shared folder).
Both helpers need this module importable on the workers (on their PYTHONPATH, or sent with
`client.upload_file`) and the headplan module installed there.

A chunk starts from the nominal answer, as a shard of `headplan batch --jobs` does before its
join is repaired: chunks give exactly the rows of one run only where the rate limits do not
bind (a scene without `rate_max_kpa`, as scenarios/default.yaml). A worker that dies
mid-study costs nothing but time: Dask runs its tasks again on another worker, and a task's
result depends on its inputs alone.
"""
import os
import subprocess

import numpy as np

import headplan

_planners = {}  # this worker process's planners, by (scene path, planner options)
builds = 0      # how many planners this process has built (the tests read it)


def planner(scene, **options):
    """The planner of this process for a scene file and Planner options, built on first use."""
    global builds
    key = (str(scene), tuple(sorted(options.items())))
    p = _planners.get(key)
    if p is None:
        p = headplan.Planner(headplan.load_scene(scene), **options)
        _planners[key] = p
        builds += 1
    return p


def plan_one(scene, trace, planner_options=None, **run_options):
    """One task on a worker: run_trace(trace, **run_options) with this worker's planner."""
    return planner(scene, **(planner_options or {})).run_trace(trace, **run_options)


def plan_traces(client, scene, traces, planner_options=None, **run_options):
    """Plans every trace (file paths) on the cluster; returns run_trace's dicts, in order."""
    futures = [client.submit(plan_one, scene, tr, planner_options, pure=False, **run_options)
               for tr in traces]
    return client.gather(futures)


def join_chunks(runs, starts):
    """One run_trace dict from chunk results, `line` counted in the whole array."""
    out = {}
    for k in runs[0]:
        if k == "messages":
            out[k] = [m for r in runs for m in r[k]]
        elif k == "line":
            out[k] = np.concatenate([r[k] + s for r, s in zip(runs, starts)])
        else:
            out[k] = np.concatenate([r[k] for r in runs])
    return out


def plan_chunks(client, scene, poses, t=None, rows=None, chunk_rows=1000,
                planner_options=None, **run_options):
    """Plans an N x 6 array of poses (mm, degrees) in chunks of chunk_rows rows on the
    cluster and joins them: the dict run_trace returns for the whole array. A message about
    a row names its row within its chunk."""
    poses = np.asarray(poses, dtype=float)
    n = len(poses)
    if t is None:
        t = np.arange(n) * 0.1  # run_trace's default time stamps
    t = np.asarray(t, dtype=float)
    if chunk_rows < 1 or len(t) != n:
        raise ValueError(f"chunk_rows {chunk_rows} must be 1 or more and t have {n} values")
    starts = list(range(0, n, chunk_rows))
    futures = [client.submit(plan_one, scene, poses[s:s + chunk_rows], planner_options,
                             t=t[s:s + chunk_rows], rows=rows, pure=False, **run_options)
               for s in starts]
    return join_chunks(client.gather(futures), starts)


def batch_file(scene, trace, results, headplan="headplan", args=()):
    """One task on a worker: `headplan batch SCENE TRACE -o RESULTS/NAME.csv` (NAME the
    trace's file name without .csv), the file every other route writes (one process, --jobs,
    GNU parallel, Slurm). Returns its path; raises with batch's message if batch fails."""
    out = os.path.join(results, os.path.basename(trace).removesuffix(".csv") + ".csv")
    os.makedirs(results, exist_ok=True)
    p = subprocess.run([headplan, "batch", scene, trace, "--no-progress", *args, "-o", out],
                       capture_output=True, text=True)
    if p.returncode not in (0, 1):  # 1: some rows only closest, with --strict
        raise RuntimeError(f"headplan batch {scene} {trace}: exit {p.returncode}: "
                           f"{p.stderr.strip()}")
    return out


def batch_files(client, scene, traces, results, headplan="headplan", args=()):
    """Plans every trace with `headplan batch` on the cluster into RESULTS (a folder the
    workers share); returns the result paths, in order."""
    return client.gather([client.submit(batch_file, scene, tr, results, headplan, tuple(args),
                                        pure=False) for tr in traces])
