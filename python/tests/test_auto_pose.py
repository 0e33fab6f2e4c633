"""Planner's auto_pose (mm and degrees, the command line's units): the correction at which
auto, on a scene with a load, measures every level's model error (hp_settings.auto_pose).
By default the scene's correction, as `headplan solve` plans it; the keyword overrides it.
The fixture tests/scene/auto_pose.yaml is built so that the pose decides: linear at the
nominal pose, load at its correction (a 3 deg pitch). References: `headplan solve --json`'s
level_choice for the same correction."""
import json
import math
import os

import numpy as np
import pytest

import headplan
from conftest import SRC, cli

FIXTURE = os.path.join(SRC, "tests", "scene", "auto_pose.yaml")


@pytest.fixture(scope="module")
def scene():
    return headplan.load_scene(FIXTURE)


def solve_choice(*args):
    rc, out, err = cli("solve", FIXTURE, *args, "--json", check=False)
    assert rc in (0, 1), err
    j = json.loads(out)
    return j["why"] if j["level"] == "load" else j["level_choice"]  # the load table says "why"


def test_default_is_the_scenes_correction(scene):
    p = headplan.Planner(scene)
    assert p.settings["auto_pose"] == pytest.approx([0, 0, 0, 3, 0, 0], abs=1e-12)
    assert p.level == "load"
    assert p.level_choice == solve_choice()
    assert "at the pose x 0 mm, y 0 mm, z 0 mm, pitch 3 deg, roll 0 deg, yaw 0 deg" in p.level_choice


def test_keyword_moves_the_pose(scene):
    p = headplan.Planner(scene, auto_pose=np.zeros(6))
    assert p.settings["auto_pose"] == [0.0] * 6
    assert p.level == "linear"
    assert p.level_choice == solve_choice("--correction", "0,0,0,0,0,0")
    assert p.level_choice.startswith("auto chose linear by model error at the nominal pose")
    # a list of ints is taken as a pose too
    assert headplan.Planner(scene, auto_pose=[0, 0, 0, 3, 0, 0]).level == "load"


@pytest.mark.parametrize("i", range(6))
def test_bad_auto_pose_refused(scene, i):
    name = ["x", "y", "z", "pitch", "roll", "yaw"][i]
    for bad, why in ((math.nan, "not finite"), (math.inf, "not finite"),
                     (2000.0 if i < 3 else 200.0, "out of range")):
        pose = [0.0] * 6
        pose[i] = bad
        with pytest.raises(headplan.Error,
                           match=rf"^auto_pose \(the correction auto measures at\) {name}: {why}"):
            headplan.Planner(scene, auto_pose=pose)


def test_auto_pose_shape_type_and_range(scene):
    with pytest.raises(headplan.Error, match=r"^auto_pose: expected 6 values"):
        headplan.Planner(scene, auto_pose=[0, 0, 0])
    with pytest.raises(TypeError, match="auto_pose"):
        headplan.Planner(scene, auto_pose=["a"] * 6)
    # inside hp_plan's range but outside the ellipsoid's identifiable range (below 90 deg)
    with pytest.raises(headplan.Error, match=r"auto_pose \(the correction auto measures at\) "
                       r"rotation: angle 100\.0 deg is outside the identifiable range"):
        headplan.Planner(scene, auto_pose=[0, 0, 0, 100, 0, 0])
