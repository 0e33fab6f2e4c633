#!/usr/bin/python3
"""Regenerate every measured number the docs show, from one run, and say where it ran.

Usage:
  regen_docs.py [--src DIR] [--bin BUILD] [--quick]     run everything, rewrite the regions
  regen_docs.py --check-readme [--src DIR] [--bin BUILD] compare README's sample output with
                                                         a fresh run (exit 1 when stale)

A generated part of a doc sits between two marks, `<!-- regen:NAME -->` and
`<!-- /regen:NAME -->` (inline or on their own lines); only the text between them is rewritten,
and a doc whose marks are missing or unbalanced stops the run before anything is written. The
date, machine and build of the run go to docs/measurements.md, which the other docs cite. What
runs (the fixed configuration, in this order):
  readme-solve      headplan solve scenarios/default.yaml                  README.md
  bench-*, speed-*  headplan-bench --out docs/figures (all families), then
                    bench/csv_tables.py docs/figures                        docs/benchmarks.md,
                                                                            README.md
  restarts-cost     planner.csv of the same headplan-bench run              docs/planner.md
  backends-table    headplan-bench-backends                                 docs/backends.md
  loop-table        loop.csv of the same headplan-bench run                 docs/control-loop.md
  loop-headline     the same loop.csv, realtime medians                     docs/benchmarks.md,
                                                                            README.md
  loop-tail         bench/loop_tail.sh (callgrind: instructions a plan), linear
                    level, step trace, own answers and measured readings    docs/control-loop.md
  load-table        load.csv of the same headplan-bench run                 docs/load.md
  load-law-table    bench/load_law_table.py (headplan solve, both laws)     docs/load.md
  load-law-cost     bench/load_law_table.py --cost 21                       docs/load.md
  fidelity-table    fidelity.csv of the same headplan-bench run             docs/accuracy.md
  horizon-rh        headplan-bench-horizon rh scenarios/horizon/step.yaml
                    scenarios/traces/step.csv                               docs/horizon.md
  python-row        Planner(default scene).run_trace() of its drift trace,
                    median solve_time_us                                    docs/python.md
  batch-throughput  bench/batch_throughput.sh 200000 200                    docs/batch.md
  run               date, host, compiler, build type, library versions      docs/measurements.md
--quick runs the benchmark lab at its test size (seconds, noisy): for trying the script, never
for a commit. Standard library only; the C locale for every program it runs.
"""
import argparse
import csv
import datetime
import os
import platform
import re
import subprocess
import sys
import time

MARK = re.compile(r"<!-- regen:([a-z0-9-]+) -->(.*?)<!-- /regen:\1 -->", re.S)
# The one field of `headplan solve` that is a time: compared by its shape only.
TIME = re.compile(r"\b\d+(\.\d+)? (us|ms|s)\b")


def run(cmd, cwd, env=None, stdout=subprocess.PIPE):
    e = dict(os.environ, LC_ALL="C")
    e.update(env or {})
    t0 = time.monotonic()
    r = subprocess.run(cmd, cwd=cwd, env=e, stdout=stdout, stderr=subprocess.PIPE, text=True)
    if r.returncode not in (0,):
        sys.exit("regen_docs: %s: exit %d: %s" % (" ".join(cmd), r.returncode, r.stderr[-400:]))
    return r.stdout, time.monotonic() - t0


def regions(text):
    return {m.group(1): m.group(2) for m in MARK.finditer(text)}


def replace(path, new):
    """Rewrites the named regions of one file; every name must be there exactly once."""
    with open(path, encoding="utf-8") as f:
        text = f.read()
    if text.count("<!-- regen:") != text.count("<!-- /regen:"):
        sys.exit("regen_docs: %s: unbalanced regen marks" % path)
    for name in new:
        if len(re.findall(r"<!-- regen:%s -->" % re.escape(name), text)) != 1:
            sys.exit("regen_docs: %s: region %s missing or repeated" % (path, name))

    def sub(m):
        return "<!-- regen:%s -->%s<!-- /regen:%s -->" % (
            m.group(1), new.get(m.group(1), m.group(2)), m.group(1))

    return path, MARK.sub(sub, text)


def block(body):
    """A fenced region body on lines of its own."""
    return "\n" + body.rstrip("\n") + "\n"


def readme_solve(src, binary):
    out, _ = run([os.path.join(binary, "headplan"), "solve", "scenarios/default.yaml"], src)
    return block("```text\n" + out.rstrip("\n") + "\n```")


def check_readme(src, binary):
    with open(os.path.join(src, "README.md"), encoding="utf-8") as f:
        have = regions(f.read()).get("readme-solve")
    if have is None:
        print("README.md: no <!-- regen:readme-solve --> region")
        return 1
    want = readme_solve(src, binary)
    if not TIME.search(have):
        print("README.md: the sample output's time field is missing or malformed")
        return 1
    a, b = TIME.sub("<time>", have).splitlines(), TIME.sub("<time>", want).splitlines()
    if a == b:
        print("README.md: sample output matches `headplan solve scenarios/default.yaml`")
        return 0
    import difflib
    print("README.md: sample output is stale (regenerate: bash scripts/regen-docs.sh):")
    sys.stdout.writelines(l + "\n" for l in difflib.unified_diff(a, b, "README.md", "headplan solve", lineterm=""))
    return 1


# Times are written as the benchmark tables write them (one home: bench/csv_tables.py).
sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))),
                                "bench"))
import csv_tables  # noqa: E402


def fmt_us(us):
    return csv_tables.t(float(us) * 1e3)


def bench_tables(src, figures):
    out, _ = run(["/usr/bin/python3", "bench/csv_tables.py", figures], src)
    parts = re.split(r"^### (\S+)\n", out, flags=re.M)
    return {"bench-" + parts[i].replace("_", "-"): block(parts[i + 1].strip("\n"))
            for i in range(1, len(parts), 2)}


def speed(src, figures):
    """The few figures the README and the advice at the top of benchmarks.md quote, all from
    planner.csv of this run: medians, and ratios of medians of the same run."""
    with open(os.path.join(figures, "planner.csv"), newline="") as f:
        rows = {r["method"]: r for r in csv.DictReader(f)}

    def ns(m):
        return float(rows[m]["median_ns"])

    lines = ["| contact level | direct chain (no limit binds) | realtime, a limit binds "
             "| NLopt SLSQP | Ipopt | SLSQP / realtime | Ipopt / realtime |",
             "|---|---|---|---|---|---|---|"]
    for lv in ("linear", "plane", "surface"):
        rt, sq, ip = ns("realtime-%s-1e-09" % lv), ns("nlopt-slsqp-%s-1e-09" % lv), \
            ns("ipopt-%s-1e-09" % lv)
        lines.append("| %s | %s | %s | %s | %s | %.0f× | %.0f× |" % (
            lv, fmt_us(ns("fastpath-" + lv) / 1e3), fmt_us(rt / 1e3), fmt_us(sq / 1e3),
            fmt_us(ip / 1e3), sq / rt, ip / rt))
    trace = ns("trace-realtime-surface")
    lines.append("")
    lines.append("Medians of cold plans on the default scene at tolerance 1e-9: the direct "
                 "chain on reachable targets, the rest on binding ones (`docs/benchmarks.md`, "
                 "section 2); along a warm trace the surface level takes %s a row. The run: "
                 "`docs/measurements.md`." % fmt_us(trace / 1e3))
    return block("\n".join(lines))


def restarts_cost(figures):
    """What restarts cost (docs/planner.md, Restarts): the planner family's Ipopt and SLSQP
    rows at the surface level, tolerance 1e-9, with restarts 0 (-r0) and the default, on the
    binding and the reachable targets (-reach); medians and their ratio, one run."""
    with open(os.path.join(figures, "planner.csv"), newline="") as f:
        rows = {r["method"]: r for r in csv.DictReader(f)}
    lines = ["| backend | targets | restarts 0 | default restarts (7) | default / 0 |",
             "|---|---|---|---|---|"]
    for b in ("ipopt", "nlopt-slsqp"):
        for reach, what in (("", "binding"), ("-reach", "reachable")):
            m = "%s-surface-1e-09%s" % (b, reach)
            one, dflt = float(rows[m + "-r0"]["median_ns"]), float(rows[m]["median_ns"])
            lines.append("| %s | %s | %s | %s | %.2f× |" % (
                b, what, fmt_us(one / 1e3), fmt_us(dflt / 1e3), dflt / one))
    return block("\n".join(lines))


def loop_rows(figures):
    """The rows of loop.csv of this run, as dictionaries keyed by its header."""
    with open(os.path.join(figures, "loop.csv"), newline="") as f:
        return list(csv.DictReader(f))


def loop_table(figures):
    """The control-loop family (loop.csv of this run): per backend, level and trace the
    medians of the four modes, × the ratio to the rate-free plan of the same trace (the modes
    take turns every cycle), `set` hp_planner_set_measured's median, and the deadline mode's
    time-limit stops, overshoots of the budget by more than 5 us and, of those, the ones by
    more than 100 us (the host's stalls)."""
    rows = loop_rows(figures)
    by = {(r["backend"], r["level"], r["trace"], r["mode"]): r for r in rows}
    keys = []
    for r in rows:
        k = (r["backend"], r["level"], r["trace"])
        if k not in keys:
            keys.append(k)
    lines = ["%-8s %-12s %-7s %6s  %-14s %-14s %-14s %5s  %s" % (
        "level", "backend", "trace", "free", "rate (x)", "measured (x)", "deadline (x)", "set",
        "deadline: time-limit / over (host)")]
    for b, lv, tr in keys:
        m = {mode: by[(b, lv, tr, mode)] for mode in ("free", "rate", "measured", "deadline")}

        def med(mode):
            return "%.2f (%.2f)" % (float(m[mode]["median_us"]), float(m[mode]["ratio_median"]))
        d = m["deadline"]
        lines.append("%-8s %-12s %-7s %6.2f  %-14s %-14s %-14s %5.2f  %s / %s (%s) of %s" % (
            lv, b, tr, float(m["free"]["median_us"]), med("rate"), med("measured"),
            med("deadline"), float(m["measured"]["set_measured_median_us"]), d["time_limit"],
            d["overshoots"], d["overshoots_host"], d["cycles"]))
    return block("```text\n" + "\n".join(lines) + "\n```")


def loop_headline(figures):
    """The headline of the control-loop family in README.md and docs/benchmarks.md (loop.csv of
    this run): the realtime backend's medians per level, rate-free and rate-limited on the smooth trace,
    rate-free, rate-limited and measured on the step trace (x: the ratio to the rate-free
    plan of the same trace), and hp_planner_set_measured's median on the step trace."""
    rows = loop_rows(figures)
    by = {(r["level"], r["trace"], r["mode"]): r for r in rows if r["backend"] == "realtime"}
    levels = []
    for r in rows:
        if r["backend"] == "realtime" and r["level"] not in levels:
            levels.append(r["level"])

    def x(lv, tr, mode):
        r = by[(lv, tr, mode)]
        return "%.2f (%.2f)" % (float(r["median_us"]), float(r["ratio_median"]))
    lines = ["%-8s %12s  %-12s %11s  %-12s %-13s  %s" % (
        "level", "smooth: free", "rate (x)", "step: free", "rate (x)", "measured (x)",
        "set_measured")]
    for lv in levels:
        lines.append("%-8s %12.2f  %-12s %11.2f  %-12s %-13s  %.2f us" % (
            lv, float(by[(lv, "smooth", "free")]["median_us"]), x(lv, "smooth", "rate"),
            float(by[(lv, "step", "free")]["median_us"]), x(lv, "step", "rate"),
            x(lv, "step", "measured"), float(by[(lv, "step", "measured")]["set_measured_median_us"])))
    return block("```text\n" + "\n".join(lines) + "\n```")


def load_table(figures):
    """The load family (load.csv of this run): per scene the kinematic plan's median, and per
    backend the load level's status and median with its ratio to that kinematic plan."""
    with open(os.path.join(figures, "load.csv"), newline="") as f:
        rows = list(csv.DictReader(f))
    order = ("realtime", "ipopt", "nlopt-slsqp")
    lines = ["| scene | kinematic realtime (baseline) | load, realtime | load, ipopt "
             "| load, nlopt-slsqp |", "|---|---|---|---|---|"]
    for scene in sorted({r["scene"] for r in rows}):
        by = {r["backend"]: r for r in rows if r["scene"] == scene}
        base = float(by[order[0]]["kinematic_median_ns"])
        cells = []
        for b in order:
            r = by[b]
            if r["load_status"] == "refused":
                cells.append("refused at create")
            else:
                t = float(r["load_median_ns"])
                cells.append("%s, %s (×%.0f)" % (r["load_status"], csv_tables.t(t), t / base))
        lines.append("| `%s` | %s | %s |" % (scene, csv_tables.t(base), " | ".join(cells)))
    return block("\n".join(lines))


def fidelity_table(figures):
    """The fidelity family (fidelity.csv of this run): per scene and level, the law the level
    planned with, the solver's tolerance, the median over the cases of the pose error under
    the fitted law and the worst with the law's error band, the median share of the weight
    the fitted law's forces bear at the claimed pose, and the rests outside the law's
    domain."""
    import statistics
    with open(os.path.join(figures, "fidelity.csv"), newline="") as f:
        rows = list(csv.DictReader(f))

    def err(v):
        return "∞" if v == float("inf") else "%.3g" % v

    lines = ["| scene | mass | level | law | solver tolerance (mm, °) | cases | median error "
             "mm / ° | worst with the band mm / ° | weight carried (median) | outside the "
             "domain |", "|---|---|---|---|---|---|---|---|---|---|"]
    keys = []
    for r in rows:
        if (r["scene"], r["level"]) not in keys:
            keys.append((r["scene"], r["level"]))
    for scene, level in keys:
        rs = [r for r in rows if r["scene"] == scene and r["level"] == level]
        head = "| `%s` | %s | %s | %s | %s |" % (scene, rs[0]["mass"], level, rs[0]["law"],
                                                rs[0]["tolerance"])
        planned = [r for r in rs if r["status"] not in ("refused", "error")]
        if not planned:
            lines.append(head + " 0 of %d | refused at create | | | |" % len(rs))
            continue
        mm = [float(r["pose_mm"]) for r in planned]
        dg = [float(r["pose_deg"]) for r in planned]
        out = sum(1 for r in planned if r["domain"] != "in")
        norest = sum(1 for r in planned if r["domain"] == "no rest")
        lines.append(head + " %d of %d | %s / %s | %s / %s | %.0f %% | %d (%d no rest) |" % (
            len(planned), len(rs), err(statistics.median(mm)), err(statistics.median(dg)),
            err(max(float(r["band_mm"]) for r in planned)),
            err(max(float(r["band_deg"]) for r in planned)),
            100 * statistics.median(float(r["carried"]) for r in planned) + 0.0, out, norest))
    return block("\n".join(lines))


def horizon_table(out):
    rows = list(csv.DictReader(out.splitlines()))
    by = {(r["N"], r["prediction"]): r for r in rows}
    ns = sorted({int(r["N"]) for r in rows})
    lines = ["| N | hold median | hold p99 | velocity median | velocity p99 |",
             "|---|---|---|---|---|"]
    for n in ns:
        h, v = by[(str(n), "hold")], by[(str(n), "velocity")]
        lines.append("| %d | %s | %s | %s | %s |" % (n, fmt_us(h["median_us"]), fmt_us(h["p99_us"]),
                                                  fmt_us(v["median_us"]), fmt_us(v["p99_us"])))
    return block("\n".join(lines))


PY_ROW = """
import numpy as np, headplan
scene = headplan.load_scene("scenarios/default.yaml")
run = headplan.Planner(scene).run_trace()
assert (run["status"] == "reached").all(), "drift trace: not every row reached"
print(float(np.median(run["solve_time_us"])))
"""


def source_rev(src):
    """The commit the run measures, read before the run: the run itself rewrites the tracked
    figures, which would otherwise read as local changes."""
    def sh(cmd):
        return subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True,
                              env=dict(os.environ, LC_ALL="C")).stdout.strip()
    try:
        rev = sh(["git", "-C", src, "rev-parse", "--short", "HEAD"])
        if rev and sh(["git", "-C", src, "status", "--porcelain", "--untracked-files=no"]):
            rev += " plus the working tree's changes"
        return rev
    except OSError:
        return ""


def machine(src, binary, wall, rev):
    def sh(cmd):
        try:
            return subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL,
                                  text=True, env=dict(os.environ, LC_ALL="C")).stdout.strip()
        except OSError:
            return ""
    cpu = ""
    for line in sh(["lscpu"]).splitlines():
        if line.startswith("Model name:"):
            cpu = line.split(":", 1)[1].strip()
    build_type = ""
    cache = os.path.join(binary, "CMakeCache.txt")
    if os.path.exists(cache):
        for line in open(cache):
            if line.startswith("CMAKE_BUILD_TYPE:"):
                build_type = line.split("=", 1)[1].strip()
    gcc = sh(["gcc", "-dumpfullversion"])
    ipopt = sh(["pkg-config", "--modversion", "ipopt"])
    nlopt = sh(["dpkg-query", "-W", "-f=${Version}", "libnlopt0"])
    load = open("/proc/loadavg").read().split()[:3] if os.path.exists("/proc/loadavg") else []
    now = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    lines = [
        "| | |", "|---|---|",
        "| date | %s |" % now,
        "| processor | %s, %d logical cores |" % (cpu or platform.processor(), os.cpu_count() or 0),
        "| system | %s %s |" % (platform.system(), platform.release()),
        "| load average at the end | %s |" % " ".join(load),
        "| compiler | gcc %s |" % gcc,
        "| build | `%s` (%s) |" % (os.path.relpath(binary, src) if binary.startswith(src) else binary,
                                  build_type),
        "| Ipopt, NLopt | %s, %s |" % (ipopt, nlopt),
        "| source | %s |" % (rev or "not a git checkout"),
        "| wall time | %s |" % ", ".join("%s %.0f s" % kv for kv in wall),
    ]
    return block("\n".join(lines))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--src", default=os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    ap.add_argument("--bin")
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--check-readme", action="store_true")
    a = ap.parse_args()
    src = os.path.abspath(a.src)
    binary = os.path.abspath(a.bin or os.path.join(src, "build"))
    if a.check_readme:
        return check_readme(src, binary)

    figures = os.path.join(src, "docs", "figures")
    rev = source_rev(src)
    wall, new = [], {}
    new["README.md"] = {"readme-solve": readme_solve(src, binary)}
    bench = [os.path.join(binary, "headplan-bench"), "--out", figures] + (["--quick"] if a.quick else [])
    _, w = run(bench, src)
    wall.append(("headplan-bench", w))
    tables = bench_tables(src, figures)
    sp = speed(src, figures)
    new["README.md"]["speed-readme"] = sp
    lh = loop_headline(figures)
    new["README.md"]["loop-headline"] = lh
    new["docs/benchmarks.md"] = dict(tables, **{"speed-benchmarks": sp, "loop-headline": lh})
    new["docs/control-loop.md"] = {"loop-table": loop_table(figures)}
    tails = []
    for feed in ("0", "1"):
        out, w = run(["bash", "bench/loop_tail.sh", os.path.join(binary, "headplan-bench-count"),
                      "scenarios/default.yaml", "0", "step", feed, "300" if a.quick else "3000"], src)
        wall.append(("loop_tail.sh feed " + feed, w))
        tails.append(out.strip("\n"))
    new["docs/control-loop.md"]["loop-tail"] = block("```text\n" + "\n\n".join(tails) + "\n```")
    new["docs/planner.md"] = {"restarts-cost": restarts_cost(figures)}
    out, w = run(["/usr/bin/python3", "bench/auto_cost.py", "--runs", "5" if a.quick else "21"],
                 src, env={"PYTHONPATH": os.path.join(binary, "python")})
    wall.append(("auto_cost.py", w))
    new["docs/planner.md"]["auto-cost"] = block(out.strip("\n"))
    new["docs/load.md"] = {"load-table": load_table(figures)}
    law_table = [sys.executable, "bench/load_law_table.py", os.path.join(binary, "headplan"), src]
    out, w = run(law_table, src)
    wall.append(("load_law_table.py", w))
    new["docs/load.md"]["load-law-table"] = block(out.strip("\n"))
    out, w = run(law_table + ["--cost", "5" if a.quick else "21"], src)
    wall.append(("load_law_table.py --cost", w))
    new["docs/load.md"]["load-law-cost"] = block(out.strip("\n"))
    new["docs/accuracy.md"] = {"fidelity-table": fidelity_table(figures)}
    out, w = run([os.path.join(binary, "headplan-bench-backends")], src)
    wall.append(("headplan-bench-backends", w))
    new["docs/backends.md"] = {"backends-table": block(out.strip("\n"))}
    out, w = run([os.path.join(binary, "headplan-bench-horizon"), "rh",
                  "scenarios/horizon/step.yaml", "scenarios/traces/step.csv"], src)
    wall.append(("headplan-bench-horizon", w))
    new["docs/horizon.md"] = {"horizon-rh": horizon_table(out)}
    out, w = run(["/usr/bin/python3", "-c", PY_ROW], src,
                 env={"PYTHONPATH": os.path.join(binary, "python")})
    wall.append(("python", w))
    new["docs/python.md"] = {"python-row": fmt_us(out.strip())}
    out, w = run(["bash", "bench/batch_throughput.sh", "20000" if a.quick else "200000",
                  "20" if a.quick else "200", os.path.join(binary, "headplan")], src)
    wall.append(("batch_throughput.sh", w))
    new["docs/batch.md"] = {"batch-throughput": block("```text\n" + out.strip("\n") + "\n```")}
    new["docs/measurements.md"] = {"run": machine(src, binary, wall, rev)}

    # Every file's marks are checked before any file is written.
    done = [replace(os.path.join(src, p), r) for p, r in new.items()]
    for path, text in done:
        with open(path + ".tmp", "w", encoding="utf-8") as f:
            f.write(text)
        os.replace(path + ".tmp", path)
        print("regen_docs: %s" % os.path.relpath(path, src))
    return 0


if __name__ == "__main__":
    sys.exit(main())
