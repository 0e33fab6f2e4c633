"""load_scene: files, path-like objects, dicts, and the parser's messages as exceptions."""
import os
import pathlib
import re

import numpy as np
import pytest

import headplan
from conftest import DEFAULT, scenario


def test_load_file_reads_every_field(default_scene):
    sc = default_scene
    assert sc.kind == "layout"
    assert sc.name == "default adult head, eight bladders"
    assert len(sc.bladder_names) == 8 and sc.bladder_names[0] == "base_neck_left"
    # The scene's correction comes back in mm and degrees as written in the file.
    assert sc.correction.tolist() == [1.0, 0.0, -0.5, 0.3, 0.0, -0.2]
    assert sc.trace.endswith(os.path.join("traces", "drift_10hz.csv"))
    assert sc.trace_rows == "deviation"
    assert sc.backend == "realtime" and sc.level == "auto"


def test_layout_dict_in_mm(default_scene):
    L = default_scene.layout
    assert L["head"]["shape"] == "ellipsoid"
    assert L["head"]["semi_axes_mm"].tolist() == [77.5, 115.0, 97.5]
    assert len(L["bladders"]) == 8
    b = L["bladders"][0]
    assert b["Ri_mm"] == 27.0 and b["Ro_mm"] == 30.0
    assert b["pressure_min_pa"] == -5000.0 and b["pressure_max_pa"] == 10000.0
    assert np.linalg.norm(b["normal"]) == pytest.approx(1.0, abs=1e-12)
    # touch placement: the nominal contact distance is Ro (no preload).
    assert b["rho0_mm"] == pytest.approx(30.0, abs=1e-9)


def test_pathlike_and_bytes(default_scene):
    a = headplan.load_scene(pathlib.Path(DEFAULT))
    b = headplan.load_scene(os.fsencode(DEFAULT))
    assert a.bladder_names == b.bladder_names == default_scene.bladder_names


def test_dict_scene_plans_like_the_file():
    d = {
        "headplan_scene": 1,
        "name": "from a dict",
        "head": {"shape": "ellipsoid", "semi_axes_mm": [77.5, 115, 97.5],
                 "center_mm": [0, 0, 0], "mass_kg": 4.5},
        "pivot_mm": np.zeros(3),  # NumPy values are accepted
        "bladder_defaults": {"Ri_mm": 27, "Ro_mm": 30,
                             "material": {"convention": "paper", "C1_pa": 1.1e4, "C2_pa": 2.2e4},
                             "pressure_min_kpa": -5, "pressure_max_kpa": 10,
                             "stretch_min": 0.8, "stretch_max": 1.3},
        "bladders": [
            {"name": "base_neck_left", "touch_dir": [0.35, -0.45, -1]},
            {"name": "base_neck_right", "touch_dir": [-0.35, -0.45, -1]},
            {"name": "base_skull_left", "touch_dir": [0.35, 0.45, -1]},
            {"name": "base_skull_right", "touch_dir": [-0.35, 0.45, -1]},
            {"name": "side_fore_left", "touch_dir": [1, 0.45, 0.15]},
            {"name": "side_fore_right", "touch_dir": [-1, 0.45, 0.15]},
            {"name": "side_chin_left", "touch_dir": [1, -0.45, -0.15]},
            {"name": "side_chin_right", "touch_dir": [-1, -0.45, -0.15]},
        ],
        "model": {"level": "auto", "tolerance_mm": 0.01, "auto_translation_mm": 5,
                  "auto_rotation_deg": 3},
    }
    sc = headplan.load_scene(d)
    assert sc.file == "<dict>" and sc.name == "from a dict"
    file_sc = headplan.load_scene(DEFAULT)
    c = [1.0, 0.0, -0.5, 0.3, 0.0, -0.2]
    a = headplan.Planner(sc).plan(c)
    b = headplan.Planner(file_sc).plan(c)
    assert np.array_equal(a["pressure_pa"], b["pressure_pa"])


def test_dict_error_names_line_and_key():
    with pytest.raises(headplan.Error) as e:
        headplan.load_scene({"headplan_scene": 1, "name": "x", "bladders": [], "colour": "red"})
    msg = str(e.value)
    assert msg.startswith("<dict>:"), msg
    assert re.match(r"<dict>:\d+:\d+: ", msg), msg


def test_file_errors_carry_file_line_col(tmp_path):
    bad = tmp_path / "bad.yaml"
    bad.write_text(open(DEFAULT).read().replace("Ri_mm: 27", "Ri_mm: -27"))
    with pytest.raises(headplan.Error) as e:
        headplan.load_scene(str(bad))
    assert re.match(re.escape(str(bad)) + r":\d+:\d+: .*Ri", str(e.value)), str(e.value)
    assert isinstance(e.value, ValueError)


def test_missing_file_and_wrong_type(tmp_path):
    with pytest.raises(headplan.Error, match="nope.yaml"):
        headplan.load_scene(str(tmp_path / "nope.yaml"))
    with pytest.raises(TypeError):
        headplan.load_scene(42)
    with pytest.raises(TypeError):
        headplan.load_scene({"headplan_scene": object()})


def test_bladder_scene_has_no_layout():
    sc = headplan.load_scene(scenario("paper_expansion.yaml"))
    assert sc.kind == "bladder"
    assert set(sc.bladder) == {"Ri_mm", "Ro_mm", "c1_pa", "c2_pa"}
    with pytest.raises(headplan.Error, match="single-bladder"):
        headplan.Planner(sc)
    with pytest.raises(headplan.Error, match="single-bladder"):
        sc.layout
