"""Shared fixtures of the Python module's tests.

Run by ctest (test python_pytest) with PYTHONPATH at the build tree's module folder,
HEADPLAN_BIN at the command-line program and HEADPLAN_SRC at the source tree."""
import json
import os
import subprocess

import pytest

import headplan

SRC = os.environ.get("HEADPLAN_SRC", os.path.join(os.path.dirname(__file__), "..", ".."))
BIN = os.environ.get("HEADPLAN_BIN", os.path.join(SRC, "build", "headplan"))
DEFAULT = os.path.join(SRC, "scenarios", "default.yaml")
UNDER_ASAN = os.environ.get("HP_UNDER_ASAN") == "1"


def scenario(name):
    return os.path.join(SRC, "scenarios", name)


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
