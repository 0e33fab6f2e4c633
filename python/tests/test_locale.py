"""A host that sets a comma locale (locale.setlocale(locale.LC_ALL, "") in Germany) plans an
array trace as in the C locale: run_trace prints the array as CSV for the library's trace
reader, and "%.17g" wrote "0,1" under the comma locale, so every row split into extra
columns. The comma locale is the system's when installed, else built with localedef into a
temporary LOCPATH (as tests/support/comma_locale.h); skipped only when neither works."""
import locale
import os
import subprocess

import numpy as np
import pytest

import headplan

from conftest import DEFAULT


def comma_locale(tmp_path):
    for name in ("de_DE.UTF-8", "de_DE.utf8", "fr_FR.UTF-8"):
        try:
            locale.setlocale(locale.LC_NUMERIC, name)
        except locale.Error:
            continue
        if locale.localeconv()["decimal_point"] == ",":
            return True
    p = subprocess.run(["localedef", "-i", "de_DE", "-f", "UTF-8", str(tmp_path / "de_DE.UTF-8")],
                       capture_output=True)
    if p.returncode != 0:
        return False
    os.environ["LOCPATH"] = str(tmp_path)  # glibc reads it at every setlocale
    try:
        locale.setlocale(locale.LC_NUMERIC, "de_DE.UTF-8")
    except locale.Error:
        return False
    return locale.localeconv()["decimal_point"] == ","


def test_array_trace_under_comma_locale(tmp_path):
    rng = np.random.default_rng(7)
    poses = rng.uniform(-1.5, 1.5, (12, 6))
    t = 0.1 * np.arange(12) + 1.0 / 3.0
    sc = headplan.load_scene(DEFAULT)
    want = headplan.Planner(sc).run_trace(poses, t=t, rows="correction")
    saved = os.environ.get("LOCPATH")
    try:
        if not comma_locale(tmp_path):
            pytest.skip("no comma-decimal locale could be set or built")
        got = headplan.Planner(headplan.load_scene(DEFAULT)).run_trace(poses, t=t,
                                                                      rows="correction")
        assert locale.localeconv()["decimal_point"] == ","  # the host's locale is kept
    finally:
        locale.setlocale(locale.LC_NUMERIC, "C")
        if saved is None:
            os.environ.pop("LOCPATH", None)
        else:
            os.environ["LOCPATH"] = saved
    assert list(got["status"]) == list(want["status"])
    assert np.array_equal(got["t_s"], want["t_s"])
    assert np.array_equal(got["t_s"], t)
    assert np.array_equal(got["achieved"], want["achieved"])
    assert np.array_equal(got["pressure_pa"], want["pressure_pa"])
