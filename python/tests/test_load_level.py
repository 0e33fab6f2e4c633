"""A scene `headplan solve` plans at the load level (hp_scene_plan_level): a Planner refuses
it in batch's words unless level= names a kinematic level, as batch refuses it unless
--level does; Scene.level says 'load' when the scene does. Before, Planner(load scene)
planned it kinematically without a word (-1664 Pa where solve gives ~6 kPa)."""
import re

import numpy as np
import pytest

import headplan
from conftest import cli, cli_json, scenario

SUPINE = scenario("load_supine.yaml")


def level_load_scene(tmp_path):
    text = open(SUPINE).read().replace("level: auto", "level: load")
    p = tmp_path / "supine_level_load.yaml"
    p.write_text(text)
    return str(p)


def reason(msg):
    """The '(why)' of 'the scene is planned at the load level (why), which only ...'."""
    m = re.search(r"planned at the load level \((.*)\), which only headplan solve plans", msg)
    assert m, msg
    return m.group(1)


@pytest.mark.parametrize("make", [lambda t: SUPINE, level_load_scene])
def test_planner_refuses_what_solve_plans_at_the_load_level(tmp_path, make):
    path = make(tmp_path)
    rc, _, err = cli("batch", path, "--format", "csv", check=False)
    assert rc == 65, err
    sc = headplan.load_scene(path)
    for kw in ({}, {"level": None}) + (({"level": "auto"},) if "auto" in open(path).read() else ()):
        with pytest.raises(headplan.Error) as e:
            headplan.Planner(sc, **kw)
        assert reason(str(e.value)) == reason(err)
        assert "level='surface'" in str(e.value)


def test_level_load_is_refused_as_batch_refuses_it():
    with pytest.raises(headplan.Error, match=r"^level: load is planned by headplan solve only"):
        headplan.Planner(headplan.load_scene(SUPINE), level="load")
    rc, _, err = cli("batch", SUPINE, "--level", "load", "--format", "csv", check=False)
    assert rc == 64 and "load is planned by headplan solve only" in err


def test_kinematic_level_plans_as_batch_and_solve_with_that_level():
    c = list(headplan.load_scene(SUPINE).correction)
    for level in ("surface", "plane", "linear"):
        r = headplan.Planner(headplan.load_scene(SUPINE), level=level).plan(c)
        j = cli_json("solve", SUPINE, "--level", level, "--correction", ",".join(map(str, c)))
        assert j["status"] == r["status"]
        np.testing.assert_array_equal(r["pressure_pa"],
                                      [b["pressure_pa"] for b in j["bladders"]])
    # and not the load level's pressures: solve without --level holds the weight
    load = cli_json("solve", SUPINE, "--correction", ",".join(map(str, c)))
    assert load["level"] == "load"
    assert abs(load["bladders"][0]["pressure_pa"] - r["pressure_pa"][0]) > 1000.0


def test_scene_level_says_load(tmp_path):
    assert headplan.load_scene(level_load_scene(tmp_path)).level == "load"
    assert headplan.load_scene(SUPINE).level == "auto"
    assert headplan.load_scene(scenario("default.yaml")).level != "load"
