#!/usr/bin/python3
"""Regenerate every table of fem/tables/ with CalculiX (the one command; docs/accuracy.md).

    fem/make_tables.py [--headplan build/headplan] [--only verify,contact,sweep,shape,thick,tilt]
                       [--quick]
                       [--workers N] [--cache FILE] [--cases TAG,...] [--budget SECONDS]

verify   free inflation against the closed-form IK (`headplan ik`): three meshes, the
         observed rate of convergence, the compressibility study; the thin-wall limit
contact  one contact case: penalty stiffness, mesh and D1 studies; the two supports
sweep    F/(P pi ro^2) against delta/ro over wall thickness/ro, P/C1, C2/C1, ro/head radius
shape    the base case's free outer surface against the sphere the levels assume
thick    the 5 mm wall over the sweep's indentations at bulk/shear 1e3
tilt     3-D: the plane's normal tilted from the bladder's axis (fem/hpfem3d.py)

Each CSV starts with '#' lines of provenance (engine version, mesh, command, date). Runs are
nice'd and single-threaded; the whole set takes about the time docs/accuracy.md states.
"""
import argparse
import datetime
import json
import math
import os
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import hpfem  # noqa: E402

TABLES = os.path.join(HERE, "tables")


def headplan_ik(exe, Ri, Ro, ri, C1, C2):
    """The project's closed-form IK (iab_ik through the CLI): pressure at inner radius ri."""
    out = subprocess.run([exe, "ik", "--Ri", repr(Ri * 1e3), "--Ro", repr(Ro * 1e3),
                          "--ri", repr(ri * 1e3), "--c1", repr(C1), "--c2", repr(C2), "--json"],
                         capture_output=True, text=True, check=True).stdout
    return json.loads(out)["pressure_pa"]


def write_csv(name, header, rows, notes):
    os.makedirs(TABLES, exist_ok=True)
    path = os.path.join(TABLES, name)
    with open(path, "w") as fh:
        fh.write("# engine: CalculiX ccx %s\n" % hpfem.ccx_version())
        fh.write("# command: fem/make_tables.py %s\n" % " ".join(sys.argv[1:]))
        fh.write("# date: %s\n" % datetime.datetime.now(datetime.timezone.utc)
                 .strftime("%Y-%m-%d %H:%M UTC"))
        for n in notes:
            fh.write("# %s\n" % n)
        fh.write(",".join(header) + "\n")
        for r in rows:
            fh.write(",".join(x if isinstance(x, str) else "%.7g" % x for x in r) + "\n")
    print("wrote", path, flush=True)


def inflate(case):
    """Inner radius at the equator and at the pole after free inflation."""
    res = hpfem.run(case)
    t, U = res[("displacements", "INNER")][-1]
    if abs(t - 1.0) > 1e-9:
        raise RuntimeError("inflation stopped at t = %g" % t)
    eq, pole = case.inner_nodes[0], case.inner_nodes[-1]
    return case.Ri + U[eq][0], case.Ri + U[pole][1]


MESHES = [(2, 10), (4, 20), (8, 40)]  # elements through the wall, along the quarter meridian


def verify(exe, quick):
    rows = []
    shells = [(0.027, 0.030, 1.1e4, 2.2e4, (1.05, 1.15, 1.3)),
              (0.025, 0.030, 1.1e4, 2.2e4, (1.05, 1.3)),
              (0.027, 0.030, 1.1e4, 0.0, (1.05, 1.15, 1.3))]
    # displacement control reaches the load scenes' stretch_max 1.6, where pressure control
    # stops at about 1.43 (hpfem.Case.stretch); 1.3 overlaps the pressure-controlled rows
    stretched = [(0.027, 0.030, 1.1e4, 2.2e4, (1.3, 1.5, 1.6))]
    if quick:
        shells, stretched = shells[:1], []

    def one(Ri, Ro, C1, C2, lam, nr, nt, br, control):
        """A row: pressure control inflates to P_IK(lam Ri) and reads ri; displacement
        control moves the inner surface to lam Ri and reads the pressure."""
        P = headplan_ik(exe, Ri, Ro, lam * Ri, C1, C2)
        if control == "pressure":
            c = hpfem.Case(Ri=Ri, Ro=Ro, C1=C1, C2=C2, P=P, nr=nr, nt=nt, grade=1.0,
                           bulk_ratio=br)
            ri, rp = inflate(c)
            Pf, e = P, headplan_ik(exe, Ri, Ro, ri, C1, C2) / P - 1.0
        else:
            c = hpfem.Case(Ri=Ri, Ro=Ro, C1=C1, C2=C2, nr=nr, nt=nt, grade=1.0,
                           bulk_ratio=br, stretch=lam)
            Pf = hpfem.cavity_pressure(c, hpfem.run(c))
            ri = rp = lam * Ri
            e = P / Pf - 1.0
        return [Ri * 1e3, Ro * 1e3, C1, C2, Pf, lam, "%dx%d" % (nr, nt), br, ri * 1e3,
                rp * 1e3, e, (ri - lam * Ri) / (lam * Ri - Ri), control]

    for control, group in (("pressure", shells), ("displacement", stretched)):
        for Ri, Ro, C1, C2, lams in group:
            for lam in lams:
                rs = [one(Ri, Ro, C1, C2, lam, nr, nt, 1e4, control) for nr, nt in MESHES]
                rows += rs
                # the quantity each control computes: ri (pressure) or P (displacement)
                q = [r[8] if control == "pressure" else r[4] for r in rs]
                d1, d2 = abs(q[0] - q[1]), abs(q[1] - q[2])
                rate = math.log(d1 / d2) / math.log(2.0) if d1 > 0 and d2 > 0 else float("nan")
                rows.append([Ri * 1e3, Ro * 1e3, C1, C2, rs[0][4], lam, "rate", 1e4, rate, 0, 0,
                             0, control])
                print("verify", control, Ri, Ro, C2, lam, rs[-1][10], "rate", rate, flush=True)
    # compressibility: the answer must not move with D1 (bulk/shear 1e3, 3e3, 1e4)
    for control, lam in (("pressure", 1.3), ("displacement", 1.6)):
        if quick and control == "displacement":
            continue
        for br in (1e3, 3e3, 1e4):
            rows.append(one(0.027, 0.030, 1.1e4, 2.2e4, lam, 8, 40, br, control))
    write_csv("inflation.csv",
              ["Ri_mm", "Ro_mm", "C1_pa", "C2_pa", "P_pa", "lambda_i_ik", "mesh", "bulk_over_shear",
               "ri_fem_mm", "ri_pole_fem_mm", "P_ik_at_ri_fem_over_P_minus_1",
               "ri_error_over_ri_minus_Ri", "control"],
              rows, ["free inflation of the centre-held shell (CAX8R, uniform mesh, MESHES "
                     "nr x nt); control 'pressure': P from `headplan ik` at lambda_i_ik*Ri, "
                     "ri_fem the inner radius it reaches; control 'displacement': the inner "
                     "surface moved to the sphere lambda_i_ik*Ri, P_pa the pressure read from "
                     "its reactions, P_ik_at_ri_fem_over_P_minus_1 = P_IK(lambda_i_ik*Ri)/P_pa "
                     "- 1; rows 'rate': the observed order of convergence of ri_fem (pressure) "
                     "or P (displacement), log2(|q1-q2|/|q2-q3|), in ri_fem_mm"])


def first_converged(tries, make, read, keys):
    """Run make(inc, gap) for each (inc, gap) of tries until read(case, results) succeeds:
    (case, inc, gap, read's dict); when none does, the last try's with NaN for keys and the
    engine's last error line."""
    for inc, gap in tries:
        c = make(inc, gap)
        try:
            return c, inc, gap, read(c, hpfem.run(c))
        except Exception as e:
            err = "no convergence: " + str(e).splitlines()[-1].strip()[-60:]
    return c, inc, gap, dict({k: float("nan") for k in keys}, error=err)


def contact_run(kw):
    """One contact run (a worker of the pool): the case's parameters -> a result row dict."""
    key = json.dumps(kw, sort_keys=True)
    if key in CACHE and "outer" in CACHE[key]:  # older entries lack the outer surface
        return CACHE[key]
    t0 = time.time()
    if DEADLINE is not None and t0 > DEADLINE:  # --budget: a run not started is a row saying so
        c = hpfem.Case(**{k: v for k, v in kw.items() if k != "tag"})
        r = {"force": float("nan"), "patch": float("nan"), "dvol": float("nan"),
             "error": "not run: over the --budget"}
        ri, ro = c.free_radius()
        r.update(kw, ro=ro, seconds=0.0)
        return r
    # CalculiX's contact iterations fail now and then where the bladder first touches; a
    # smaller first increment or another starting clearance (so that touch happens at
    # another point of the path) usually gets through. The end state does not depend on
    # either. A run that never converges is a row that says so.
    c, inc, gap, r = first_converged(
        ((0.02, 1.0), (0.01, 1.0), (0.02, 0.5), (0.02, 2.0), (0.05, 1.0)),
        lambda i, g: hpfem.Case(**{k: v for k, v in dict(kw, inc=i, gap=g).items()
                                   if k != "tag"}),
        hpfem.contact_result, ("force", "patch", "dvol"))
    kw = dict(kw, inc=inc, gap=gap)
    ri, ro = c.free_radius()
    r.update(kw)
    r.update(ro=ro, seconds=time.time() - t0)
    if "error" in r and "budget" in r["error"]:
        r["seconds"] = 0.0
    print("contact", kw.get("tag", ""), kw["delta"], r["force"] / (c.P * math.pi * ro * ro),
          "%.0fs" % r["seconds"], flush=True)
    if CACHE_FILE and "error" not in r:
        with open(CACHE_FILE, "a") as fh:
            fh.write(json.dumps({"key": key, "result": r}) + "\n")
    return r


# --cache FILE: converged runs are appended there and reused by a later run with the same
# parameters (an interrupted regeneration resumes instead of starting over).
CACHE_FILE, CACHE = None, {}
# --budget SECONDS: the wall time after which no new run starts (set before the pool forks)
DEADLINE = None


def load_cache(path):
    global CACHE_FILE
    CACHE_FILE = path
    if path and os.path.exists(path):
        with open(path) as fh:
            for line in fh:
                e = json.loads(line)
                CACHE[e["key"]] = e["result"]


def pool(jobs, workers, done, indexed=None):
    """Run the jobs on `workers` processes (indexed: the worker, contact_run's by default);
    done(results so far, in job order) is called after each, so an interrupted run keeps
    what it finished."""
    import multiprocessing
    out = [None] * len(jobs)
    with multiprocessing.Pool(workers) as p:
        for i, r in p.imap_unordered(indexed or _indexed, list(enumerate(jobs))):
            out[i] = r
            done([x for x in out if x is not None])
    return out


def _indexed(ij):
    return ij[0], contact_run(ij[1])


BASE = dict(Ri=0.027, Ro=0.030, C1=1.1e4, C2=2.2e4, P=5e3, nr=4, nt=40, grade=4.0,
            bulk_ratio=1e4, indenter="plane", support="centre", penalty=100.0, inc=0.05)
DELTAS = (0.02, 0.05, 0.1, 0.18, 0.26)
MEMBRANE_DELTAS = (0.0238, 0.0601, 0.1048, 0.1547, 0.2082, 0.2638)

CONTACT_HEADER = ["tag", "Ri_mm", "Ro_mm", "C1_pa", "C2_pa", "P_pa", "indenter", "support",
                  "mesh", "penalty", "bulk_over_shear", "ro_mm", "delta_over_ro",
                  "thickness_over_ro", "P_over_C1", "C2_over_C1", "ro_over_head_radius",
                  "F_over_P_pi_ro2", "cap_law", "patch_over_ro", "volume_change", "seconds",
                  "note"]


def contact_rows(results):
    rows = []
    for r in results:
        ro, d = r["ro"], r["delta"]
        Rh = r["indenter"]
        curv = 0.0 if Rh == "plane" else ro / float(Rh)
        rows.append([r.get("tag", ""), r["Ri"] * 1e3, r["Ro"] * 1e3, r["C1"], r["C2"], r["P"],
                     "plane" if Rh == "plane" else "sphere_%gmm" % (float(Rh) * 1e3),
                     r["support"], "%dx%d" % (r["nr"], r["nt"]), r["penalty"],
                     r["bulk_ratio"], ro * 1e3, d, (r["Ro"] - r["Ri"]) / ro, r["P"] / r["C1"],
                     r["C2"] / r["C1"], curv, r["force"] / (r["P"] * math.pi * ro * ro),
                     2 * d - d * d, r["patch"] / ro, r["dvol"], r["seconds"],
                     r.get("error", "")])
    return rows


def contact(exe, quick, workers):
    # cheapest and most telling first: an interrupted run keeps what it finished
    Ri, Ro = 0.0294, 0.030  # thin-wall limit: the membrane check's shell, wall 2 % of Ro
    P = headplan_ik(exe, Ri, Ro, 1.1 * Ri, BASE["C1"], BASE["C2"])
    thin = dict(BASE, Ri=Ri, Ro=Ro, P=P, nt=80, tag="thin")
    jobs = [dict(BASE, delta=0.1, penalty=300.0, tag="penalty"),
            dict(BASE, delta=0.1, nr=4, nt=20, tag="mesh"),
            dict(BASE, delta=0.1, support="panel", tag="panel"),
            dict(thin, delta=MEMBRANE_DELTAS[2]),
            dict(BASE, delta=0.1, bulk_ratio=1e3, tag="bulk"),
            dict(BASE, delta=0.26, support="panel", tag="panel"),
            dict(thin, delta=MEMBRANE_DELTAS[5]),
            dict(BASE, delta=0.1, penalty=30.0, tag="penalty"),
            dict(BASE, delta=0.02, support="panel", tag="panel"),
            dict(thin, delta=MEMBRANE_DELTAS[0]),
            dict(BASE, delta=0.1, nr=8, nt=80, tag="mesh")]
    jobs += [dict(BASE, delta=d, support="panel", tag="panel") for d in (0.05, 0.18)]
    jobs += [dict(thin, delta=d) for d in MEMBRANE_DELTAS[1:5] if d != MEMBRANE_DELTAS[2]]
    if quick:
        jobs = jobs[:1]
    pool(jobs, workers, lambda res: write_csv("contact_checks.csv", CONTACT_HEADER,
                                              contact_rows(res), CHECK_NOTES))


CHECK_NOTES = ["studies on one contact case (plane, centre held, delta/ro = 0.1): penalty "
               "(contact pressure per overclosure = penalty*(C1+C2)/wall), mesh (nr x nt, "
               "graded 4:1 toward the pole), bulk/shear; the panel support over the sweep's "
               "indentations; the thin-wall limit (wall 2 % of Ro, stretch 1.1) at the "
               "membrane check's indentations", "the sweep's base case is penalty 100, mesh "
               "4x40, bulk/shear 1e4 (rows with an empty note converged)"]


# The scenes' pressures on the same 3 mm shell: wall/ro and P/C1 move together, as they do
# for a real bladder. P0k5 is below the sweep's smallest pressure; P6k (stretch 1.33) is
# above the default stretch_max 1.3. P6k at delta/ro 0.02 and 0.05 did not converge (at
# first touch, increment size smaller than minimum, after 120 s and 158 s): those rows are
# carried, the case runs its other indentations. Pst16, the pressure of the load scenes' stretch_max 1.6
# (7.99 kPa, from the closed-form IK), does not converge in CalculiX 2.20: free inflation
# alone stops at about 0.81 of it (stretch 1.43, "too many cutbacks", on meshes 2x40 and
# 4x40, grade 1 and 4, increments 0.01 to 0.05, bulk/shear 1e3 and 1e4), so it is run at
# one indentation only, a row that says so.
P_STRETCH_16 = hpfem.ik(BASE["Ri"], BASE["Ro"], 1.6 * BASE["Ri"], BASE["C1"], BASE["C2"])[0]
SWEEP_CASES = [("base", {}), ("P2k", dict(P=2e3)), ("P1k", dict(P=1e3)),
               ("P1k_C2_0", dict(P=1e3, C2=0.0)), ("wall5", dict(Ri=0.025)),
               ("head90", dict(indenter=0.090)), ("head52", dict(indenter=0.052)),
               ("P6k", dict(P=6e3, deltas=(0.1, 0.18, 0.26))), ("P0k5", dict(P=500.0)),
               ("Pst16", dict(P=P_STRETCH_16, deltas=(0.1,)))]


def carried_rows(runs):
    """The rows of the existing sweep.csv that are not rerun (--cases; runs: the (tag,
    delta/ro) pairs run now), verbatim, and that table's provenance lines, so that a partial
    regeneration keeps both."""
    path = os.path.join(TABLES, "sweep.csv")
    if not os.path.exists(path):
        return [], []
    with open(path) as fh:
        lines = fh.read().splitlines()
    prov = [l[2:] for l in lines if l.startswith(("# engine", "# command", "# date"))]
    older = [l[2:] for l in lines if l.startswith("# rows of ")]
    body = [l.split(",") for l in lines if not l.startswith("#")][1:]
    return [r for r in body if (r[0], float(r[12])) not in runs], [" | ".join(prov)] + older


def sweep(exe, quick, workers, only_cases):
    cases = [c for c in SWEEP_CASES if not only_cases or c[0] in only_cases]
    jobs = [dict(BASE, delta=d, tag=t, **{k: v for k, v in kw.items() if k != "deltas"})
            for t, kw in cases for d in kw.get("deltas", DELTAS)]
    if quick:
        jobs = jobs[:1]
    kept, prov = (carried_rows({(j["tag"], j["delta"]) for j in jobs}) if only_cases
                   else ([], []))
    notes = SWEEP_NOTES + (["rows of %s carried from the table this command rewrote: %s" % (
        ", ".join(sorted({r[0] for r in kept})), prov[0])] + prov[1:] if kept else [])
    pool(jobs, workers, lambda res: write_csv("sweep.csv", CONTACT_HEADER,
                                              kept + contact_rows(res), notes))


SWEEP_NOTES = ["F/(P pi ro^2) of one bladder, centre held, pressure held, pressed by a rigid "
               "frictionless plane or sphere (the head's radius of curvature) along its "
               "axis; one group varied at a time from the base case (wall 3 mm of Ro 30 mm, "
               "C2/C1 = 2, P = 5 kPa, plane); cap_law = 2 d - d^2 is the cap law's "
               "F/(P pi ro^2)"]


SHAPE_NOTES = ["the free outer surface of the base case (centre held, plane, wall 3 mm of Ro "
               "30 mm, C2/C1 = 2, P = 5 kPa, mesh 4x40) against the sphere of radius ro the "
               "levels assume: bulge = |x|/ro - 1 of an outer-surface node about the held "
               "centre; bulge_max (bulge_min) the largest (most negative) on the free surface, "
               "at elevation bulge_max_deg (bulge_min_deg) above the equator; bulge_A at elevation A degrees (interpolated between nodes; empty "
               "inside the patch); edge_deg the patch edge's elevation; F and patch as in "
               "sweep.csv (the same runs)"]
SHAPE_HEADER = (["tag", "delta_over_ro", "ro_mm", "F_over_P_pi_ro2", "patch_over_ro",
                 "edge_deg", "bulge_max", "bulge_max_deg", "bulge_max_mm", "bulge_min",
                 "bulge_min_deg", "bulge_min_mm"] +
                ["bulge_%d" % a for a in hpfem.SHAPE_ANGLES] + ["seconds", "note"])


def shape_rows(results):
    rows = []
    for r in sorted(results, key=lambda r: r["delta"]):
        ro, nan = r["ro"], float("nan")
        g = lambda k: r.get(k, nan)
        rows.append([r["tag"], r["delta"], ro * 1e3, r["force"] / (r["P"] * math.pi * ro * ro),
                     r["patch"] / ro, g("edge_deg"), g("bulge_max"), g("bulge_max_deg"),
                     g("bulge_max") * ro * 1e3, g("bulge_min"), g("bulge_min_deg"),
                     g("bulge_min") * ro * 1e3] +
                    ["" if math.isnan(g("bulge_%d" % a)) else g("bulge_%d" % a)
                     for a in hpfem.SHAPE_ANGLES] + [r["seconds"], r.get("error", "")])
    return rows


def shape(quick, workers):
    jobs = [dict(BASE, delta=d, tag="base") for d in DELTAS]
    if quick:
        jobs = jobs[:1]
    pool(jobs, workers, lambda res: write_csv("shape.csv", SHAPE_HEADER, shape_rows(res),
                                              SHAPE_NOTES))


# 3-D: the plane's normal tilted from the bladder's axis (fem/hpfem3d.py), the base case's
# material, pressure and support; tilt 0 verifies the 3-D model against the axisymmetric one
# bulk/shear 1e3, not the sweep's 1e4: at 1e4 Newton converged only linearly once the patch
# spread (too many cutbacks at t = 0.92 and 0.95 of the step); 1e3 moves the axisymmetric
# force by 4.5e-3 (contact_checks.csv, tag bulk), and that row is the 3-D run's reference
TILT_BASE = dict(Ri=BASE["Ri"], Ro=BASE["Ro"], C1=BASE["C1"], C2=BASE["C2"], P=BASE["P"],
                 n=16, nv=4, nr=2, grade=0.5, bulk_ratio=1e3,
                 penalty=BASE["penalty"], support="centre", plate_cells=1)
# in the order run (an interrupted regeneration keeps the first): centre held, the 3-D model
# against the axisymmetric one (its increments are the reference of the tilted runs), the
# plane tilted 20 and 10 degrees (these stop at about 0.9 of the path, docs/accuracy.md
# section 5.4); then held by the panel, which reaches the law's largest indentation at
# every tilt: along the axis and tilted 10 and 20 degrees at delta/ro 0.1 and 0.26
TILT_RUNS = ([dict(tilt=0.0, delta=0.1), dict(tilt=20.0, delta=0.1), dict(tilt=10.0, delta=0.1)] +
             [dict(support="panel", tilt=t, delta=d) for d in (0.26, 0.1) for t in (20.0, 0.0, 10.0)])
TILT_HEADER = ["support", "tilt_deg", "delta_over_ro", "mesh", "bulk_over_shear", "ro_mm",
               "t_reached", "delta_over_ro_at_t", "F_over_P_pi_ro2",
               "F_axisymmetric", "F_over_F_axisymmetric", "F_over_F_3d_tilt_0", "F_law",
               "F_over_F_law", "angle_deg", "offset_over_ro", "seconds", "note"]
TILT_NOTES = ["the base case (wall 3 mm of Ro 30 mm, C2/C1 = 2, P = 5 kPa, centre held: "
              "equator u_z = 0 and its mean u_x = 0) pressed by a rigid frictionless plane "
              "whose normal is tilted tilt_deg from the bladder's axis, in 3-D (half model, "
              "cubed-sphere C3D20R mesh: mesh = cells across the top face x up a side x "
              "through the wall, grade = the top face's spacing at the pole over uniform; "
              "fem/hpfem3d.py); support panel: the equator rim bonded (u = 0); "
              "F_axisymmetric the axisymmetric base case with the same support at the same "
              "delta/ro, centre held at the same bulk/shear (sweep.csv, contact_checks.csv "
              "tag bulk), panel at bulk/shear 1e4 (contact_checks.csv tag panel: the only "
              "one; centre held, 1e3 moves the force by 4.5e-3); F_over_F_3d_tilt_0 "
              "against the 3-D run along the axis with the same support; F_law the "
              "fitted law of kinematics/contact_law_fit.h; angle_deg between the force and "
              "the plane's normal; offset_over_ro the centre of pressure's distance from the "
              "foot of the normal through the centre, along the plane toward the tilt; "
              "t_reached the step's time of the state reported (pressure t P, the plane at "
              "t of its travel; delta_over_ro_at_t its indentation over the free radius "
              "at t P): a run that stopped before 1 reports its last converged "
              "state, compared with the run along the axis at the same t (its force "
              "interpolated linearly between increments) and with nothing else"]


def tilt_run(kw):
    """One 3-D run (a worker of the pool) -> a result row dict; a run that stops keeps the
    state it reached (hpfem3d.result's t)."""
    import hpfem3d
    key = json.dumps(dict(kw, model="3d"), sort_keys=True)
    if key in CACHE:
        return CACHE[key]
    t0 = time.time()
    c = hpfem3d.Case3D(**kw)
    try:
        r = hpfem3d.result(c, hpfem.run(c, partial=True))
    except Exception as e:
        r = {"force": float("nan"), "angle_deg": float("nan"), "offset": float("nan"),
             "t": float("nan"), "series": [], "error": str(e).splitlines()[-1][-80:]}
    ri, ro = c.free_radius()
    r.update(kw, ro=ro, seconds=time.time() - t0)
    print("tilt", kw["tilt"], kw["delta"], "t", r["t"], r["force"] / (c.P * math.pi * ro * ro),
          "%.0fs" % r["seconds"], flush=True)
    if CACHE_FILE:
        with open(CACHE_FILE, "a") as fh:
            fh.write(json.dumps({"key": key, "result": r}) + "\n")
    return r


def _at(series, t):
    """|F| of a run's series at time t, linear between its increments (NaN outside)."""
    for (t1, f1), (t2, f2) in zip(series, series[1:]):
        if t1 <= t <= t2 and t2 > t1:
            return f1 + (f2 - f1) * (t - t1) / (t2 - t1)
    return series[-1][1] if series and abs(series[-1][0] - t) < 1e-12 else float("nan")


TILT_KEYS = set(TILT_BASE) | {"tilt", "delta"}


def tilt_rows(results):
    import fit_law
    import hpfem3d
    law = fit_law.committed_law()
    # the axisymmetric base case with the same support at the same delta/ro: centre held at
    # the same bulk/shear (the sweep's rows, and the compressibility study's: contact_checks
    # tag bulk); held by the panel at 1e4, the only one there is (contact_checks tag panel)
    axi = {(r["support"], float(r["delta_over_ro"]), float(r["bulk_over_shear"])):
           float(r["F_over_P_pi_ro2"])
           for r in table_rows("sweep.csv") + table_rows("contact_checks.csv")
           if r["tag"] in ("base", "bulk", "panel") and r["note"] == ""}
    axi_bulk = {"centre": None, "panel": 1e4}
    same = lambda r: (r["support"], r["delta"], r["bulk_ratio"], r["grade"], r["n"], r["nr"])
    aligned = {same(r): r["series"] for r in results if r["tilt"] == 0.0}
    rows = []
    nan = float("nan")
    for r in sorted(results, key=lambda r: (r["support"], r["delta"], r["tilt"])):
        ro, P, t = r["ro"], r["P"], r["t"]
        end = abs(t - 1.0) < 1e-9
        g = r["force"] / (P * math.pi * ro * ro)
        # the axisymmetric run and the law hold the end state only
        fl = (law(r["delta"], (r["Ro"] - r["Ri"]) / ro, P / r["C1"], r["C2"] / r["C1"], 0.0)
              if end else nan)
        fa = (axi.get((r["support"], r["delta"], axi_bulk[r["support"]] or r["bulk_ratio"]), nan)
              if end else nan)
        f0 = _at(aligned.get(same(r), []), t)
        dt = hpfem3d.Case3D(**{k: v for k, v in r.items() if k in TILT_KEYS}).delta_at(t)
        rows.append([r["support"], r["tilt"], r["delta"],
                     "%dx%dx%d grade %g" % (r["n"], r["nv"], r["nr"], r["grade"]),
                     r["bulk_ratio"], ro * 1e3, t, dt, g, fa, g / fa, r["force"] / f0, fl,
                     g / fl, r["angle_deg"], r["offset"] / ro, r["seconds"],
                     r.get("error", "")])
    return rows


def table_rows(name):
    import csv
    with open(os.path.join(TABLES, name)) as fh:
        return list(csv.DictReader(l for l in fh if not l.startswith("#")))


def _indexed_tilt(ij):
    return ij[0], tilt_run(ij[1])


THICK_NOTES = ["the thick wall (Ri 25 mm, Ro 30 mm, wall/ro 0.156 at 5 kPa; sweep case wall5) "
               "with bulk/shear 1e3: with the sweep's 1e4 only delta/ro 0.02 converged; on "
               "the 3 mm wall 1e3 moves the force by 4.5e-3 at delta/ro 0.1 "
               "(contact_checks.csv, tag bulk), and the 0.02 row here against sweep.csv's "
               "measures it for this wall; the other columns as in sweep.csv"]


def thick(quick, workers):
    jobs = [dict(BASE, Ri=0.025, bulk_ratio=1e3, delta=d, tag="wall5_bulk1e3") for d in DELTAS]
    if quick:
        jobs = jobs[:1]
    pool(jobs, workers, lambda res: write_csv("thick.csv", CONTACT_HEADER, contact_rows(res),
                                              THICK_NOTES))


def tilt_inflation(exe):
    """The 3-D model's free inflation at the base pressure against the closed form: a note
    line of tilt.csv (the 3-D mesh, material and pressure checked before any contact)."""
    import hpfem3d
    kw = dict(TILT_BASE, delta=None, inc=0.05)
    key = json.dumps(dict(kw, model="3d inflation"), sort_keys=True)
    if key in CACHE:
        rp, re = CACHE[key]
    else:
        c = hpfem3d.Case3D(**kw)
        rp, re = hpfem3d.inflation_radii(c, hpfem.run(c))
        if CACHE_FILE:
            with open(CACHE_FILE, "a") as fh:
                fh.write(json.dumps({"key": key, "result": [rp, re]}) + "\n")
    c = hpfem3d.Case3D(**kw)
    e = [headplan_ik(exe, c.Ri, c.Ro, r, c.C1, c.C2) / c.P - 1 for r in (rp, re)]
    return ("3-D free inflation at P = %g Pa (the same mesh, no plane): P_IK(ri)/P - 1 = "
            "%.2g with ri at the pole, %.2g at the equator" % (c.P, e[0], e[1]))


def tilt(exe, quick, workers):
    jobs = [dict(TILT_BASE, **kw) for kw in TILT_RUNS]
    notes = TILT_NOTES
    if quick:
        jobs = jobs[:1]
    else:
        notes = notes + [tilt_inflation(exe)]
    pool(jobs, workers, lambda res: write_csv("tilt.csv", TILT_HEADER, tilt_rows(res),
                                              notes), _indexed_tilt)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--headplan", default=os.path.join(HERE, "..", "build", "headplan"))
    ap.add_argument("--only", default="verify,contact,sweep,shape,thick,tilt")
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--cache", default=None)
    ap.add_argument("--cases", default="",
                    help="sweep cases to (re)run, comma-separated tags; the other rows of "
                         "the existing sweep.csv are kept")
    ap.add_argument("--budget", type=float, default=None,
                    help="seconds of engine time in total: no run starts after "
                         "BUDGET/WORKERS seconds of wall time")
    a = ap.parse_args()
    t0 = time.time()
    global DEADLINE
    if a.budget is not None:
        DEADLINE = t0 + a.budget / max(1, a.workers)
    load_cache(a.cache)
    parts = a.only.split(",")
    if "verify" in parts:
        verify(a.headplan, a.quick)
    if "contact" in parts:
        contact(a.headplan, a.quick, a.workers)
    if "sweep" in parts:
        sweep(a.headplan, a.quick, a.workers, set(filter(None, a.cases.split(","))))
        import fit_law
        fit_law.main()
    if "shape" in parts:
        shape(a.quick, a.workers)
    if "thick" in parts:
        thick(a.quick, a.workers)
    if "tilt" in parts:
        tilt(a.headplan, a.quick, a.workers)
    print("done in %.0f s" % (time.time() - t0))


if __name__ == "__main__":
    main()
