#!/usr/bin/python3
"""The SciPy SLSQP peer of `headplan-bench --only peers` (docs/benchmarks.md).

The planner's NLP as a researcher would first write it with SciPy, at the linear contact
level, from the problem data headplan exports (JSON, mm and degrees):

    variables  x = [xi (6: mm, mm, mm, deg, deg, deg), ri (n inner radii, mm)]
    minimise   sum_i w_i (xi_i - d_i)^2
    subject to ro(ri_k) - (rho0_k + J_k . xi) = 0,   ro(ri) = cbrt(Ro^3 - Ri^3 + ri^3)
               ri_lo_k <= ri_k <= ri_hi_k

Two variants: "analytic" (gradient and constraint Jacobian given) and "fd" (SciPy's finite
differences). Each target is solved `repeats` times from the same cold start (xi = 0,
ri = Ri); the per-target time is the median of the repeats (time.perf_counter_ns around
minimize only).

usage: /usr/bin/python3 scipy_peer.py PROBLEM.json OUT.csv
Writes OUT.csv: variant,target,success,nit,time_ns,x0..x{5+n}. Exit 2 on bad usage, 3 when
SciPy is missing (message on stderr).
"""
import json
import statistics
import sys
import time

try:
    import numpy as np
    from scipy.optimize import minimize
except ImportError as e:  # the bench checks first; say it clearly anyway
    sys.stderr.write("scipy_peer.py: SciPy/NumPy not importable by %s: %s\n" % (sys.executable, e))
    sys.exit(3)


def solve(p, d, analytic):
    n = p["n"]
    w = np.array(p["w"])
    J = np.array(p["J"])
    rho0 = np.array(p["rho0"])
    Ri = np.array(p["Ri"])
    Ro = np.array(p["Ro"])
    d = np.array(d)
    k3 = Ro ** 3 - Ri ** 3

    def f(x):
        r = x[:6] - d
        return float(np.sum(w * r * r))

    def grad(x):
        g = np.zeros(6 + n)
        g[:6] = 2.0 * w * (x[:6] - d)
        return g

    def ro(ri):
        return np.cbrt(k3 + ri ** 3)

    def c(x):
        return ro(x[6:]) - (rho0 + J @ x[:6])

    def cjac(x):
        ri = x[6:]
        A = np.zeros((n, 6 + n))
        A[:, :6] = -J
        A[np.arange(n), 6 + np.arange(n)] = (ri / ro(ri)) ** 2
        return A

    x0 = np.concatenate([np.zeros(6), Ri])
    bounds = [(None, None)] * 6 + list(zip(p["ri_lo"], p["ri_hi"]))
    cons = {"type": "eq", "fun": c}
    kw = {}
    if analytic:
        cons["jac"] = cjac
        kw["jac"] = grad
    t0 = time.perf_counter_ns()
    res = minimize(f, x0, method="SLSQP", bounds=bounds, constraints=[cons],
                   options={"ftol": p["ftol"], "maxiter": p["maxiter"]}, **kw)
    dt = time.perf_counter_ns() - t0
    return res, dt


def main():
    if len(sys.argv) != 3:
        sys.stderr.write("usage: scipy_peer.py PROBLEM.json OUT.csv\n")
        return 2
    with open(sys.argv[1]) as fh:
        p = json.load(fh)
    rows = []
    for variant, analytic in (("analytic", True), ("fd", False)):
        for k, d in enumerate(p["targets"]):
            times = []
            for _ in range(max(1, p["repeats"])):
                res, dt = solve(p, d, analytic)
                times.append(dt)
            x = ",".join("%.17g" % v for v in res.x)
            rows.append("%s,%d,%d,%d,%d,%s" % (variant, k, 1 if res.success else 0,
                                                int(res.nit), int(statistics.median(times)), x))
    with open(sys.argv[2], "w") as fh:
        n = p["n"]
        fh.write("variant,target,success,nit,time_ns," +
                 ",".join("x%d" % i for i in range(6 + n)) + "\n")
        fh.write("\n".join(rows) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
