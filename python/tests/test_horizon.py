"""run_trace over a horizon (mode greedy / receding / offline) against `headplan horizon`:
the same rows, statuses and poses, bit for bit for the poses (both print the same doubles:
the CLI with 17 significant digits), the pressures to 1e-12 relative (the CLI prints kPa);
and the offline plan tracks no worse than the greedy one (it is the optimum of their common
problem)."""
import csv
import io  # noqa: F401

import numpy as np
import pytest

import headplan
from conftest import PATIENT_S, cli, patient_scene, scenario

KEYS = headplan.POSE_KEYS


@pytest.fixture(scope="module")
def step(tmp_path_factory):
    path = tmp_path_factory.mktemp("hz") / "step80.csv"
    with open(scenario("traces/step.csv")) as f:
        path.write_text("".join(f.readlines()[:81]))  # header + 80 rows (8 s)
    return str(path)


@pytest.fixture(scope="module")
def step_scene(tmp_path_factory):
    # The receding horizon stops each row's solve within four fifths of the scene's budget:
    # the runs compared below plan with PATIENT_S instead, so that no row ends "time-limit"
    # in one run and not in the other on a stalled machine.
    return patient_scene(scenario("horizon/step.yaml"), tmp_path_factory.mktemp("hz"))


def horizon_csv(scene, trace, mode):
    out_path = trace + "." + mode + ".csv"
    rc, out, err = cli("horizon", scene, trace, "--rows", "deviation", "--mode", mode,
                       "-o", out_path, check=False)
    assert rc in (0, 1), err
    body = "".join(l for l in open(out_path) if not l.startswith("#"))
    return [r for r in csv.DictReader(io.StringIO(body)) if r["plan"] == mode]


@pytest.mark.parametrize("mode", ["greedy", "receding", "offline"])
def test_horizon_equals_cli(step, step_scene, mode):
    sc = headplan.load_scene(step_scene)
    r = headplan.Planner(sc).run_trace(step, rows="deviation", mode=mode)
    rows = horizon_csv(step_scene, step, mode)
    assert len(rows) == len(r["status"]) == 80
    names = sc.bladder_names
    for i, row in enumerate(rows):
        assert r["status"][i] == row["status"], i
        for c, k in enumerate(KEYS):
            assert r["achieved"][i, c] == float(row["achieved_" + k]), (i, k)
            assert r["desired"][i, c] == float(row["desired_" + k]), (i, k)
        for b, n in enumerate(names):
            want = float(row[n + "_kpa"]) * 1e3
            assert abs(r["pressure_pa"][i, b] - want) <= 1e-12 * max(1.0, abs(want)), (i, n)


def test_offline_no_worse_than_greedy(step, step_scene):
    p = headplan.Planner(headplan.load_scene(step_scene))
    err = {}
    for mode in ("greedy", "offline"):
        r = p.run_trace(step, rows="deviation", mode=mode)
        d = r["achieved"] - r["desired"]
        err[mode] = float(np.sum(d * d))
    assert err["offline"] <= err["greedy"] * (1 + 1e-6), err


def test_horizon_arguments(step, default_planner, default_scene):
    with pytest.raises(headplan.Error, match="mode"):
        default_planner.run_trace(step, rows="deviation", mode="sideways")
    with pytest.raises(headplan.Error, match="only with mode"):
        default_planner.run_trace(step, rows="deviation", horizon=5)
    with pytest.raises(headplan.Error, match="prediction"):
        default_planner.run_trace(step, rows="deviation", mode="receding", prediction="psychic")
    with pytest.raises(headplan.Error, match="horizon"):
        default_planner.run_trace(step, rows="deviation", mode="receding", horizon=0)
    # Every value given reaches the validator, the ones an argument parser could take for
    # "not given" too (they were planned with the defaults), as `headplan horizon` refuses
    # them; None is "not given".
    for mode, kw, msg in [("receding", {"horizon": -1}, "horizon: must be in"),
                          ("offline", {"window": -1}, "window: must be"),
                          ("greedy", {"rate_kpa_per_s": float("nan")}, "rate_kpa_per_s"),
                          ("greedy", {"rate_kpa_per_s": float("inf")}, "rate_kpa_per_s"),
                          ("batch", {"horizon": -1}, "only with mode"),
                          ("greedy", {"rate_kpa_per_s": -1},
                           r"^rate_kpa_per_s: must be > 0 kPa/s \(got -1\)$"),
                          ("receding", {"horizon": 2**40}, "horizon: .* out of range")]:
        with pytest.raises(headplan.Error, match=msg):
            default_planner.run_trace(step, rows="deviation", mode=mode, **kw)
    with pytest.raises(TypeError, match="horizon"):
        default_planner.run_trace(step, rows="deviation", mode="receding", horizon=2.5)
    none = default_planner.run_trace(step, rows="deviation", mode="greedy", horizon=None,
                                     rate_kpa_per_s=None)
    assert np.array_equal(none["pressure_pa"],
                          default_planner.run_trace(step, rows="deviation",
                                                    mode="greedy")["pressure_pa"])
    # NumPy integers and floats are numbers like Python's (a sweep's values come from arrays).
    patient = headplan.Planner(default_scene, max_time_s=PATIENT_S)
    a = patient.run_trace(step, rows="deviation", mode="receding", horizon=np.int64(3),
                          rate_kpa_per_s=np.float32(20))
    b = patient.run_trace(step, rows="deviation", mode="receding", horizon=3,
                          rate_kpa_per_s=float(np.float32(20)))
    assert np.array_equal(a["pressure_pa"], b["pressure_pa"])


@pytest.mark.parametrize("mode", ["greedy", "receding", "offline"])
def test_horizon_refuses_a_row_plan_refuses(tmp_path, default_planner, mode):
    # A 100 deg pitch is outside the identifiable range: plan() and batch mode give it
    # invalid-input, headplan horizon refuses it (65). The horizon modes planned it (greedy
    # and receding as invalid-input, offline as closest).
    path = tmp_path / "inv.csv"
    path.write_text("# headplan-trace: rows=correction\n"
                    "t_s,x_mm,y_mm,z_mm,pitch_deg,roll_deg,yaw_deg\n"
                    "0,1,0,0,0,0,0\n1,0,0,0,100,0,0\n2,1,0,0,0,0,0\n")
    assert default_planner.plan([0, 0, 0, 100, 0, 0])["status"] == "invalid-input"
    assert list(default_planner.run_trace(str(path))["status"])[1] == "invalid-input"
    with pytest.raises(headplan.Error, match=r"^line 4: desired rotation: angle 100\.0 deg"):
        default_planner.run_trace(str(path), mode=mode)


def test_first_interval_as_cli(tmp_path, step_scene):
    # A trace sampled every 50 ms whose first row asks for a 2 mm shift at once: with a
    # per-second limit (2.5 kPa/s) row 0 may move what the start pressures held for one
    # interval allow, the trace's first interval (125 Pa), as headplan horizon plans it.
    # Python assumed 0.1 s (250 Pa) before row 0 and planned another trace.
    path = tmp_path / "fast.csv"
    path.write_text("# headplan-trace: rows=correction\n"
                    "t_s,x_mm,y_mm,z_mm,pitch_deg,roll_deg,yaw_deg\n" +
                    "".join(f"{0.05 * i:.2f},2,0,1,0,0,0\n" for i in range(24)))
    scene = step_scene
    sc = headplan.load_scene(scene)
    planner, names = headplan.Planner(sc), sc.bladder_names
    for mode in ("greedy", "receding", "offline"):
        out = str(tmp_path / (mode + ".csv"))
        rc, _, err = cli("horizon", scene, str(path), "--mode", mode, "--rate-kpa-per-s", "2.5",
                         "-o", out, check=False)
        assert rc == 0, err
        body = "".join(l for l in open(out) if not l.startswith("#"))
        rows = list(csv.DictReader(io.StringIO(body)))
        r = planner.run_trace(str(path), mode=mode, rate_kpa_per_s=2.5)
        assert len(rows) == len(r["status"]) == 24
        for i, row in enumerate(rows):
            assert r["status"][i] == row["status"], (mode, i)
            for c, k in enumerate(KEYS):
                assert r["achieved"][i, c] == float(row["achieved_" + k]), (mode, i, k)
            for b, n in enumerate(names):
                # the CLI prints pressure * 1e-3 with 17 digits: the same double, bit for bit
                assert r["pressure_pa"][i, b] * 1e-3 == float(row[n + "_kpa"]), (mode, i, n)


@pytest.mark.parametrize("mode,kw", [("greedy", {"horizon": 5}),
                                     ("greedy", {"prediction": "velocity"}),
                                     ("greedy", {"window": 20}),
                                     ("offline", {"horizon": 5}),
                                     ("offline", {"prediction": "hold"}),
                                     ("receding", {"window": 20}),
                                     ("receding", {"window": 20, "overlap": 5})])
def test_option_its_mode_does_not_read(step, default_planner, mode, kw):
    # As headplan horizon refuses --horizon/--prediction outside receding and --window/
    # --overlap outside offline, run_trace refuses them (they were ignored without a word).
    name = next(iter(kw))
    with pytest.raises(ValueError, match=rf"^{name}: only the .* mode"):
        default_planner.run_trace(step, rows="deviation", mode=mode, **kw)
