/* Where the loop benchmark's slowest plans spend their time, by phase, built as
 * build/headplan-bench-phases:
 *   headplan-bench-phases SCENE LEVEL TRACE CYCLES REPEATS TOP
 * LEVEL 0 linear, 1 plane, 2 surface; TRACE smooth, noisy or step (bench/loop_trace.h, the
 * loop benchmark's); CYCLES 1..100000, REPEATS 1..50, TOP 1..100. Three realtime planners take
 * turns on every cycle as in the loop benchmark: free (no rate limits), rate (every bladder's
 * rate_max 500 Pa a plan) and measured (rate, and its pressures read back with ±3 Pa of
 * seeded noise through hp_planner_set_measured). The run is repeated REPEATS times with new
 * planners; per cycle the median over the repeats of each plan's time and of the time inside
 * each phase, the library's internal calls that the link wraps (-Wl,--wrap, CMakeLists.txt):
 *   resolve  hpi_setup_rate_resolve: a rate window's ends made exact (root finds)
 *   qp       hpi_qp_solve_lazy and hpi_qp_resume_lazy: the realtime backend's QP, with its
 *            stops at stand-in rows
 *   answer   hpi_plan_answer_from_pose: the answer's rows (radii and pressures)
 *   setup    hpi_setup_cycle_bounds_lazy: the rate windows' stand-ins at a plan's start
 *   other    the rest of the plan
 * Prints, for each planner, the median cycle and the TOP slowest cycles (by median time): the
 * cycle, its times in ns and how many calls each phase made; then each phase's calls over the
 * whole trace (the counts depend on the trace and the planners alone; the times, and so which
 * cycles are listed, on the host). The clock is the processor's time-stamp
 * counter on x86-64 (a read costs a few ns, where CLOCK_MONOTONIC's ~20 ns would weigh on a
 * 3 µs plan with ~30 reads), scaled to ns against CLOCK_MONOTONIC over 0.1 s; elsewhere
 * CLOCK_MONOTONIC. The phases nest in the plan, not in each other. */
#define _POSIX_C_SOURCE 200809L
#include "headplan/headplan.h"
#include "bench/loop_trace.h"
#include "bench/standalone.h"
#include "planner/problem_setup.h"
#include "planner/qp.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#if defined(__x86_64__)
#include <x86intrin.h>
#endif

enum { PH_RESOLVE, PH_QP, PH_ANSWER, PH_SETUP, N_PH };
enum { N_PLANNERS = 3, MAX_REPEATS = 50, MAX_TOP = 100 };
static const char *const phase_names[N_PH] = {"resolve", "qp", "answer", "setup"};
static const char *const planner_names[N_PLANNERS] = {"free", "rate", "measured"};

static uint64_t ticks(void)
{
#if defined(__x86_64__)
    return __rdtsc();
#else
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (uint64_t)ts.tv_sec * 1000000000u + (uint64_t)ts.tv_nsec;
#endif
}

/* ns per tick: the counter against CLOCK_MONOTONIC over 0.1 s (1 without the counter). */
static double ns_per_tick(void)
{
#if defined(__x86_64__)
    double t0 = sa_now();
    uint64_t c0 = ticks();
    while (sa_now() - t0 < 0.1) {}
    return (sa_now() - t0) * 1e9 / (double)(ticks() - c0);
#else
    return 1.0;
#endif
}

/* The current plan's ticks and calls in each phase (one plan at a time: no threads). */
static uint64_t in_phase[N_PH];
static unsigned calls[N_PH];

#define WRAP(ph, ret, name, params, args)                                                          \
    ret __real_##name params;                                                                      \
    ret __wrap_##name params;                                                                      \
    ret __wrap_##name params                                                                       \
    {                                                                                              \
        uint64_t t0 = ticks();                                                                     \
        ret r = __real_##name args;                                                                \
        in_phase[ph] += ticks() - t0;                                                              \
        ++calls[ph];                                                                               \
        return r;                                                                                  \
    }
WRAP(PH_RESOLVE, int, hpi_setup_rate_resolve, (hp_rate_lazy * z, int k, unsigned ends),
     (z, k, ends))
WRAP(PH_QP, hp_qp_status, hpi_qp_solve_lazy,
     (hp_qp * qp, const double *Lg, const int *guess, const unsigned char *lazy, int *hit,
      int max_iter, double feas_tol),
     (qp, Lg, guess, lazy, hit, max_iter, feas_tol))
WRAP(PH_QP, hp_qp_status, hpi_qp_resume_lazy,
     (hp_qp * qp, const unsigned char *lazy, int *hit, int max_iter, double feas_tol),
     (qp, lazy, hit, max_iter, feas_tol))
WRAP(PH_ANSWER, int, hpi_plan_answer_from_pose,
     (hp_planner * p, const double x[6], const double *rho_known, int direct, hp_result *res,
      double *clamp_mm),
     (p, x, rho_known, direct, res, clamp_mm))
WRAP(PH_SETUP, hp_error, hpi_setup_cycle_bounds_lazy, (hp_rate_lazy * z, hp_diag *d), (z, d))

/* One plan's record: total and phase ticks, phase calls. */
typedef struct rec {
    double t[1 + N_PH];
    unsigned n[N_PH];
} rec;

static int usage(void)
{
    fprintf(stderr, "usage: headplan-bench-phases SCENE LEVEL TRACE CYCLES REPEATS TOP\n"
                    "  LEVEL 0 linear, 1 plane, 2 surface; TRACE smooth, noisy or step;\n"
                    "  CYCLES 1..100000, REPEATS 1..50, TOP 1..100\n");
    return 64;
}

/* A whole number in [lo, hi] from a (sa_whole), or -1 (a message naming what on stderr). */
static long number(const char *what, const char *a, long lo, long hi)
{
    long v = sa_whole(a);
    if (v < lo || v > hi) {
        fprintf(stderr, "headplan-bench-phases: %s: '%s' is not a whole number in %ld..%ld\n", what,
                a, lo, hi);
        return -1;
    }
    return v;
}

/* The cycles' median times of one planner, by which its cycles are ranked (qsort has no
 * context argument; one ranking at a time). */
static const double *rank_key;
static int slower_first(const void *a, const void *b)
{
    double x = rank_key[*(const long *)a], y = rank_key[*(const long *)b];
    return (x < y) - (x > y);
}

/* Runs the trace REPEATS times into r[(planner · repeats + rep) · cycles + j]. */
static int run(const hp_layout *L0, int level, int trace, long cycles, int repeats, rec *r)
{
    for (int rep = 0; rep < repeats; ++rep) {
        hp_planner *p[N_PLANNERS];
        int rc = sa_loop_planners(L0, level, N_PLANNERS, "headplan-bench-phases", p);
        sa_loop_walk w;
        sa_loop_walk_start(&w, trace);
        for (long j = 0; j < cycles && rc == 0; ++j) {
            double xi[6];
            sa_loop_walk_at(&w, j, xi);
            for (int mm = 0; mm < N_PLANNERS && rc == 0; ++mm) {
                int m = j % 2 ? N_PLANNERS - 1 - mm : mm; /* forwards, then backwards */
                memset(in_phase, 0, sizeof in_phase);
                memset(calls, 0, sizeof calls);
                hp_result res;
                uint64_t t0 = ticks();
                hp_error e = hp_plan(p[m], xi, &res);
                uint64_t dt = ticks() - t0;
                if (e != HP_OK) {
                    fprintf(stderr, "headplan-bench-phases: cycle %ld: %s\n", j, hp_error_name(e));
                    rc = 70;
                    break;
                }
                rec *o = &r[((long)m * repeats + rep) * cycles + j];
                o->t[0] = (double)dt;
                for (int ph = 0; ph < N_PH; ++ph) {
                    o->t[1 + ph] = (double)in_phase[ph];
                    o->n[ph] = calls[ph];
                }
                if (m == 2) {
                    double P[HP_MAX_BLADDERS];
                    sa_loop_readings(&res, &w.noise, P);
                    if (hp_planner_set_measured(p[m], P, NULL) != HP_OK) rc = 70;
                }
            }
        }
        for (int m = 0; m < N_PLANNERS; ++m) hp_planner_destroy(p[m]);
        if (rc != 0) return rc;
    }
    return 0;
}

/* One cycle's line: its medians over the repeats (ns), other = total − the phases, and the
 * calls of the first repeat (every repeat makes the same). */
static void print_cycle(const rec *r, long cycles, int repeats, int m, long j, double npt,
                        const char *tag)
{
    double med[1 + N_PH], v[MAX_REPEATS] = {0};
    for (int c = 0; c <= N_PH; ++c) {
        for (int rep = 0; rep < repeats; ++rep)
            v[rep] = r[((long)m * repeats + rep) * cycles + j].t[c];
        med[c] = sa_median(v, (size_t)repeats) * npt;
    }
    double other = med[0];
    for (int ph = 0; ph < N_PH; ++ph) other -= med[1 + ph];
    const rec *o = &r[(long)m * repeats * cycles + j];
    printf("%-8s %-6s %6ld %8.0f", planner_names[m], tag, j, med[0]);
    for (int ph = 0; ph < N_PH; ++ph) printf(" %8.0f %3u", med[1 + ph], o->n[ph]);
    printf(" %8.0f\n", other);
}

int main(int argc, char **argv)
{
    if (argc != 7) return usage();
    int trace = sa_loop_trace_of(argv[3]);
    if (trace < 0) {
        fprintf(stderr, "headplan-bench-phases: TRACE: '%s' is not smooth, noisy or step\n",
                argv[3]);
        return 64;
    }
    long level = number("LEVEL", argv[2], 0, 2), cycles = number("CYCLES", argv[4], 1, 100000);
    long repeats = number("REPEATS", argv[5], 1, MAX_REPEATS);
    long top = number("TOP", argv[6], 1, MAX_TOP);
    if (level < 0 || cycles < 0 || repeats < 0 || top < 0) return 64;
    if (top > cycles) top = cycles;
    static hp_scene sc;
    hp_diag d = {{0}};
    if (hp_scene_load(argv[1], &sc, &d) != HP_OK) {
        fprintf(stderr, "headplan-bench-phases: %s\n", d.text);
        return 66;
    }
    rec *r = calloc((size_t)(N_PLANNERS * repeats * cycles), sizeof *r);
    double *tot = malloc((size_t)cycles * sizeof *tot);
    long *order = malloc((size_t)cycles * sizeof *order);
    if (!r || !tot || !order) {
        fprintf(stderr, "headplan-bench-phases: out of memory\n");
        free(r);
        free(tot);
        free(order);
        return 70;
    }
    int rc = run(&sc.layout, (int)level, trace, cycles, (int)repeats, r);
    double npt = rc == 0 ? ns_per_tick() : 0.0;
    if (rc == 0) {
        printf("# %s, level %ld, %s trace, %ld cycles, medians over %ld repeats (ns); per phase "
               "the time and the calls\n",
               argv[1], level, sa_loop_trace_name(trace), cycles, repeats);
        printf("%-8s %-6s %6s %8s", "planner", "rank", "cycle", "total");
        for (int ph = 0; ph < N_PH; ++ph) printf(" %8s %3s", phase_names[ph], "n");
        printf(" %8s\n", "other");
    }
    for (int m = 0; m < N_PLANNERS && rc == 0; ++m) {
        double v[MAX_REPEATS];
        for (long j = 0; j < cycles; ++j) {
            for (int rep = 0; rep < repeats; ++rep)
                v[rep] = r[((long)m * repeats + rep) * cycles + j].t[0];
            tot[j] = sa_median(v, (size_t)repeats);
            order[j] = j;
        }
        /* slowest first; the median cycle is the one ranked in the middle */
        rank_key = tot;
        qsort(order, (size_t)cycles, sizeof *order, slower_first);
        char tag[24];
        for (long a = 0; a < top; ++a) {
            snprintf(tag, sizeof tag, "%ld", a + 1);
            print_cycle(r, cycles, (int)repeats, m, order[a], npt, tag);
        }
        print_cycle(r, cycles, (int)repeats, m, order[cycles / 2], npt, "median");
        /* every phase's calls over the first repeat's trace: the same in every run */
        unsigned long sum[N_PH] = {0};
        for (long j = 0; j < cycles; ++j)
            for (int ph = 0; ph < N_PH; ++ph) sum[ph] += r[(long)m * repeats * cycles + j].n[ph];
        printf("%-8s %-6s", planner_names[m], "calls");
        for (int ph = 0; ph < N_PH; ++ph) printf(" %s %lu", phase_names[ph], sum[ph]);
        printf("\n");
    }
    free(r);
    free(tot);
    free(order);
    return rc;
}
