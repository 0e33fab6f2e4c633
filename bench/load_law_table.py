#!/usr/bin/env python3
"""The load scenes under the two contact laws (docs/load.md, "The load scenes").

For every catalogue load scene (scenarios/load_*.yaml) under the fitted law (`load.law: fem`,
the default) and the cap law (`load.law: cap`): what `headplan solve` plans for the scene's
own correction: status and stability, the pressures of the base and side bladders, the
largest indentation delta/ro, the sum of the bladders' forces against the load's weight,
and how far below the desired pose the answer holds the head (0 when reached). Then the
earlier scenes (the default-size bladders: examples/calibration/load_supine_cap.yaml and its
tilted, 1.3-stretch and prone variants) under both laws: under the fitted law their refusal
at create, the capacity it states against the weight.

    python3 bench/load_law_table.py [HEADPLAN] [SOURCE_DIR] [--cost N [--quick]]

prints a Markdown table (scripts/regen_docs.py writes it into docs/load.md). Everything is
computed by the program; nothing here is a model. With --cost N it prints instead, per
catalogue scene the load level plans, the median over N runs of the plan's own time (the
time `headplan solve` prints on its level line: one cold plan, realtime backend, without
the process's start) under each law, the runs alternating fem, cap, fem, ... so that both
see the same machine, and the ratio of the medians.
"""
import json
import os
import re
import subprocess
import sys
import tempfile

ARGS = [a for a in sys.argv[1:] if not a.startswith("--")]
COST = int(sys.argv[sys.argv.index("--cost") + 1]) if "--cost" in sys.argv else 0
if COST:
    ARGS.remove(str(COST))
    if "--quick" in sys.argv:  # the docs test's size: the command runs, the figure is noise
        COST = 3
HP = ARGS[0] if len(ARGS) > 0 else "build/headplan"
SRC = ARGS[1] if len(ARGS) > 1 else "."
SCENES = ["load_supine", "load_tilted", "load_heavy", "load_prone"]


def with_law(text, law):
    """The scene text with load.law set (the key added first in the load section)."""
    text = re.sub(r"law: \w+, ", "", text)
    return text.replace("load: {", "load: {law: %s, " % law, 1)


def run_solve(text, extra):
    with tempfile.NamedTemporaryFile("w", suffix=".yaml", delete=False) as f:
        f.write(text)
        path = f.name
    try:
        return subprocess.run([HP, "solve", path, "--level", "load"] + extra, capture_output=True,
                              text=True, env=dict(os.environ, LC_ALL="C"))
    finally:
        os.unlink(path)


def plan_us(text):
    """The plan's own time [us] from solve's level line."""
    r = run_solve(text, [])
    m = re.search(r"^level .*, ([0-9.]+) us$", r.stdout, re.M)
    return float(m.group(1)) if m else None


def median(v):
    v = sorted(v)
    n = len(v)
    return v[n // 2] if n % 2 else 0.5 * (v[n // 2 - 1] + v[n // 2])


def cost(n):
    print("| scene | status fem / cap | fem, median | cap, median | fem / cap |")
    print("|---|---|---|---|---|")
    for s in SCENES:
        text = open(os.path.join(SRC, "scenarios", s + ".yaml")).read()
        o, _ = solve(with_law(text, "fem"))
        oc, _ = solve(with_law(text, "cap"))
        if o is None or oc is None:
            continue  # refused (at create, or held only at a saddle) under a law: no answer to time
        t = {"fem": [], "cap": []}
        for _ in range(n):
            for law in ("fem", "cap"):
                t[law].append(plan_us(with_law(text, law)))
        f, c = median(t["fem"]), median(t["cap"])
        print("| `%s` | %s / %s | %.1f µs | %.1f µs | ×%.2f |" % (s, o["status"], oc["status"], f, c,
                                                                f / c))


def solve(text):
    r = run_solve(text, ["--json"])
    if r.returncode in (0, 1):
        return json.loads(r.stdout), None
    return None, r.stderr.strip().split(": ", 2)[-1]


def kpa_range(bl, prefix):
    p = [b["pressure_pa"] / 1e3 for b in bl if b["name"].startswith(prefix)]
    lo, hi = min(p), max(p)
    return "%.2f" % lo if abs(hi - lo) < 0.005 else "%.2f–%.2f" % (lo, hi)


def weight(text):
    mass = float(re.search(r"mass_kg: ([0-9.]+)", text).group(1))
    frac = float(re.search(r"carried_fraction: ([0-9.]+)", text).group(1))
    return mass * frac * 9.80665


def row(name, law, text):
    o, err = solve(with_law(text, law))
    if o is None:
        m = re.search(r"carry at most ([0-9.]+) N.*weighs ([0-9.]+) N", err)
        u = re.search(r"only at an unstable equilibrium.*smallest eigenvalue is ([-0-9.e]+) N/mm",
                      err)
        what = ("refused at create: carries at most %s N of %s N" % m.groups() if m else
                "refused: held only at a saddle (λ_min %s N/mm)" % u.group(1) if u else err)
        return "| `%s` | %s | %s | | | | | |" % (name, law, what)
    bl = o["bladders"]
    sink = o["desired"]["z_mm"] - o["achieved"]["z_mm"]
    stable = "stable" if o["stable"] else "not stable"
    return "| `%s` | %s | %s, %s | %s | %s | %.3f | %.1f, %.1f N | %.2f |" % (
        name, law, o["status"], stable, kpa_range(bl, "base_"), kpa_range(bl, "side_"),
        max(b["indent"] for b in bl), sum(b["force_n"] for b in bl), weight(text),
        round(sink, 2) + 0.0)


def main():
    print("| scene | law | status, hold | base kPa | side kPa | largest δ/ro "
          "| Σ forces, weight | head below desired, mm |")
    print("|---|---|---|---|---|---|---|---|")
    for s in SCENES:
        text = open(os.path.join(SRC, "scenarios", s + ".yaml")).read()
        for law in ("fem", "cap"):
            print(row(s, law, text))
    old = open(os.path.join(SRC, "examples", "calibration", "load_supine_cap.yaml")).read()
    variants = [
        ("earlier load_supine", old),
        ("earlier load_tilted", old.replace(
            "gravity_dir: [0, 0, -1]", "gravity_dir: [0, -0.17364817766693, -0.98480775301221]")),
        ("earlier load_heavy", old.replace("stretch_max: 1.6", "stretch_max: 1.3")),
        ("earlier load_prone", old.replace("carried_fraction: 0.8", "carried_fraction: 1.0")
         .replace("gravity_dir: [0, 0, -1]", "gravity_dir: [0, 0, 1]")),
    ]
    for name, text in variants:
        for law in ("fem", "cap"):
            print(row(name, law, text))


if __name__ == "__main__":
    if COST:
        cost(COST)
    else:
        main()
