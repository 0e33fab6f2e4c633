#!/usr/bin/python3
"""Fit the dimensionless contact law to fem/tables/sweep.csv and write its coefficients
(kinematics/contact_law_fit.h, included by kinematics/contact_law.c) and its error table
(fem/tables/law_error.csv). Run by fem/make_tables.py after the sweep; alone:

    fem/fit_law.py

The law (kinematics/contact_law.h):
    g = F/(P pi ro^2) = G(d) (s + bp (1 + bd d)/sqrt(pm^2 + pc^2)),  G(d) = d (a1 + a2 d + a3 d^2),
with d = delta/ro, pm = P/mu (mu = C1 + C2, the rubber's initial shear modulus),
s = 1 + bw (wall/ro - w0) + bk ro/Rh, w0 the base case's wall/ro. Fitted by least squares
on the relative error F_law/F_fem - 1 over every converged row. pc is fixed (PC below):
the tables do not identify it well (worst error 4.7 % at 0.002, 4.6 % at 0.004, 4.7 % at
0.006, 5.6 % at 0.008); with pc > 0 the wall's share of the force, bp mu P/sqrt(P^2 +
(pc mu)^2), vanishes with the pressure and is smooth and bounded for every P.
"""
import csv
import datetime
import os

import numpy as np
from scipy.optimize import least_squares

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)


MIN_ROWS = 3  # a case enters the fit and the domain with at least this many indentations


def read(path):
    """The converged rows of the cases that converged at MIN_ROWS indentations or more (a
    case measured at fewer says too little about the law's shape in delta/ro), and the
    converged rows of the other cases."""
    with open(path) as fh:
        lines = [l for l in fh if not l.startswith("#")]
    rows = [r for r in csv.DictReader(lines) if r["note"] == ""]
    count = {}
    for r in rows:
        count[r["tag"]] = count.get(r["tag"], 0) + 1
    return ([r for r in rows if count[r["tag"]] >= MIN_ROWS],
            [r for r in rows if count[r["tag"]] < MIN_ROWS])


def groups(rows):
    f = lambda k: np.array([float(r[k]) for r in rows])
    return (f("delta_over_ro"), f("thickness_over_ro"), f("P_over_C1"), f("C2_over_C1"),
            f("ro_over_head_radius"), f("F_over_P_pi_ro2"))


PC = 0.004  # pc: 0.004 mu = 132 Pa for the scenes' bladders, 1/4 of the smallest pressure run


def model(th, d, w, p, c, k, ref):
    a1, a2, a3, bw, bp, bk, bd = th
    w0 = ref[0]
    s = 1 + bw * (w - w0) + bk * k
    pm = p / (1 + c)  # P/mu = (P/C1)/(1 + C2/C1)
    return d * (a1 + a2 * d + a3 * d * d) * (s + bp * (1 + bd * d) / np.sqrt(pm * pm + PC * PC))


def committed_law():
    """The law kinematics/contact_law_fit.h holds, as g(d, w, p, c, k) = F/(P pi ro^2) with
    model()'s arguments (scalars): what the C code evaluates, for comparing new tables
    with it without refitting."""
    v = {}
    with open(os.path.join(ROOT, "kinematics", "contact_law_fit.h")) as fh:
        for line in fh:
            p = line.split()
            if len(p) == 3 and p[0] == "#define" and p[1].startswith("HP_CLAW_FIT_"):
                v[p[1][12:]] = float(p[2].strip("()"))
    if v["PC"] != PC:
        raise SystemExit("fit_law.py: contact_law_fit.h was fitted with another PC")
    th = [v[n] for n in ("A1", "A2", "A3", "BW", "BP", "BK", "BD")]
    return lambda d, w, p, c, k: float(model(th, d, w, p, c, k, (v["W0"],)))


def sane(th, dom):
    """The checks a planner relies on over the domain: the force is positive and rises with
    the indentation (G' > 0 and (G (1 + bd d))' > 0 on [0, DMAX], both terms positive) and
    with the pressure at a fixed radius. Returns the failures (empty when sane)."""
    a1, a2, a3, bw, bp, bk, bd = th
    bad = []
    dd = np.linspace(0, dom["DMAX"], 200)
    G1 = a1 + 2 * a2 * dd + 3 * a3 * dd * dd
    H1 = G1 * (1 + bd * dd) + bd * dd * (a1 + a2 * dd + a3 * dd * dd)
    if G1.min() <= 0 or H1.min() <= 0 or bp <= 0 or (1 + bd * dom["DMAX"]) <= 0:
        bad.append("not rising with the indentation on [0, DMAX]")
    for w in (dom["WMIN"], dom["WMAX"]):
        for k in (0.0, dom["KMAX"]):
            if not 1 + bw * (w - W0) + bk * k > 0:  # P s: the pressure's share rises with P
                bad.append("s <= 0 at wall/ro %g, ro/Rh %g" % (w, k))
    return bad


def main():
    rows, few = read(os.path.join(HERE, "tables", "sweep.csv"))
    d, w, p, c, k, g = groups(rows)
    base = [i for i, r in enumerate(rows) if r["tag"] == "base"]
    ref = (float(np.mean(w[base])),)
    global W0
    W0 = ref[0]
    fit = least_squares(lambda th: model(th, d, w, p, c, k, ref) / g - 1,
                        x0=[0.3, 1.0, 0.0, 0.0, 0.05, 0.0, 0.0])
    th = fit.x
    err = model(th, d, w, p, c, k, ref) / g - 1
    cap = (2 * d - d * d) / g - 1
    # the tables' box, widened by 1e-6 relative: the CSV prints 7 digits, so a state the
    # tables hold must not fall outside by their rounding
    lo, hi = 1 - 1e-6, 1 + 1e-6
    dom = dict(DMAX=float(d.max()) * hi, WMIN=float(w.min()) * lo, WMAX=float(w.max()) * hi,
               PMIN=float(p.min()) * lo, PMAX=float(p.max()) * hi, CMIN=float(c.min()) * lo,
               CMAX=float(c.max()) * hi, KMAX=float(k.max()) * hi)
    names = ["A1", "A2", "A3", "BW", "BP", "BK", "BD"]
    bad = sane(th, dom)
    if bad:
        raise SystemExit("fit_law.py: the fitted law is not sane over its domain: " + "; ".join(bad[:3]))
    date = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    with open(os.path.join(ROOT, "kinematics", "contact_law_fit.h"), "w") as fh:
        fh.write("/* Generated by fem/fit_law.py from fem/tables/sweep.csv (%d rows, %s); do not\n"
                 " * edit. The fitted contact law's coefficients (contact_law.h) and the domain of\n"
                 " * the tables it was fitted over. Worst relative error in force against the\n"
                 " * tables: %.1f %% (RMS %.1f %%); docs/accuracy.md. */\n"
                 % (len(rows), date, 100 * np.abs(err).max(), 100 * np.sqrt(np.mean(err ** 2))))
        fh.write("#ifndef HP_CONTACT_LAW_FIT_H\n#define HP_CONTACT_LAW_FIT_H\n\n")
        for n, v in zip(names, th):
            fh.write("#define HP_CLAW_FIT_%s (%.17g)\n" % (n, v))
        for n, v in (("PC", PC), ("W0", ref[0])):
            fh.write("#define HP_CLAW_FIT_%s (%.17g)\n" % (n, v))
        for n, v in dom.items():
            fh.write("#define HP_CLAW_FIT_%s (%.17g)\n" % (n, v))
        fh.write("\n#endif\n")
    with open(os.path.join(HERE, "tables", "law_error.csv"), "w") as fh:
        fh.write("# fem/fit_law.py, %s: the fitted law and the cap law against fem/tables/sweep.csv\n"
                 % date)
        fh.write("tag,delta_over_ro,thickness_over_ro,P_over_C1,C2_over_C1,ro_over_head_radius,"
                 "F_fem,F_law,law_error,cap_error\n")
        for r, gi, e, ce in zip(rows, g, err, cap):
            fh.write("%s,%s,%s,%s,%s,%s,%.6g,%.6g,%.4f,%.4f\n" % (
                r["tag"], r["delta_over_ro"], r["thickness_over_ro"], r["P_over_C1"],
                r["C2_over_C1"], r["ro_over_head_radius"], gi, gi * (1 + e), e, ce))
        if few:  # outside the fit and its domain: their error is extrapolation
            d2, w2, p2, c2, k2, g2 = groups(few)
            e2 = model(th, d2, w2, p2, c2, k2, ref) / g2 - 1
            for r, gi, e, ce in zip(few, g2, e2, (2 * d2 - d2 * d2) / g2 - 1):
                fh.write("%s (outside the fit),%s,%s,%s,%s,%s,%.6g,%.6g,%.4f,%.4f\n" % (
                    r["tag"], r["delta_over_ro"], r["thickness_over_ro"], r["P_over_C1"],
                    r["C2_over_C1"], r["ro_over_head_radius"], gi, gi * (1 + e), e, ce))
    print("coefficients", dict(zip(names, th)), "ref", ref)
    print("law: worst %.2f %%, rms %.2f %%; cap law: %.0f %% .. %.0f %%" % (
        100 * np.abs(err).max(), 100 * np.sqrt(np.mean(err ** 2)), 100 * cap.min(),
        100 * cap.max()))
    print("domain", dom)


if __name__ == "__main__":
    main()
