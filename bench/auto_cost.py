"""What auto's choice by model error costs at create (docs/planner.md, "What create does").

  PYTHONPATH=build/python /usr/bin/python3 bench/auto_cost.py [--runs N]

For each scene that asks for auto with a load: the time to build a headplan.Planner (one
hp_planner_create: the level resolved, the planner built) with the level auto measures at the
nominal pose (auto_pose 0), at the scene's correction (the default a scene gives), and with
--level load (the baseline: the load level's own create, no comparison). Medians of N runs,
the three variants interleaved in each run so that a loaded machine slows them alike; ratios
against the baseline of the same run. Prints a Markdown table (scripts/regen_docs.py puts it
in docs/planner.md)."""
import argparse
import os
import statistics
import time

import headplan

SCENES = ("scenarios/load_supine.yaml", "scenarios/load_tilted.yaml", "tests/scene/auto_pose.yaml")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--runs", type=int, default=21)
    ap.add_argument("--src", default=os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    a = ap.parse_args()
    variants = (("load", dict(level="load")), ("nominal", dict(auto_pose=[0.0] * 6)),
                ("correction", {}))
    print("| scene | `--level load` (baseline) | auto at the nominal pose | auto at the correction "
          "| chosen at the nominal pose, at the correction |")
    print("|---|---|---|---|---|")
    for name in SCENES:
        sc = headplan.load_scene(os.path.join(a.src, name))
        t = {k: [] for k, _ in variants}
        for _ in range(a.runs):
            for k, kw in variants:
                t0 = time.perf_counter()
                headplan.Planner(sc, **kw)
                t[k].append(time.perf_counter() - t0)
        med = {k: statistics.median(v) * 1e3 for k, v in t.items()}
        chosen = (headplan.Planner(sc, auto_pose=[0.0] * 6).level, headplan.Planner(sc).level)
        print("| %s | %.1f ms | %.1f ms (%.1f×) | %.1f ms (%.1f×) | %s, %s |" % (
            os.path.basename(name), med["load"], med["nominal"], med["nominal"] / med["load"],
            med["correction"], med["correction"] / med["load"], *chosen))
    print("\nMedians of %d interleaved runs of `headplan.Planner(scene, ...)` (one create each); "
          "`bench/auto_cost.py`." % a.runs)


if __name__ == "__main__":
    main()
