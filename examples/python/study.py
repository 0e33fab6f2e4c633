#!/usr/bin/env python3
"""A worked offline study with the headplan Python module (docs/python.md).

Loads a scene, plans its correction and draws the scene (head, bladders coloured by pressure,
limits that bind, desired against achieved head motion), runs the scene's trace greedily as
`headplan batch` does with two backends and compares them, and draws the trace over time
(per-axis pose error with the clinical tolerance band, pressures with their limits, rows
that only reached the closest correction). Units: mm, degrees, Pa (kPa on the pictures).

    PYTHONPATH=build/python python3 examples/python/study.py [SCENE] [--out DIR]

Copy the pieces you need into a notebook: scene_figure() and trace_figure() take the
module's results and return matplotlib figures.
"""
import argparse
import os
import sys

import matplotlib

matplotlib.use("Agg")  # files only; remove in a notebook
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.colors import TwoSlopeNorm, Normalize

import headplan

HERE = os.path.dirname(os.path.abspath(__file__))
TOLERANCE = 0.5  # clinical tolerance band: 0.5 mm in translation, 0.5 degree in rotation


def sphere(center, radius, n=16):
    u, v = np.meshgrid(np.linspace(0, 2 * np.pi, 2 * n), np.linspace(0, np.pi, n))
    return (center[0] + radius * np.sin(v) * np.cos(u),
            center[1] + radius * np.sin(v) * np.sin(u),
            center[2] + radius * np.cos(v))


def rotation(pitch, roll, yaw):
    """R = Rz(yaw) Ry(roll) Rx(pitch), angles in degrees (the library's convention)."""
    a, b, c = np.radians([pitch, roll, yaw])
    rx = np.array([[1, 0, 0], [0, np.cos(a), -np.sin(a)], [0, np.sin(a), np.cos(a)]])
    ry = np.array([[np.cos(b), 0, np.sin(b)], [0, 1, 0], [-np.sin(b), 0, np.cos(b)]])
    rz = np.array([[np.cos(c), -np.sin(c), 0], [np.sin(c), np.cos(c), 0], [0, 0, 1]])
    return rz @ ry @ rx


def moved(layout, pose, q):
    """Head point q (mm) moved by pose [x, y, z mm, pitch, roll, yaw deg] about the pivot."""
    piv = layout["pivot_mm"]
    return piv + rotation(*pose[3:]) @ (q - piv) + pose[:3]


def scene_figure(scene, result):
    """The head, every bladder as a sphere of its planned outer radius coloured by pressure
    (kPa), binding limits in red, and the desired (wide green) against the achieved (blue)
    motion of three head landmarks, magnified; seen from the feet and from below."""
    L = scene.layout
    head = L["head"]
    lo = min(b["pressure_min_pa"] for b in L["bladders"]) / 1e3
    hi = max(b["pressure_max_pa"] for b in L["bladders"]) / 1e3
    norm = TwoSlopeNorm(vmin=lo, vcenter=0.0, vmax=hi) if lo < 0 < hi else Normalize(lo, hi)
    cmap = plt.get_cmap("RdBu_r")
    marks = [head["center_mm"] + np.diag(head["semi_axes_mm"])[i] for i in (2, 1, 0)]
    zero = np.zeros(6)
    big = max(np.abs(moved(L, p, q) - q).max() for q in marks
              for p in (result["desired"], result["achieved"]))
    mag = 1.0 if big == 0 else 10 ** np.floor(np.log10(25 / big))
    fig = plt.figure(figsize=(14, 6.5))
    views = [("from the feet", 0, -90), ("from below", -90, -90)]
    for i, (title, elev, azim) in enumerate(views):
        ax = fig.add_axes([0.01 + 0.33 * i, 0.02, 0.34, 0.9], projection="3d")
        ax.computed_zorder = False  # labels and arrows over the spheres, in drawing order
        x, y, z = sphere(head["center_mm"], 1.0, 24)
        a, b, c = head["semi_axes_mm"]
        hc = head["center_mm"]
        ax.plot_wireframe(hc[0] + a * (x - hc[0]), hc[1] + b * (y - hc[1]),
                          hc[2] + c * (z - hc[2]), color="0.75", linewidth=0.4)
        for k, bl in enumerate(L["bladders"]):
            kpa = result["pressure_pa"][k] / 1e3
            ax.plot_surface(*sphere(bl["center_mm"], result["ro_mm"][k]),
                            color=cmap(norm(kpa)), edgecolor="0.35", linewidth=0.2, shade=False)
            out = bl["center_mm"] - hc
            at = bl["center_mm"] + out / np.linalg.norm(out) * (result["ro_mm"][k] + 9)
            bind = result["binding"][k]
            ax.text(*at, str(k + 1), color="#d00000" if bind else "k", fontsize=12,
                    fontweight="bold" if bind else "normal", ha="center", va="center", zorder=10)
        for q in marks:
            p0 = moved(L, zero, q)
            for pose, style in ((result["desired"], dict(color="#66bd63", lw=5)),
                                (result["achieved"], dict(color="#2166ac", lw=2))):
                p1 = p0 + mag * (moved(L, pose, q) - p0)
                ax.plot(*np.column_stack([p0, p1]), zorder=9, **style)
        ax.view_init(elev=elev, azim=azim)
        ax.set_box_aspect((1, 1, 1), zoom=1.45)
        lim = max(head["semi_axes_mm"]) + 40
        for f in (ax.set_xlim, ax.set_ylim, ax.set_zlim):
            f(-lim, lim)
        ax.set_axis_off()
        ax.set_title(title)
    ax = fig.add_axes([0.69, 0.2, 0.3, 0.7])
    ax.axis("off")
    lines = ["bladder              kPa    [min, max]"]
    for k, bl in enumerate(L["bladders"]):
        names = ",".join(headplan.binding_names(int(result["binding"][k])))
        lines.append(f"{k + 1} {bl['name']:<16} {result['pressure_pa'][k] / 1e3:7.3f}  "
                     f"[{bl['pressure_min_pa'] / 1e3:g}, {bl['pressure_max_pa'] / 1e3:g}] {names}")
    lines += ["", "pose        desired   achieved"]
    for i, key in enumerate(headplan.POSE_KEYS):
        lines.append(f"{key:<10} {result['desired'][i]:9.4f} {result['achieved'][i]:9.4f}")
    lines += ["", f"status {result['status']}; motion x{mag:g}:",
              "desired (wide green), achieved (blue)"]
    ax.text(0, 1, "\n".join(lines), family="monospace", fontsize=9, va="top")
    cax = fig.add_axes([0.70, 0.1, 0.25, 0.03])
    fig.colorbar(plt.cm.ScalarMappable(norm=norm, cmap=cmap), cax=cax, orientation="horizontal",
                 label="pressure [kPa]")
    fig.suptitle(scene.name)
    return fig


def trace_figure(scene, run, title):
    """Per-axis pose error (achieved - desired) over time with the tolerance band, every
    pressure with its limits, closest rows (orange) and failed rows (red) marked."""
    t = run["t_s"]
    ok = run["status"] != "bad-row"
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(13, 8), sharex=True)
    top.axhspan(-TOLERANCE, TOLERANCE, color="#d9f0d3", label="tolerance ±0.5")
    for i, key in enumerate(headplan.POSE_KEYS):
        top.plot(t[ok], run["error"][ok, i], label=key, lw=1.2)
    top.set_ylabel("pose error [mm or deg]")
    for ax in (top, bottom):
        for status, color, marker in (("closest", "#f08000", "^"), ("failed", "#d00000", "x")):
            sel = run["status"] == status if status == "closest" else \
                ok & ~np.isin(run["status"], ["reached", "closest"])
            if sel.any():
                ax.plot(t[sel], np.full(sel.sum(), ax.get_ylim()[1]), marker, color=color,
                        label=status, clip_on=False)
    names = scene.bladder_names
    L = scene.layout
    for k, name in enumerate(names):
        line, = bottom.plot(t[ok], run["pressure_pa"][ok, k] / 1e3, lw=1.0, label=name)
        for key in ("pressure_min_pa", "pressure_max_pa"):
            bottom.axhline(L["bladders"][k][key] / 1e3, ls="--", lw=0.8, color=line.get_color())
    bottom.set_ylabel("pressure [kPa] (limits dashed)")
    bottom.set_xlabel("time [s]")
    for ax in (top, bottom):
        ax.grid(alpha=0.3)
        ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1), fontsize=8)
    n = len(t)
    top.set_title(f"{n} rows: {(run['status'] == 'closest').sum()} closest, "
                  f"{(ok & ~np.isin(run['status'], ['reached', 'closest'])).sum()} failed, "
                  f"{(~ok).sum()} bad rows")
    fig.suptitle(title)
    fig.tight_layout()
    return fig


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("scene", nargs="?",
                    default=os.path.join(HERE, "..", "..", "scenarios", "default.yaml"))
    ap.add_argument("--out", default=".", help="folder for the two pictures")
    a = ap.parse_args()

    scene = headplan.load_scene(a.scene)
    planner = headplan.Planner(scene)                 # the scene's backend and level
    print(f"{scene.name}: {len(scene.bladder_names)} bladders, level {planner.level}")

    one = planner.plan(scene.correction if scene.correction is not None else np.zeros(6))
    print(f"correction {one['desired']} -> {one['status']}, pose error {one['pose_error']:.3g}")
    fig = scene_figure(scene, one)
    fig.savefig(os.path.join(a.out, "study_scene.png"), dpi=100)

    if scene.trace is None:
        print("the scene names no trace: done")
        return 0
    runs = {}
    for backend in ("realtime", "nlopt-slsqp"):
        runs[backend] = headplan.Planner(scene, backend=backend).run_trace()
        r = runs[backend]
        print(f"{backend:12s} {len(r['status'])} rows: "
              f"{(r['status'] == 'reached').sum()} reached, "
              f"{(r['status'] == 'closest').sum()} closest; worst pose error "
              f"{np.nanmax(r['pose_error']):.3g}; median {np.nanmedian(r['solve_time_us']):.1f} us")
    d = np.nanmax(np.abs(runs["realtime"]["pressure_pa"] - runs["nlopt-slsqp"]["pressure_pa"]))
    print(f"largest pressure difference between the backends: {d:.3g} Pa")
    fig = trace_figure(scene, runs["realtime"],
                       f"{scene.name}: {os.path.basename(scene.trace)} (realtime)")
    fig.savefig(os.path.join(a.out, "study_trace.png"), dpi=100)
    return 0


if __name__ == "__main__":
    sys.exit(main())
