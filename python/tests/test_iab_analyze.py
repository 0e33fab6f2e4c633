"""ik / fk vectorised, and analyze, against the command line bit for bit."""
import numpy as np
import pytest

import headplan
from conftest import DEFAULT, cli_json, scenario

B = dict(Ri_mm=27.0, Ro_mm=30.0, c1_pa=1.1e4, c2_pa=2.2e4)
CLI_B = ["--Ri", "27", "--Ro", "30", "--c1", "11000", "--c2", "22000"]


def test_ik_equals_cli_and_keeps_shape():
    ri = np.array([[20.0, 25.0, 27.0], [28.5, 31.0, 33.3]])
    P = headplan.ik(ri, **B)
    assert P.shape == ri.shape and P.dtype == np.float64
    for v, p in zip(ri.ravel(), P.ravel()):
        assert p == cli_json("ik", *CLI_B, "--ri", repr(v))["pressure_pa"]
    assert headplan.ik(27, **B) == 0.0  # P = 0 exactly at ri = Ri (a 0-d array)


def test_fk_equals_cli_and_inverts_ik():
    P = np.array([-3000.0, -10.0, 0.0, 500.0, 1000.0])
    ri = headplan.fk(P, **B)
    for v, r in zip(P, ri):
        assert r == cli_json("fk", *CLI_B, "--pressure", repr(v))["ri_mm"]
    # round trip: the closed form of the pressure at the radius found (relative 1e-12:
    # fk's Newton tolerance and the slope dP/dri of about 1e3 Pa/mm)
    assert np.allclose(headplan.ik(ri, **B), P, rtol=1e-12, atol=1e-9)


def test_strided_int_and_list_inputs():
    ri = np.linspace(20, 34, 40)
    ref = headplan.ik(ri, **B)
    assert np.array_equal(headplan.ik(ri[::2], **B), ref[::2])
    assert np.array_equal(headplan.ik(list(ri), **B), ref)
    assert np.array_equal(headplan.ik(np.array([27, 28]), **B), headplan.ik([27.0, 28.0], **B))


def test_ik_fk_bad_input():
    with pytest.raises(headplan.Error, match=r"ri_mm: element 1 is NaN"):
        headplan.ik([25, np.nan], **B)
    with pytest.raises(headplan.Error, match=r"ri_mm\[0\] = -1"):
        headplan.ik([-1.0], **B)
    with pytest.raises(TypeError):
        headplan.ik(["a"], **B)
    with pytest.raises(TypeError):
        headplan.ik([25.0], Ri_mm=27, Ro_mm=30, c1_pa=1e4)  # c2_pa missing
    # In the caller's names and mm, as headplan ik says it (the library's check says m).
    with pytest.raises(headplan.Error, match=r"^ik: Ro_mm: must be greater than Ri_mm "
                                             r"\(got Ro_mm 20, Ri_mm 27\)$"):
        headplan.ik([25.0], Ri_mm=27, Ro_mm=20, c1_pa=1e4, c2_pa=0)
    with pytest.raises(headplan.Error, match=r"^fk: Ri_mm: must be > 0 mm \(got 0\)$"):
        headplan.fk([25.0], Ri_mm=0, Ro_mm=20, c1_pa=1e4, c2_pa=0)
    with pytest.raises(headplan.Error, match="Ri_mm: must be finite"):
        headplan.ik([25.0], Ri_mm=float("inf"), Ro_mm=20, c1_pa=1e4, c2_pa=0)
    # a neo-Hookean bladder has an inflation limit point: no stable radius above it
    neo = dict(Ri_mm=27.0, Ro_mm=30.0, c1_pa=1.1e4, c2_pa=0.0)
    with pytest.raises(headplan.Error, match=r"pressure_pa\[1\] = 1000000 Pa: no stable"):
        headplan.fk([0.0, 1e6], **neo)


def test_bladder_scene_feeds_ik():
    sc = headplan.load_scene(scenario("paper_expansion.yaml"))
    assert np.isfinite(headplan.ik([sc.bladder["Ri_mm"] * 1.1], **sc.bladder)).all()


def test_analyze_equals_cli(default_scene):
    a = headplan.analyze(default_scene)
    j = cli_json("analyze", DEFAULT)
    assert a["level"] == j["level"] == "surface"
    # The scene asks for auto, which resolves to surface: the request is reported as asked.
    assert a["level_requested"] == j["level_requested"] == "auto"
    assert a["singular_values"].tolist() == j["singular_values"]
    assert a["rank"] == j["rank"] == 6 and a["condition"] == j["condition"]
    assert a["weakest_direction"]["vector"].tolist() == j["weakest_direction"]["vector"]
    assert a["weakest_direction"]["phrase"] == j["weakest_direction"]["phrase"]
    for i, k in enumerate(headplan.POSE_KEYS):
        assert a["reach"][i].tolist() == j["reach"][k]
    for k in ("linear_mm", "plane_mm", "auto_level", "translation_mm", "rotation_deg"):
        assert a["error_bounds"][k] == j["error_bounds"][k], k
    lin = headplan.analyze(default_scene, level="linear")
    assert lin["level"] == "linear" and lin["level_requested"] == "linear"
    assert lin["reach"].tolist() == [v for k in headplan.POSE_KEYS
                                     for v in [cli_json("analyze", DEFAULT, "--level",
                                                        "linear")["reach"][k]]]
    with pytest.raises(headplan.Error, match="unknown level"):
        headplan.analyze(default_scene, level="cubic")


def test_analyze_sphere_has_no_rotation():
    a = headplan.analyze(headplan.load_scene(scenario("sphere_head.yaml")))
    assert a["rotation_commandable"] is False and a["rank"] == 3
    assert np.all(np.isnan(a["reach"][3:])) and np.all(np.isfinite(a["reach"][:3]))


def test_binding_names():
    assert headplan.binding_names(0) == []
    assert headplan.binding_names(1 | 8 | 64) == ["pressure_min", "stretch_max", "limit_point"]
    with pytest.raises(TypeError):
        headplan.binding_names("x")
    assert headplan.binding_names(2047) == ["pressure_min", "pressure_max", "stretch_min",
                                            "stretch_max", "rate_down", "rate_up",
                                            "limit_point", "stress_max", "indent_max",
                                            "cannot_pull", "stability"]
    assert headplan.binding_names(1024) == ["stability"]
    # A bit no flag defines, or a value out of any C integer's range, is refused, not read
    # as "binds nothing"; so is a negative value.
    for bad in (2048, 2**31, 2**40, 2**64, -1, -2**70, np.int64(-3)):
        with pytest.raises(ValueError, match=r"^binding_names: flags must be in 0\.\.2047"):
            headplan.binding_names(bad)
    # An element of a result's binding array (a NumPy uint32), as the docs say to pass.
    sat = headplan.load_scene(scenario("saturation.yaml"))
    r = headplan.Planner(sat, backend="realtime").plan(sat.correction)
    k = int(np.argmax(r["binding"]))
    assert headplan.binding_names(r["binding"][k]) == ["pressure_min"]
    assert headplan.binding_names(np.int64(2)) == ["pressure_max"]
