/* headplan-bench-backends: rough timings of the general-purpose backends on the default
 * layout, through the core/backend contract (part of the benchmark lab; docs/backends.md
 * gives the command). Prints a Markdown table, one row
 * per case: backend, level, target set, start, median CPU and median / p90 / max wall time
 * per solve, mean iterations (NLopt: evaluations), number not converged, worst pose
 * difference from Ipopt's cold answer (mm or deg). */
#define _POSIX_C_SOURCE 199309L
#include "planner/backend_common.h"
#include "tests/support/backend_fixture.h"
#include "bench/bench_settings.h"

#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#define N 300

static double clock_s(clockid_t c)
{
    struct timespec t;
    clock_gettime(c, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static unsigned long long rng = 88172645463325252ULL;
static double urand(void) /* xorshift64: seeded, reproducible */
{
    rng ^= rng << 13;
    rng ^= rng >> 7;
    rng ^= rng << 17;
    return (double)(rng >> 11) / 9007199254740992.0;
}

static int cmp(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double targets[N][6];
static double ref[N][HP_PROBLEM_NX_MAX];

static void run(const hp_backend_ops *ops, hp_level level, const char *set, double tol, int warm,
                int is_ref)
{
    hp_layout L;
    if (fx_layout(&L) != HP_OK) exit(1);
    hp_problem pb;
    hp_geom G;
    if (fx_problem(&L, &G, level, targets[0], &pb) != HP_OK) exit(1);
    /* The backend is chosen through ops; level is that of the problem pb. */
    hp_settings s = bench_settings(HP_BACKEND_IPOPT, level, tol, warm);
    void *st;
    if (ops->create(&st, &pb, &s, NULL) != HP_OK) exit(1);
    double t[N], cpu[N], x[HP_PROBLEM_NX_MAX], prev[HP_PROBLEM_NX_MAX], x0[HP_PROBLEM_NX_MAX] = {0};
    for (int k = 0; k < pb.n; k++) x0[6 + k] = FX_RI * 1e3;
    memcpy(prev, x0, sizeof prev);
    int fails = 0;
    long iters = 0;
    double worst = 0.0;
    for (int i = 0; i < N; i++) {
        memcpy(pb.d, targets[i], sizeof pb.d);
        hp_backend_result r;
        double t0 = clock_s(CLOCK_MONOTONIC), c0 = clock_s(CLOCK_THREAD_CPUTIME_ID);
        hp_error e = ops->solve(st, &pb, warm ? prev : x0, x, &r, NULL);
        t[i] = clock_s(CLOCK_MONOTONIC) - t0;
        cpu[i] = clock_s(CLOCK_THREAD_CPUTIME_ID) - c0;
        if (e != HP_OK || !r.converged) fails++;
        iters += r.iterations;
        memcpy(prev, x, sizeof prev);
        if (is_ref) memcpy(ref[i], x, sizeof ref[i]);
        else
            for (int j = 0; j < 6; j++) worst = fmax(worst, fabs(x[j] - ref[i][j]));
    }
    ops->destroy(st);
    qsort(t, N, sizeof *t, cmp);
    qsort(cpu, N, sizeof *cpu, cmp);
    printf("| %s | %s | %s | %s | %.0e | %.0f | %.0f | %.0f | %.0f | %.1f | %d | %.1e |\n",
           ops->name, hp_level_name(level), set, warm ? "warm" : "cold", tol, 1e6 * cpu[N / 2],
           1e6 * t[N / 2], 1e6 * t[N * 9 / 10], 1e6 * t[N - 1], (double)iters / N, fails, worst);
}

static void suite(hp_level level, const char *set)
{
    run(&hpi_backend_ipopt_ops, level, set, 1e-9, 0, 1);
    run(&hpi_backend_ipopt_ops, level, set, 1e-9, 1, 0);
    run(&hpi_backend_nlopt_slsqp_ops, level, set, 1e-9, 0, 0);
    run(&hpi_backend_nlopt_cobyla_ops, level, set, 1e-7, 0, 0);
}

int main(void)
{
    printf("| backend | level | targets | start | tol | median CPU µs | median wall µs | "
           "p90 wall µs | max wall µs | mean iters | not converged | max pose diff from "
           "Ipopt |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    /* Reachable: a smooth trajectory (for the warm starts) of ±1 mm / ±0.5°. */
    for (int i = 0; i < N; i++)
        for (int j = 0; j < 6; j++)
            targets[i][j] = (j < 3 ? 1.0 : 0.5) * sin(0.05 * i * (1.0 + 0.3 * j) + j);
    suite(HP_LEVEL_LINEAR, "reachable");
    suite(HP_LEVEL_SURFACE, "reachable");
    /* Random, mostly beyond reach: ±8 mm / ±4°. */
    for (int i = 0; i < N; i++)
        for (int j = 0; j < 6; j++) targets[i][j] = (j < 3 ? 8.0 : 4.0) * (2.0 * urand() - 1.0);
    suite(HP_LEVEL_SURFACE, "unreachable");
    return 0;
}
