/* The one place the benchmark lab builds planner settings, so every family (and the
 * backend timing program) measures methods under the same budgets. */
#ifndef BENCH_SETTINGS_H
#define BENCH_SETTINGS_H

#include "headplan/hp_planner.h"

/* A budget generous enough that it never decides a benchmark's answer: iterations
 * (COBYLA counts evaluations, hence more) and seconds of the plan's wall time. */
#define BENCH_MAX_ITER 3000
#define BENCH_MAX_ITER_COBYLA 5000
#define BENCH_MAX_TIME_S 5.0

/* Defaults, then the backend, level and pose tolerance under test, warm start on or off,
 * and the lab's budgets. */
static inline hp_settings bench_settings(hp_backend b, hp_level l, double tol, int warm)
{
    hp_settings s;
    hp_settings_default(&s);
    s.backend = b;
    s.level = l;
    s.tolerance = tol;
    s.warm_start = warm;
    s.max_iter = b == HP_BACKEND_NLOPT_COBYLA ? BENCH_MAX_ITER_COBYLA : BENCH_MAX_ITER;
    s.max_time = BENCH_MAX_TIME_S;
    return s;
}

#endif
