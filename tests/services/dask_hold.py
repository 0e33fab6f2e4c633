"""A task for test_dask_study.py that holds its worker on its first attempt, so the test can
kill that worker while the task runs; Dask's retry plans the trace as any other task."""
import os
import time

import dask_study


def hold_then_plan(flag, scene, trace, **run_options):
    try:
        fd = os.open(flag, os.O_CREAT | os.O_EXCL | os.O_WRONLY)
    except FileExistsError:  # the retry, on whichever worker Dask chose
        return dask_study.plan_one(scene, trace, **run_options)
    os.write(fd, str(os.getpid()).encode())
    os.close(fd)
    time.sleep(600)  # the test kills this process long before; if not, its wait fails
    raise RuntimeError("the worker holding this task was not killed")
