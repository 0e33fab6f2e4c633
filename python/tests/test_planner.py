"""Planner: plan and plan_many against `headplan solve --json`, bit for bit, and every kind of
bad input. The program prints 17 significant digits (jansson precision 17), which reads back
to the same double, so the comparisons below are == on the parsed floats."""
import json

import numpy as np
import pytest

import headplan
from conftest import DEFAULT, PATIENT_S, cli, scenario, patient_scene

KEYS = headplan.POSE_KEYS


def corrections():
    rng = np.random.default_rng(15)
    rows = [[1.0, 0.0, -0.5, 0.3, 0.0, -0.2], [0, 0, 0, 0, 0, 0], [-2, 1, 3, -1, 0.5, 2]]
    rows += np.round(rng.uniform(-4, 4, (4, 6)), 3).tolist()  # some out of reach: closest
    return rows


def solve_json(scene, c, *extra):
    rc, out, err = cli("solve", scene, "--correction", ",".join(repr(float(v)) for v in c),
                       "--json", *extra, check=False)
    assert rc in (0, 1), err
    return json.loads(out)


def assert_same(r, j, names):
    assert r["status"] == j["status"]
    assert r["iterations"] == j["iterations"]
    for i, k in enumerate(KEYS):
        assert r["desired"][i] == j["desired"][k]
        assert r["achieved"][i] == j["achieved"][k], (k, r["achieved"][i], j["achieved"][k])
    for b, jb in enumerate(j["bladders"]):
        assert jb["name"] == names[b]
        assert r["pressure_pa"][b] == jb["pressure_pa"]
        assert r["ri_mm"][b] == jb["ri_mm"]
        assert r["ro_mm"][b] == jb["ro_mm"]
        assert headplan.binding_names(int(r["binding"][b])) == jb["binding"]


@pytest.mark.parametrize("backend,level", [("realtime", None), ("realtime", "linear"),
                                           ("realtime", "plane"), ("nlopt-slsqp", None),
                                           ("ipopt", "linear")])
def test_plan_equals_cli_bit_for_bit(default_scene, backend, level, tmp_path):
    kw = {"backend": backend, "max_time_s": PATIENT_S}
    scene = patient_scene(DEFAULT, tmp_path)
    extra = ["--backend", backend]
    if level:
        kw["level"] = level
        extra += ["--level", level]
    p = headplan.Planner(default_scene, **kw)
    seen = set()
    cs = corrections()
    many = p.plan_many(np.array(cs))
    for i, c in enumerate(cs):
        r = p.plan(c)
        j = solve_json(scene, c, *extra)
        assert_same(r, j, p.bladder_names)
        seen.add(r["status"])
        # plan_many row i is plan(c), bit for bit (each from the nominal pose).
        for key in ("pressure_pa", "ri_mm", "ro_mm", "stretch", "binding", "achieved"):
            assert np.array_equal(many[key][i], r[key]), key
        assert many["status"][i] == r["status"]
    assert seen == {"reached", "closest"}, seen  # both paths were exercised


@pytest.mark.parametrize("name", ["saturation.yaml", "sphere_head.yaml", "large_rotation.yaml",
                                  "soft_material.yaml", "near_degenerate.yaml"])
def test_other_scenes_equal_cli(name, tmp_path):
    path = patient_scene(scenario(name), tmp_path)
    sc = headplan.load_scene(path)
    p = headplan.Planner(sc)
    c = sc.correction if sc.correction is not None else np.zeros(6)
    assert_same(p.plan(c), solve_json(path, c), p.bladder_names)


def test_result_fields_and_units(default_planner, default_scene):
    r = default_planner.plan(default_scene.correction)
    assert r["status"] == "reached" and r["status_code"] == 0
    assert r["pressure_pa"].shape == (8,) and r["pressure_pa"].dtype == np.float64
    assert r["binding"].dtype == np.uint32
    # stretch = ri / Ri with Ri = 27 mm for every bladder of the default scene
    assert np.allclose(r["stretch"], r["ri_mm"] / 27.0, rtol=1e-15, atol=0)
    assert np.array_equal(r["error"], r["achieved"] - r["desired"])
    assert r["pose_error"] <= 1e-6
    assert r["solve_time_us"] > 0
    assert default_planner.level == "surface" and default_planner.backend == "realtime"


def test_closest_sets_binding_flags(default_planner):
    r = default_planner.plan([0, 0, 30, 0, 0, 0])  # far beyond the reach of +z (8.2 mm)
    assert r["status"] == "closest"
    assert r["binding"].any()
    lo = np.array([b["pressure_min_pa"] for b in headplan.load_scene(DEFAULT).layout["bladders"]])
    assert np.all(r["pressure_pa"] >= lo)
    assert r["message"] != ""


def test_input_conversions(default_planner):
    x = np.random.default_rng(3).uniform(-1, 1, (20, 6))
    ref = default_planner.plan_many(x)
    # a strided (non-contiguous) view, Fortran order, float32->float64 of exact values, ints
    wide = np.zeros((20, 12))
    wide[:, ::2] = x
    view = wide[:, ::2]
    assert not view.flags["C_CONTIGUOUS"]
    for other in (view, np.asfortranarray(x), x.tolist()):
        got = default_planner.plan_many(other)
        assert np.array_equal(got["pressure_pa"], ref["pressure_pa"])
    ints = np.array([[1, 0, -1, 0, 0, 0]], dtype=np.int16)
    assert np.array_equal(default_planner.plan_many(ints)["pressure_pa"][0],
                          default_planner.plan([1.0, 0.0, -1.0, 0.0, 0.0, 0.0])["pressure_pa"])


@pytest.mark.parametrize("bad", [np.zeros((3, 5)), np.zeros(6), np.zeros((2, 3, 6)), [], 7.0])
def test_wrong_shapes_raise(default_planner, bad):
    with pytest.raises(headplan.Error, match=r"poses: expected shape \(N, 6\)"):
        default_planner.plan_many(bad)


@pytest.mark.parametrize("bad", [np.array([["a"] * 6]), np.zeros((1, 6), complex),
                                 np.zeros((1, 6), bool), np.array([[object()] * 6]),
                                 [[1, 2, 3, 4, 5, "x"]]])
def test_wrong_dtypes_raise(default_planner, bad):
    with pytest.raises(TypeError):
        default_planner.plan_many(bad)


def test_plan_wants_six_values(default_planner):
    with pytest.raises(headplan.Error, match="6 values"):
        default_planner.plan([1, 2, 3])
    with pytest.raises(TypeError):
        default_planner.plan("abcdef")


def test_nan_row_is_invalid_input_others_unaffected(default_planner):
    x = np.zeros((3, 6))
    x[1, 2] = np.nan
    x[2, 0] = np.inf
    r = default_planner.plan_many(x)
    assert r["status"].tolist() == ["reached", "invalid-input", "invalid-input"]
    # the safe output: the nominal pressures, inside every limit
    assert np.array_equal(r["pressure_pa"][1], r["pressure_pa"][0])
    assert np.all(np.isfinite(r["pressure_pa"]))


def test_empty_array(default_planner):
    r = default_planner.plan_many(np.zeros((0, 6)))
    assert r["pressure_pa"].shape == (0, 8) and r["status"].shape == (0,)


def test_settings_overrides_and_errors(default_scene):
    p = headplan.Planner(default_scene, backend="nlopt-slsqp", level="plane", tolerance=1e-7,
                         max_iter=50, max_time_s=0.5, weight_mm_per_deg=2, warm_start=0)
    s = p.settings
    assert (s["backend"], s["level"], s["tolerance"], s["max_iter"]) == ("nlopt-slsqp", "plane",
                                                                          1e-7, 50)
    assert p.level == "plane"
    with pytest.raises(headplan.Error, match="unknown backend 'fast'"):
        headplan.Planner(default_scene, backend="fast")
    with pytest.raises(headplan.Error, match="unknown level"):
        headplan.Planner(default_scene, level="exact")
    with pytest.raises(headplan.Error, match="tolerance"):
        headplan.Planner(default_scene, tolerance=-1)
    with pytest.raises(headplan.Error, match="finite"):
        headplan.Planner(default_scene, tolerance=float("nan"))
    with pytest.raises(headplan.Error, match="max_iter"):
        headplan.Planner(default_scene, max_iter=0)
    with pytest.raises(headplan.Error,
                       match=r"^level_tolerance_mm: must be finite and > 0 mm \(got -1\)$"):
        headplan.Planner(default_scene, level_tolerance_mm=-1)  # not "-0.001 m"
    with pytest.raises(headplan.Error, match="max_iter"):  # not an OverflowError
        headplan.Planner(default_scene, max_iter=2**70)
    with pytest.raises(TypeError, match="max_iter"):
        headplan.Planner(default_scene, max_iter=50.0)
    # NumPy scalars are numbers like Python's.
    s = headplan.Planner(default_scene, max_iter=np.int32(50), tolerance=np.float32(0.5)).settings
    assert s["max_iter"] == 50 and s["tolerance"] == 0.5
    # restarts (NLopt SLSQP's further starts): an int in 0..64, like max_iter a keyword.
    assert headplan.Planner(default_scene).settings["restarts"] == 7  # HP_DEFAULT_RESTARTS
    assert headplan.Planner(default_scene, restarts=np.int64(0)).settings["restarts"] == 0
    assert headplan.Planner(default_scene, restarts=64).settings["restarts"] == 64
    for bad in (-1, 65):
        with pytest.raises(headplan.Error,
                           match=rf"^restarts: must be an integer in 0\.\.64 \(got {bad}\)$"):
            headplan.Planner(default_scene, restarts=bad)
    with pytest.raises(headplan.Error, match=r"^restarts: \d+ is out of range"):  # no Overflow
        headplan.Planner(default_scene, restarts=2**70)
    for bad in (3.0, float("nan"), float("inf"), "3", [3]):
        with pytest.raises(TypeError, match="restarts"):
            headplan.Planner(default_scene, restarts=bad)
    with pytest.raises(TypeError, match="unknown keyword 'speed'"):
        headplan.Planner(default_scene, speed=3)



def test_overrides_say_what_the_cli_says(default_scene):
    """Keywords and --backend / --level are one library call (hp_scene_settings_override):
    the same refusal word for word, the keyword named in its own units (max_time_s, not the
    field max_time)."""
    with pytest.raises(headplan.Error) as e:
        headplan.Planner(default_scene, max_time_s=0)
    assert str(e.value) == "max_time_s: must be > 0 and at most 3600 s (got 0)"
    for key, value in (("backend", "fast"), ("level", "exact")):
        with pytest.raises(headplan.Error) as e:
            headplan.Planner(default_scene, **{key: value})
        rc, _, err = cli("batch", DEFAULT, scenario("traces/step.csv"), "--rows",
                         "deviation", "--format", "csv", "--" + key, value, check=False)
        assert rc == 64, err
        said = err.strip().removeprefix("headplan batch: --")
        assert str(e.value) == said, (str(e.value), said)
    with pytest.raises(TypeError):
        headplan.Planner("scenarios/default.yaml")


def test_unbuilt_planner_refuses():
    p = headplan.Planner.__new__(headplan.Planner)
    with pytest.raises(RuntimeError):
        p.plan([0] * 6)
    with pytest.raises(RuntimeError):
        p.level


@pytest.mark.parametrize("name,backend,c", [
    ("saturation.yaml", None, None),  # ipopt: its last radii hold no pose
    ("default.yaml", "nlopt-slsqp", [4, 3, 2, 3, 2, 1]),  # the budget's last feasible iterate
    ("default.yaml", "realtime", [4, 3, 2, 3, 2, 1]),
])
def test_iteration_limit_message_is_the_clis(tmp_path, name, backend, c):
    """A plan stopped by its iteration budget carries the text `headplan solve` prints for
    it (one text, the planner's): before, Python said 'iteration-limit: binding none' where
    the command line named the backend and the budget."""
    text = open(scenario(name)).read()
    path = tmp_path / name
    path.write_text(text.replace(text[text.index("max_iter: "):].split(",")[0], "max_iter: 1"))
    sc = headplan.load_scene(str(path))
    c = list(sc.correction) if c is None else c
    r = headplan.Planner(sc, **({"backend": backend} if backend else {})).plan(c)
    assert r["status"] == "iteration-limit"
    args = ["solve", str(path), "--correction", ",".join(repr(float(v)) for v in c)]
    rc, _, err = cli(*(args + (["--backend", backend] if backend else [])), check=False)
    assert rc == 70
    assert err == f"headplan solve: {path}: {r['message']} (no answer printed)\n"
    assert r["message"].startswith("iteration-limit: the ")
    assert "backend did not converge within solver.max_iter = 1 iterations" in r["message"]


def test_scene_restarts_reach_the_planner(tmp_path):
    """solver.restarts in a scene file is the Planner's setting; a bad value is refused with
    the file, line and column, as the command line refuses it."""
    text = open(scenario("default.yaml")).read()
    path = tmp_path / "restarts.yaml"
    path.write_text(text.replace("solver: {", "solver: {restarts: 2, ", 1))
    assert headplan.Planner(headplan.load_scene(str(path))).settings["restarts"] == 2
    path.write_text(text.replace("solver: {", "solver: {restarts: 65, ", 1))
    with pytest.raises(headplan.Error, match=r"restarts.yaml:\d+:\d+: solver.restarts: 65 is "
                       r"out of range \[0, 64\]"):
        headplan.load_scene(str(path))


def test_level_choice_is_solves_text(default_scene):
    # The default scene asks for auto: the planner says what auto chose and why, in the words
    # `headplan solve` prints ("level choice: ...") and batch writes (level_choice).
    rc, out, err = cli("solve", DEFAULT, "--json", check=False)
    assert rc == 0, err
    want = json.loads(out)["level_choice"]
    assert want.startswith("auto chose surface: ")
    assert headplan.Planner(default_scene).level_choice == want
    # A level named (by the caller or the scene) has no choice to explain.
    assert headplan.Planner(default_scene, level="plane").level_choice is None
    assert headplan.Planner(headplan.load_scene(scenario("saturation.yaml"))).level_choice is None
    # A tolerance of 1 mm lies between plane's bound and linear's (analyze's error bounds):
    # auto chooses plane and names linear's bound, as analyze computes it.
    bounds = json.loads(cli("analyze", DEFAULT, "--json")[1])["error_bounds"]
    assert bounds["plane_mm"] < 1.0 < bounds["linear_mm"]
    p = headplan.Planner(default_scene, level="auto", level_tolerance_mm=1.0)
    assert p.level == "plane"
    assert p.level_choice.startswith("auto chose plane: the error bound of linear (%.3g mm) "
                                     "exceeds model.tolerance_mm 1 " % bounds["linear_mm"])
