#!/usr/bin/env python3
"""Writes the example calibration data of docs/calibration.md, deterministically (seeded,
standard library only): a "real device" whose parameters differ from the catalogue's, and
what measuring it would give.

  material_ri.csv  free inflation of one bladder, inner radius measured (sigma 0.02 mm)
  material_ro.csv  the same bladder, outer radius measured by calipers (sigma 0.02 mm)
  layout_rows.jsonl the same rows as JSON Lines
  layout_rows.csv  24 rows (eight pressures, measured pose) for scenarios/default.yaml's
                   layout on a head 0.6/-0.8/+0.5 mm off in its semi-axes and with bladders
                   sitting up to 0.3 mm off their drawn positions (pose noise 0.05 mm, 0.05 deg)

The model is the project's (docs/calibration.md, docs/kinematics.md): the closed-form
pressure of a thick Mooney-Rivlin shell, the volume law, and the exact distance from each
bladder's centre to the moved ellipsoid. The true values are written as comments at the top
of each file (the readers skip '#' lines), so a test can check the fit against them.

Run from anywhere: python3 examples/calibration/make_data.py
"""
import math
import os
import random

HERE = os.path.dirname(os.path.abspath(__file__))


def pressure(Ri, Ro, C1, C2, ri):
    """Closed-form inverse kinematics (paper convention)."""
    ro = (Ro ** 3 + ri ** 3 - Ri ** 3) ** (1.0 / 3.0)
    li, lo = ri / Ri, ro / Ro
    f = lambda l: -1.0 / l - 1.0 / (4.0 * l ** 4)
    g = lambda l: l - 1.0 / (2.0 * l * l)
    return 2.0 * C1 * (f(li) - f(lo)) + 2.0 * C2 * (g(li) - g(lo))


def inner_from_pressure(Ri, Ro, C1, C2, P):
    """Forward kinematics by bisection (the moduli here have no limit point)."""
    lo, hi = 0.3 * Ri, 2.0 * Ri
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if pressure(Ri, Ro, C1, C2, mid) < P:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def write(path, header, rows, comments):
    with open(path, "w", encoding="ascii", newline="\n") as f:
        for c in comments:
            f.write("# " + c + "\n")
        f.write(header + "\n")
        for r in rows:
            f.write(",".join(r) + "\n")


def material(rng):
    Ri, Ro, C1, C2, sig = 27.0, 30.0, 1.25e4, 1.9e4, 0.02
    pressures = [-4000 + 10000 * i / 11 for i in range(12)]
    rows_ri, rows_ro = [], []
    for P in pressures:
        ri = inner_from_pressure(Ri * 1e-3, Ro * 1e-3, C1, C2, P) * 1e3
        ro = (Ro ** 3 + ri ** 3 - Ri ** 3) ** (1.0 / 3.0)
        rows_ri.append(["%.1f" % P, "%.4f" % (ri + rng.gauss(0, sig)), "%g" % sig])
        rows_ro.append(["%.1f" % P, "%.4f" % (ro + rng.gauss(0, sig)), "%g" % sig])
    truth = ["truth: C1_pa=%g C2_pa=%g (Ri 27 mm, Ro 30 mm; catalogue: 1.1e4, 2.2e4)" % (C1, C2),
             "free inflation, radius noise sigma %g mm (seeded, make_data.py)" % sig]
    write(os.path.join(HERE, "material_ri.csv"), "pressure_pa,ri_mm,sigma_mm", rows_ri,
          ["inner radius measured"] + truth)
    write(os.path.join(HERE, "material_ro.csv"), "pressure_pa,ro_mm,sigma_mm", rows_ro,
          ["outer radius measured"] + truth)


# ---- layout: scenarios/default.yaml's geometry ----
AXES = [77.5, 115.0, 97.5]
DIRS = [("base_neck_left", (0.35, -0.45, -1)), ("base_neck_right", (-0.35, -0.45, -1)),
        ("base_skull_left", (0.35, 0.45, -1)), ("base_skull_right", (-0.35, 0.45, -1)),
        ("side_fore_left", (1, 0.45, 0.15)), ("side_fore_right", (-1, 0.45, 0.15)),
        ("side_chin_left", (1, -0.45, -0.15)), ("side_chin_right", (-1, -0.45, -0.15))]
RI, RO, C1, C2 = 27e-3, 30e-3, 1.1e4, 2.2e4


def normalize(v):
    n = math.sqrt(sum(x * x for x in v))
    return [x / n for x in v]


def touch(axes, d):
    """Surface point on the ray along d and the outward unit normal there."""
    t = 1.0 / math.sqrt(sum((d[i] / axes[i]) ** 2 for i in range(3)))
    p = [t * d[i] for i in range(3)]
    return p, normalize([p[i] / axes[i] ** 2 for i in range(3)])


def distance(axes, q):
    """Distance from an outside point q to the ellipsoid (Lagrange parameter by bisection)."""
    def s(t):
        return sum((axes[i] * q[i] / (axes[i] ** 2 + t)) ** 2 for i in range(3)) - 1.0
    lo, hi = 0.0, 1.0
    while s(hi) > 0:
        hi *= 2.0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if s(mid) > 0:
            lo = mid
        else:
            hi = mid
    t = 0.5 * (lo + hi)
    x = [axes[i] ** 2 * q[i] / (axes[i] ** 2 + t) for i in range(3)]
    return math.sqrt(sum((q[i] - x[i]) ** 2 for i in range(3)))


def rotation(pitch, roll, yaw):
    cx, sx, cy, sy, cz, sz = (math.cos(pitch), math.sin(pitch), math.cos(roll), math.sin(roll),
                              math.cos(yaw), math.sin(yaw))
    Rx = [[1, 0, 0], [0, cx, -sx], [0, sx, cx]]
    Ry = [[cy, 0, sy], [0, 1, 0], [-sy, 0, cy]]
    Rz = [[cz, -sz, 0], [sz, cz, 0], [0, 0, 1]]
    mul = lambda A, B: [[sum(A[i][k] * B[k][j] for k in range(3)) for j in range(3)]
                        for i in range(3)]
    return mul(Rz, mul(Ry, Rx))


def layout(rng):
    d_axes = [0.6, -0.8, 0.5]
    offsets = [0.3, -0.2, 0.0, 0.2, -0.3, 0.25, 0.0, -0.2]
    axes_true = [AXES[i] + d_axes[i] for i in range(3)]
    centres = []
    for k, (_, d) in enumerate(DIRS):
        p, n = touch(AXES, d)             # drawn placement on the catalogue head
        centres.append([p[i] + (RO * 1e3 + offsets[k]) * n[i] for i in range(3)])
    rows, sig_mm, sig_deg = [], 0.05, 0.05
    while len(rows) < 24:
        pose = [rng.uniform(-1.5, 1.5) for _ in range(3)] + \
               [rng.uniform(-2.0, 2.0) for _ in range(3)]
        R = rotation(*[math.radians(a) for a in pose[3:]])
        ps = []
        for c in centres:
            v = [c[i] - pose[i] for i in range(3)]
            q = [sum(R[j][i] * v[j] for j in range(3)) for i in range(3)]   # R^T (c - t)
            ro = distance(axes_true, q) * 1e-3
            ri = (ro ** 3 - RO ** 3 + RI ** 3) ** (1.0 / 3.0)
            ps.append(pressure(RI, RO, C1, C2, ri))
        if min(ps) < -4800 or max(ps) > 9800:
            continue
        meas = [pose[i] + rng.gauss(0, sig_mm if i < 3 else sig_deg) for i in range(6)]
        rows.append(["%.3f" % P for P in ps] + ["%.4f" % m for m in meas])
    header = ",".join("p_%s_pa" % n for n, _ in DIRS) + \
        ",x_mm,y_mm,z_mm,pitch_deg,roll_deg,yaw_deg"
    comments = ["layout rows for scenarios/default.yaml (seeded, make_data.py)",
                "truth: semi_axes_mm=%s" % " ".join("%g" % a for a in axes_true),
                "truth: offsets_mm=%s" % " ".join("%g" % o for o in offsets),
                "pose noise sigma %g mm, %g deg" % (sig_mm, sig_deg)]
    write(os.path.join(HERE, "layout_rows.csv"), header, rows, comments)
    # The same rows as JSON Lines (numbers written as in the CSV, so both read the same).
    keys = header.split(",")
    with open(os.path.join(HERE, "layout_rows.jsonl"), "w", encoding="ascii", newline="\n") as f:
        for r in rows:
            f.write("{" + ", ".join('"%s": %s' % (k, v) for k, v in zip(keys, r)) + "}\n")


def main():
    rng = random.Random(20261201)
    material(rng)
    layout(rng)


if __name__ == "__main__":
    main()
