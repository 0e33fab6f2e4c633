#!/usr/bin/python3
"""Print the Markdown tables of docs/accuracy.md section 5 from fem/tables/*.csv."""
import csv
import math
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))


def table(name):
    path = os.path.join(HERE, "tables", name)
    if not os.path.exists(path):
        return []
    with open(path) as fh:
        return list(csv.DictReader(l for l in fh if not l.startswith("#")))


def f(x, n=4):
    try:
        v = float(x)
    except ValueError:
        return x
    return "—" if math.isnan(v) else "%.*g" % (n, v)


def inflation():
    print("| control | Ri/Ro | C2/C1 | λi | P (Pa) | P_IK(ri)/P − 1, meshes 2×10 / 4×20 / 8×40 | observed order |")
    print("|---|---|---|---|---|---|---|")
    rows = [r for r in table("inflation.csv") if r["bulk_over_shear"] == "10000"]
    for i in range(0, len(rows), 4):
        g = rows[i:i + 4]
        if len(g) < 4 or g[3]["mesh"] != "rate":
            continue
        print("| %s | %s/%s | %s | %s | %s | %s | %s |" % (
            g[0].get("control", "pressure"), f(g[0]["Ri_mm"]), f(g[0]["Ro_mm"]),
            f(float(g[0]["C2_pa"]) / float(g[0]["C1_pa"])), g[0]["lambda_i_ik"],
            f(g[2]["P_pa"], 5),
            " / ".join("%.1e" % float(r["P_ik_at_ri_fem_over_P_minus_1"]) for r in g[:3]),
            f(g[3]["ri_fem_mm"], 2)))


def d1():
    print("| control | λi | bulk/shear | P_IK(ri)/P − 1 |")
    print("|---|---|---|---|")
    seen = set()
    for r in table("inflation.csv"):
        key = (r.get("control", "pressure"), r["lambda_i_ik"], r["bulk_over_shear"])
        if (r["mesh"] == "8x40" and r["Ri_mm"] == "27" and r["C2_pa"] == "22000"
                and (key[0], key[1]) in (("pressure", "1.3"), ("displacement", "1.6"))
                and key not in seen):
            seen.add(key)
            print("| %s | %s | %s | %.1e |" % (key[0], key[1], f(r["bulk_over_shear"]),
                                               float(r["P_ik_at_ri_fem_over_P_minus_1"])))


def membrane():
    """docs/load.md's table of the thin-membrane shooting check: {delta/ro: F/(P pi ro^2)}."""
    out = {}
    with open(os.path.join(HERE, "..", "docs", "load.md")) as fh:
        for line in fh:
            p = [x.strip() for x in line.strip().strip("|").split("|")]
            if len(p) == 4 and p[3].endswith("%") and p[0][:1].isdigit():
                out[p[0]] = float(p[1])
    return out


def thin():
    m = membrane()
    print("| δ/ro | F/(P·π·ro²) FEM, wall 2 % | membrane (docs/load.md) | FEM/membrane − 1 | cap law |")
    print("|---|---|---|---|---|")
    rows = sorted((r for r in table("contact_checks.csv") if r["tag"] == "thin"),
                  key=lambda r: float(r["delta_over_ro"]))
    for r in rows:
        g, mm = float(r["F_over_P_pi_ro2"]), m.get(r["delta_over_ro"], float("nan"))
        print("| %s | %s | %s | %+.1f %% | %s |" % (r["delta_over_ro"], f(g), f(mm),
                                                  100 * (g / mm - 1), f(r["cap_law"])))


def contact(name, tags):
    print("| tag | indenter | support | mesh | penalty | bulk/shear | δ/ro | wall/ro | P/C1 | C2/C1 | ro/Rh | F/(P·π·ro²) | cap law | cap/FEM | patch/ro | ΔV/V |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for r in table(name):
        if tags and r["tag"] not in tags:
            continue
        g, cap = float(r["F_over_P_pi_ro2"]), float(r["cap_law"])
        print("| %s |" % " | ".join([r["tag"], r["indenter"], r["support"], r["mesh"],
                                     f(r["penalty"]), f(r["bulk_over_shear"]),
                                     f(r["delta_over_ro"]), f(r["thickness_over_ro"], 3),
                                     f(r["P_over_C1"], 3), f(r["C2_over_C1"]),
                                     f(r["ro_over_head_radius"], 3), f(g), f(cap),
                                     "—" if math.isnan(g) else "%.2f" % (cap / g),
                                     f(r["patch_over_ro"], 3), f(r["volume_change"], 3)]))


def sweep():
    law = {(r["tag"], r["delta_over_ro"]): r for r in table("law_error.csv")}
    print("| case | δ/ro | wall/ro | P/C1 | C2/C1 | ro/Rh | F/(P·π·ro²) | cap/FEM | fitted law − FEM | patch/ro | ΔV/V |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for r in table("sweep.csv"):
        g, cap = float(r["F_over_P_pi_ro2"]), float(r["cap_law"])
        e = law.get((r["tag"], r["delta_over_ro"]))
        print("| %s |" % " | ".join([
            r["tag"], f(r["delta_over_ro"]), f(r["thickness_over_ro"], 3), f(r["P_over_C1"], 3),
            f(r["C2_over_C1"]), f(r["ro_over_head_radius"], 3),
            f(g) if not math.isnan(g) else "no convergence",
            "—" if math.isnan(g) else "%.2f" % (cap / g),
            "—" if e is None else "%+.1f %%" % (100 * float(e["law_error"])),
            f(r["patch_over_ro"], 3), f(r["volume_change"], 3)]))


def shape():
    rows = table("shape.csv")
    angles = [k for k in (rows[0].keys() if rows else []) if k[6:].isdigit()]  # bulge_A
    print("| case | δ/ro | F/(P·π·ro²) | patch edge (° above the equator) | largest bulge Δr/ro at (°), mm | most drawn in Δr/ro at (°), mm | Δr/ro at %s |"
          % " / ".join(k[6:] + "°" for k in angles))
    print("|---|---|---|---|---|---|---|")
    for r in rows:
        print("| %s |" % " | ".join([
            r["tag"], f(r["delta_over_ro"]), f(r["F_over_P_pi_ro2"]), f(r["edge_deg"], 3),
            "%s at %s°, %s" % (f(r["bulge_max"], 3), f(r["bulge_max_deg"], 2),
                               f(r["bulge_max_mm"], 2)),
            "%s at %s°, %s" % (f(r["bulge_min"], 3), f(r["bulge_min_deg"], 2),
                               f(r["bulge_min_mm"], 2)),
            " / ".join(f(r[k], 3) if r[k] else "patch" for k in angles)]))


def tilt():
    print("| support | tilt (°) | δ/ro | t reached | δ/ro at t | F/(P·π·ro²), 3-D | axisymmetric | 3-D/axisymmetric − 1 | against tilt 0, same support and t | fitted law | 3-D/law − 1 | force to normal (°) | centre of pressure off the normal's foot /ro |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    pc = lambda x: "—" if x in ("", "nan") else "%+.2f %%" % (100 * (float(x) - 1))
    for r in table("tilt.csv"):
        print("| %s |" % " | ".join([
            r["support"], f(r["tilt_deg"]), f(r["delta_over_ro"]),
            f(r["t_reached"]), f(r["delta_over_ro_at_t"], 3), f(r["F_over_P_pi_ro2"]),
            f(r["F_axisymmetric"]),
            pc(r["F_over_F_axisymmetric"]), pc(r["F_over_F_3d_tilt_0"]), f(r["F_law"]),
            pc(r["F_over_F_law"]), f(r["angle_deg"], 2), f(r["offset_over_ro"], 3)]))


if __name__ == "__main__":
    what = sys.argv[1] if len(sys.argv) > 1 else "all"
    if what in ("all", "inflation"):
        inflation()
    if what in ("all", "d1"):
        d1()
    if what in ("all", "thin"):
        thin()
    if what in ("all", "checks"):
        contact("contact_checks.csv", None)
    if what in ("all", "sweep"):
        sweep()
    if what in ("all", "shape"):
        shape()
    if what in ("all", "thick"):
        contact("thick.csv", None)
    if what in ("all", "tilt"):
        tilt()
