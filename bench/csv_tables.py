#!/usr/bin/python3
"""Print the Markdown tables of docs/benchmarks.md from the CSVs of `headplan-bench`.

Usage: bench/csv_tables.py [DIR]   (DIR defaults to docs/figures)

Prints, per family, the table the page shows (IK, planner, stability summary, silent wrong
answers, peers, levels, and section 6's realtime ratios), each under a "### NAME" line, so
a re-run's tables are pasted, not retyped. Reads only; standard library only. Times: < 10 µs in whole ns, < 1 ms in µs (one
decimal), else ms (two decimals); errors with three significant digits; ratios as the CSV
writes them.
"""
import csv
import os
import sys
from collections import OrderedDict


def read(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def t(ns):
    ns = float(ns)
    if ns < 1e4:
        return "%.0f ns" % ns
    if ns < 1e6:
        return "%.1f µs" % (ns / 1e3)
    return "%.2f ms" % (ns / 1e6)


def e(x):
    return "%.2e" % float(x)


def row(cells):
    return "| " + " | ".join(cells) + " |"


def worst(r):
    return r["worst_input"].split(";first_failure=")[0].replace(";", ", ")


def fails(r):
    parts = r["worst_input"].split(";first_failure=")
    first = parts[1] if len(parts) > 1 else ""
    return ("%s/%s %s" % (r["failures"], r["inputs"], first)).rstrip()


def ik(d):
    print(row(["method", "median", "p99", "max error", "worst input", "ratio to baseline",
               "front"]))
    print("|---" * 7 + "|")
    for r in read(os.path.join(d, "ik.csv")):
        print(row(["`%s`" % r["method"], t(r["median_ns"]), t(r["p99_ns"]), e(r["max_error"]),
                   worst(r), r["ratio_to_baseline"], "*" if r["pareto"] == "1" else ""]))


def planner(d):
    print(row(["method", "inputs", "median", "p99", "max error vs reference", "model error",
               "failures (first)", "ratio to Ipopt", "ratio to Ipopt (rounds)", "front"]))
    print("|---" * 10 + "|")
    for r in read(os.path.join(d, "planner.csv")):
        print(row(["`%s`" % r["method"], r["input_set"], t(r["median_ns"]), t(r["p99_ns"]),
                   e(r["max_error"]), e(r["model_error"]), fails(r), r["ratio_to_baseline"],
                   r.get("round_ratio", ""), "*" if r["pareto"] == "1" else ""]))


def peers(d):
    print(row(["method", "problem", "median", "p99", "max error vs Ipopt 1e-10", "failures",
               "ratio to Ipopt (exact Hessian)", "the same (rounds)", "front"]))
    print("|---" * 9 + "|")
    for r in read(os.path.join(d, "peers.csv")):
        print(row(["`%s`" % r["method"], r["input_set"], t(r["median_ns"]), t(r["p99_ns"]),
                   e(r["max_error"]), fails(r), r["ratio_to_baseline"], r.get("round_ratio", ""),
                   "*" if r["pareto"] == "1" else ""]))


def rounds(r):
    return [float(x) for x in r["round_ns"].split(";")] if r.get("round_ns") else []


def round_ratio(a, b):
    """Median over rounds of a's round median / b's (both timed in the same rounds)."""
    ra, rb = rounds(a), rounds(b)
    if not ra or len(ra) != len(rb):
        return None
    q = sorted(x / y for x, y in zip(ra, rb))
    n = len(q)
    return q[n // 2] if n % 2 else 0.5 * (q[n // 2 - 1] + q[n // 2])


def ratios(d):
    """Section 6's table: realtime against NLopt SLSQP and Ipopt at each level (binding
    targets, tolerance 1e-9), as the ratio of medians and as the median of per-round
    ratios."""
    rs = {r["method"]: r for r in read(os.path.join(d, "planner.csv"))}
    print(row(["level", "realtime", "NLopt SLSQP", "Ipopt", "SLSQP / realtime (medians; rounds)",
               "Ipopt / realtime (medians; rounds)"]))
    print("|---" * 6 + "|")

    def x(q):
        return ("%.0f×" if q >= 100 else "%.3g×") % q

    def pair(a, b):
        rr = round_ratio(a, b)
        return "%s; %s" % (x(float(a["median_ns"]) / float(b["median_ns"])), x(rr) if rr else "-")

    for lv in ("linear", "plane", "surface"):
        rt, sq, ip = (rs.get("%s-%s-1e-09" % (b, lv)) for b in ("realtime", "nlopt-slsqp", "ipopt"))
        if not (rt and sq and ip):
            continue
        print(row([lv, t(rt["median_ns"]), t(sq["median_ns"]), t(ip["median_ns"]), pair(sq, rt),
                   pair(ip, rt)]))
    print()
    print(row(["level", "direct chain (reachable)", "/ linear's (medians; rounds)",
               "warm trace, a row", "/ its direct chain (medians; rounds)"]))
    print("|---" * 5 + "|")
    lin = rs.get("fastpath-linear")
    for lv in ("linear", "plane", "surface"):
        fp, tr = rs.get("fastpath-" + lv), rs.get("trace-realtime-" + lv)
        if not (fp and tr and lin):
            continue
        print(row([lv, t(fp["median_ns"]), pair(fp, lin), t(tr["median_ns"]), pair(tr, fp)]))


def levels(d):
    print(row(["scene", "backend", "targets", "size", "level", "error bound (ρ) [mm]",
               "median", "pose error [mm or deg]", "time / auto"]))
    print("|---" * 9 + "|")
    for r in read(os.path.join(d, "levels.csv")):
        size = "%.3g mm, %.3g°" % (float(r["trans_mm"]), float(r["rot_deg"]))
        lev = r["level"] + (" **(auto)**" if r["is_auto"] == "1" else "")
        print(row([r["scene"], r["backend"], r["targets"], size, lev, e(r["bound_mm"]),
                   t(r["median_ns"]), e(r["max_error"]), r["time_ratio_to_auto"]]))


def stability(d):
    rows = read(os.path.join(d, "stability.csv"))
    m = OrderedDict()
    for r in rows:
        a = m.setdefault(r["method"], {"vs": 0, "ns": 0, "v": 0, "n": 0, "w": 0, "it": 0,
                                       "f": OrderedDict(), "cases": set(),
                                       "viol": 0.0, "cv": 0.0})
        a["cases"].add(r["case"])
        n, v = int(r["targets"]), int(r["verified"])
        a["n"] += n
        a["v"] += v
        if float(r["size"]) <= 31.7:
            a["ns"] += n
            a["vs"] += v
        a["w"] += int(r["wrong"])
        a["it"] = max(a["it"], int(r["max_iterations"] or 0))
        a["viol"] = max(a["viol"], float(r["max_limit_violation"]))
        if r["max_contact_violation_mm"]:
            a["cv"] = max(a["cv"], float(r["max_contact_violation_mm"]))
        for s in filter(None, r["failure_statuses"].split(";")):
            k, c = s.split(":")
            a["f"][k] = a["f"].get(k, 0) + int(c)
    print(row(["method", "verified, s ≤ 31.6", "verified, all s", "silent wrong",
               "max iterations", "failures by status", "max contact violation [mm]"]))
    print("|---" * 7 + "|")
    for k, a in m.items():
        f = ", ".join("%s %d" % (s, c) for s, c in
                      sorted(a["f"].items(), key=lambda x: (x[0] != "invalid-input", x[0])))
        print(row(["`%s`" % k, "%d/%d" % (a["vs"], a["ns"]), "%d/%d" % (a["v"], a["n"]),
                   str(a["w"]), str(a["it"]), f, "%.1e" % a["cv"]]))
    print()
    print("rows %d, plans %d, max_limit_violation %g" %
          (len(rows), sum(int(r["targets"]) for r in rows),
           max(float(r["max_limit_violation"]) for r in rows)))


def wrong(d):
    print(row(["case", "method", "s", "direction", "status", "iterations", "check",
               "error [mm or deg]"]))
    print("|---" * 8 + "|")
    for r in read(os.path.join(d, "stability_wrong.csv")):
        print(row([r["case"], "`%s`" % r["method"], "%.4g" % float(r["size"]), r["direction"],
                   r["status"], r["iterations"], r["check"], e(r["error"])]))


def main():
    d = sys.argv[1] if len(sys.argv) > 1 else "docs/figures"
    for name, fn in (("ik", ik), ("planner", planner), ("stability", stability),
                     ("stability_wrong", wrong), ("peers", peers), ("levels", levels),
                     ("ratios", ratios)):
        print("### %s\n" % name)
        try:
            fn(d)
        except FileNotFoundError as err:
            print("(not in this run: %s)" % err.filename)
        print()


if __name__ == "__main__":
    main()
