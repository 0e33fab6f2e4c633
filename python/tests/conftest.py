"""Shared fixtures of the Python module's tests.

Run by ctest (test python_pytest) with PYTHONPATH at the build tree's module folder,
HEADPLAN_BIN at the command-line program and HEADPLAN_SRC at the source tree."""
import json
import os
import re
import subprocess

import pytest

import headplan

SRC = os.environ.get("HEADPLAN_SRC", os.path.join(os.path.dirname(__file__), "..", ".."))
BIN = os.environ.get("HEADPLAN_BIN", os.path.join(SRC, "build", "headplan"))
DEFAULT = os.path.join(SRC, "scenarios", "default.yaml")
UNDER_ASAN = os.environ.get("HP_UNDER_ASAN") == "1"


def scenario(name):
    return os.path.join(SRC, "scenarios", name)


# The wall-time budget the bit-for-bit comparisons plan with: a plan the clock stops is not
# reproducible (under the sanitizers on CI's loaded machine, Ipopt and SLSQP ran past the
# scenes' 1 s), and no plan of these tests needs more than a fraction of a second unloaded.
PATIENT_S = 60


def patient_scene(path, folder):
    """A copy of the scene at PATH in FOLDER (a pathlib folder) whose solver line allows
    PATIENT_S seconds, for comparisons with the command line, which reads its budget from
    the scene (the shell tests' patient_scenes, tests/cli_lib.sh)."""
    lines = open(path).read().split("\n")
    at = [i for i, l in enumerate(lines) if l.startswith("solver: {")]
    assert len(at) == 1, f"{path}: one flow-style 'solver:' line expected"
    line = re.sub(r"max_time_s: [^,}]*,? ?", "", lines[at[0]])
    lines[at[0]] = line.replace("solver: {", f"solver: {{max_time_s: {PATIENT_S}, ", 1)
    lines[at[0]] = lines[at[0]].replace(", }", "}")
    # The scene's trace stays where it is (its path is relative to the scene's folder).
    here = os.path.dirname(os.path.abspath(path))
    moved = [re.subn(r"^trace: \{file: ([^,}]+)",
                     lambda m: "trace: {file: " + os.path.normpath(os.path.join(here, m.group(1))),
                     l) for l in lines]
    lines = [l for l, _ in moved]
    traces = [l for l in lines if l.startswith("trace:")]
    assert sum(n for _, n in moved) == len(traces), f"{path}: a trace line not in flow style"
    out = folder / os.path.basename(path)
    out.write_text("\n".join(lines))
    return str(out)


def cli(*args, check=True):
    """Runs the headplan program; returns (exit status, stdout, stderr)."""
    env = dict(os.environ, LC_ALL="C")
    env.pop("LD_PRELOAD", None)  # the program is a plain (or fully instrumented) binary
    p = subprocess.run([BIN, *map(str, args)], capture_output=True, text=True, env=env)
    if check and p.returncode not in (0, 1):
        raise AssertionError(f"headplan {' '.join(map(str, args))}: exit {p.returncode}: {p.stderr}")
    return p.returncode, p.stdout, p.stderr


def cli_json(*args):
    return json.loads(cli(*args, "--json")[1])


@pytest.fixture(scope="session")
def default_scene():
    return headplan.load_scene(DEFAULT)


@pytest.fixture(scope="session")
def default_planner(default_scene):
    return headplan.Planner(default_scene)
