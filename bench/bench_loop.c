/* headplan-bench, family "loop": the control loop as it is run. On the layout of o->scene,
 * for each level (linear, plane, surface) and backend (realtime, nlopt-slsqp), three traces
 * of corrections, one plan a cycle:
 *   smooth  breathing: sinusoids of 200 cycles (2 mm in z, 0.8 mm in y, 0.6 deg pitch) over
 *           a slow drift in x;
 *   noisy   the same with uniform noise of +-0.1 mm / +-0.05 deg on every axis each cycle;
 *   step    a new seeded target (within +-3 mm, +-2 deg) every 300 cycles, held between.
 * Four planners run every trace, taking turns on each cycle (so a slow spell of the host
 * hits all four alike):
 *   free      rate limits off, each plan from the last answer (the headline numbers' plan);
 *   rate      every bladder's rate_max SA_LOOP_RATE_PA per plan (bench/loop_trace.h);
 *   measured  rate, and after each plan the pressures read back with +-SA_LOOP_NOISE_PA noise
 *             through hp_planner_set_measured (its own time kept apart);
 *   deadline  measured, with max_time o->loop_budget_us (--loop-budget-us, default
 *             BENCH_LOOP_BUDGET_US): overshoots are plans that took longer than the budget +
 *             LOOP_OVERSHOOT_US; overshoots_host those that took longer than
 *             the budget + LOOP_HOST_US, a stall no plan's own work explains (a whole plan on
 *             the step trace is ~10 us of work, what runs past a deadline a few us): the
 *             host's (on the shared VM of the docs, multiples of its 4 ms scheduler tick).
 * Per row: median, p99, p99.9 and max of the plan time (CLOCK_MONOTONIC around hp_plan), the
 * ratios of median and p99.9 to the free planner's on the same trace in the same run, the
 * statuses (held answers apart from call errors), and set_measured's median; what the rate
 * limits' exact window ends cost, counted (not timed): the ends solved per 1000 plans and
 * the closed-form pressure evaluations per end (the library's test counters,
 * planner/problem_setup.h), and the share of the slowest 1 % of plans (at or above the
 * p99) that solved at least one end. With o->repeat > 1 each trace runs that many times
 * (fresh planners each time) and every figure is over all the cycles; from 3 runs on also
 * the p99.9 of each cycle's median time over the runs (cycle_p999). o->loop_level and
 * o->loop_backend (>= 0) keep it to that level and backend. Writes DIR/loop.csv; prints a
 * summary. */
#include "bench/bench.h"
#include "bench/bench_timing.h"
#include "bench/bench_util.h"
#include "bench/loop_trace.h"
#include "cli/exit_codes.h"
#include "planner/problem_setup.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define LOOP_OVERSHOOT_US 5.0
#define LOOP_HOST_US 100.0
#define LOOP_CYCLES_FULL 3000
#define LOOP_CYCLES_QUICK 120

/* Cycles of one run of a trace. */
static long loop_cycles(const bench_options *o)
{
    return o->quick ? LOOP_CYCLES_QUICK : LOOP_CYCLES_FULL;
}
#define N_MODES 4
#define N_TRACES 3
#define N_LEVELS 3
#define N_BACKENDS 2
#define N_ROWS (N_LEVELS * N_BACKENDS * N_TRACES * N_MODES)

static const char *const mode_names[N_MODES] = {"free", "rate", "measured", "deadline"};
static const hp_level levels[N_LEVELS] = {HP_LEVEL_LINEAR, HP_LEVEL_PLANE, HP_LEVEL_SURFACE};
static const hp_backend backends[N_BACKENDS] = {HP_BACKEND_REALTIME, HP_BACKEND_NLOPT_SLSQP};

typedef struct {
    hp_level level;
    hp_backend backend;
    int trace, mode;
    long cycles;
    double med_us, p99_us, p999_us, max_us, ratio_med, ratio_p999, set_med_us;
    /* With o->repeat >= 3: the p99.9 over the cycles of each cycle's median time across
     * the repeats, and its ratio to the free planner's (NAN otherwise; see cycle_p999). */
    double p999_cyc_us, ratio_p999_cyc;
    double budget_us; /* the deadline planner's max_time [us]; NAN for the others */
    /* other: plan outcomes beside reached, closest and time-limit (a held answer: iteration
     * limit, solver error, ...); errors: calls (hp_plan, set_measured) that returned an error
     * code. Under a deadline the trajectory depends on where the clock stopped each plan, so
     * there other counts states the host's timing led to. */
    long reached, closest, time_limit, other, errors, rate_binding, overshoots, clamped;
    long overshoots_host;
    long ends, evals;        /* rate window ends solved, closed-form evaluations they spent */
    double slow_solving_pct; /* of the plans at or above the p99, % that solved an end */
} loop_row;

static int cmp_d(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Fills the row's percentiles [us] from t[0..n-1] (sorted into sorted[], t kept in cycle
 * order), and the share of the plans at or above the p99 whose flag solved[] is set. */
static void summarise(const double *t, const unsigned char *solved, long n, double *sorted,
                      loop_row *r)
{
    memcpy(sorted, t, sizeof *t * (size_t)n);
    qsort(sorted, (size_t)n, sizeof *sorted, cmp_d);
    r->med_us = bench_percentile(sorted, n, 0.5) * 1e-3;
    r->p99_us = bench_percentile(sorted, n, 0.99) * 1e-3;
    r->p999_us = bench_percentile(sorted, n, 0.999) * 1e-3;
    r->max_us = sorted[n - 1] * 1e-3;
    long slow = 0, slow_solving = 0;
    for (long j = 0; j < n; ++j)
        if (t[j] * 1e-3 >= r->p99_us) {
            ++slow;
            slow_solving += solved[j];
        }
    r->slow_solving_pct = slow ? 100.0 * (double)slow_solving / (double)slow : NAN;
}

/* The p99.9 [us] over the n cycles of each cycle's median time over the reps runs
 * (t[rep * n + j]); work holds n + reps doubles. Every run plans the same states (fresh
 * planners, the same seeded trace), so cycle j's plan is the same work in each, and a
 * stall of the host lands in one run's time of it, not in its median over three or more:
 * the tail of the plans' own cost, not of the host's interruptions. For the deadline
 * planner too, as an estimate: its runs plan the same states until the clock first cuts a
 * plan at another point, and from then on states of the same walk, so a cycle's median over
 * the runs still leaves out a stall that hit one run (no ratio: its runs do not plan the
 * same states). */
static double cycle_p999(const double *t, long n, int reps, double *work)
{
    double *cyc = work, *one = work + n;
    for (long j = 0; j < n; ++j) {
        for (int r = 0; r < reps; ++r) one[r] = t[r * n + j];
        qsort(one, (size_t)reps, sizeof *one, cmp_d);
        cyc[j] = bench_percentile(one, reps, 0.5);
    }
    qsort(cyc, (size_t)n, sizeof *cyc, cmp_d);
    return bench_percentile(cyc, n, 0.999) * 1e-3;
}

/* The buffers of a trace's run: per mode and cycle (N_MODES x cycles x repeats). */
typedef struct loop_buf {
    double *times, *set_times, *sorted;
    unsigned char *solved;
} loop_buf;

/* One run of a level × backend × trace: the four planners in turn on every cycle, cycles
 * rep·n .. rep·n + n − 1 of the rows' buffers (total cycles nt a mode). */
static int run_once(const bench_options *o, const hp_layout *L0, const hp_settings *s0,
                    hp_level level, hp_backend bk, int trace, loop_row *rows, const loop_buf *bf,
                    int rep, long nt)
{
    long n = loop_cycles(o);
    hp_planner *p[N_MODES] = {0};
    hp_layout L;
    sa_loop_layout(L0, &L);
    int rc = 0;
    for (int m = 0; m < N_MODES && rc == 0; ++m) {
        hp_settings s = *s0;
        s.backend = bk;
        s.level = level;
        s.use_rate_limits = m > 0;
        s.max_time = m == 3 ? o->loop_budget_us * 1e-6 : 10.0;
        rc = bench_planner_new(&L, &s, &p[m]);
    }
    sa_loop_walk w;
    sa_loop_walk_start(&w, trace);
    for (long j = 0; j < n && rc == 0; ++j) {
        double xi[6];
        sa_loop_walk_at(&w, j, xi);
        for (int mm = 0; mm < N_MODES; ++mm) {
            int m = j % 2 ? N_MODES - 1 - mm : mm; /* forwards, then backwards */
            loop_row *r = &rows[m];
            hp_result res;
            unsigned long n0 = hpi_test_rate_bound_solves(), e0 = hpi_test_rate_bound_evals();
            double t0 = bench_now_ns();
            hp_error e = hp_plan(p[m], xi, &res);
            double dt = bench_now_ns() - t0;
            unsigned long ds = hpi_test_rate_bound_solves() - n0;
            r->ends += (long)ds;
            r->evals += (long)(hpi_test_rate_bound_evals() - e0);
            bf->times[m * nt + rep * n + j] = dt;
            bf->solved[m * nt + rep * n + j] = ds > 0;
            if (e != HP_OK) ++r->errors;
            else if (res.status == HP_STATUS_REACHED || res.status == HP_STATUS_UNCOMMANDED)
                ++r->reached;
            else if (res.status == HP_STATUS_CLOSEST) ++r->closest;
            else if (res.status == HP_STATUS_TIME_LIMIT) ++r->time_limit;
            else ++r->other;
            for (int k = 0; k < res.n; ++k)
                if (res.bladders[k].binding & (HP_BIND_RATE_DOWN | HP_BIND_RATE_UP)) {
                    ++r->rate_binding;
                    break;
                }
            if (m == 3 && dt > (o->loop_budget_us + LOOP_OVERSHOOT_US) * 1e3) ++r->overshoots;
            if (m == 3 && dt > (o->loop_budget_us + LOOP_HOST_US) * 1e3) ++r->overshoots_host;
            if (m >= 2) {
                double P[HP_MAX_BLADDERS];
                unsigned cl = 0;
                sa_loop_readings(&res, &w.noise, P);
                t0 = bench_now_ns();
                hp_error es = hp_planner_set_measured(p[m], P, &cl);
                double dts = bench_now_ns() - t0;
                if (m == 2) bf->set_times[rep * n + j] = dts;
                if (es != HP_OK) ++r->errors;
                r->clamped += cl != 0;
            }
        }
    }
    for (int m = 0; m < N_MODES; ++m) hp_planner_destroy(p[m]);
    return rc;
}

/* One level × backend × trace, o->repeat times: the rows of its four modes. */
static int run_trace(const bench_options *o, const hp_layout *L0, const hp_settings *s0,
                     hp_level level, hp_backend bk, int trace, loop_row *rows, const loop_buf *bf)
{
    long nt = loop_cycles(o) * o->repeat;
    for (int m = 0; m < N_MODES; ++m) {
        loop_row *r = &rows[m];
        memset(r, 0, sizeof *r);
        r->level = level;
        r->backend = bk;
        r->trace = trace;
        r->mode = m;
        r->cycles = nt;
        r->budget_us = m == 3 ? o->loop_budget_us : NAN;
    }
    int rc = 0;
    for (int rep = 0; rep < o->repeat && rc == 0; ++rep)
        rc = run_once(o, L0, s0, level, bk, trace, rows, bf, rep, nt);
    if (rc != 0) return rc;
    for (int m = 0; m < N_MODES; ++m)
        summarise(bf->times + m * nt, bf->solved + m * nt, nt, bf->sorted, &rows[m]);
    long n = loop_cycles(o);
    for (int m = 0; m < N_MODES; ++m)
        rows[m].p999_cyc_us = o->repeat >= 3
                                  ? cycle_p999(bf->times + m * nt, n, o->repeat, bf->sorted)
                                  : NAN;
    for (int m = 0; m < N_MODES; ++m) {
        rows[m].ratio_med = rows[m].med_us / rows[0].med_us;
        rows[m].ratio_p999 = rows[m].p999_us / rows[0].p999_us;
        rows[m].ratio_p999_cyc = m < 3 ? rows[m].p999_cyc_us / rows[0].p999_cyc_us : NAN;
    }
    qsort(bf->set_times, (size_t)nt, sizeof *bf->set_times, cmp_d);
    double sm = bench_percentile(bf->set_times, nt, 0.5) * 1e-3;
    rows[2].set_med_us = rows[3].set_med_us = sm;
    rows[0].set_med_us = rows[1].set_med_us = NAN;
    return 0;
}

static void csv_row(const void *arg, int i, FILE *f)
{
    const loop_row *r = (const loop_row *)arg + i;
    fprintf(f,
            "%s,%s,%s,%s,%ld,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f,%ld,%ld,%ld,%ld,%ld,%ld,%ld,%ld,%g,"
            "%ld,%.1f,%.2f,%.1f,%.3f,%.3f\n",
            hp_level_name(r->level), hp_backend_name(r->backend), sa_loop_trace_name(r->trace),
            mode_names[r->mode], r->cycles, r->med_us, r->p99_us, r->p999_us, r->max_us,
            r->ratio_med, r->ratio_p999, r->set_med_us, r->reached, r->closest, r->time_limit,
            r->other, r->errors, r->rate_binding, r->clamped, r->overshoots, r->budget_us,
            r->overshoots_host, 1000.0 * (double)r->ends / (double)r->cycles,
            r->ends ? (double)r->evals / (double)r->ends : NAN, r->slow_solving_pct, r->p999_cyc_us,
            r->ratio_p999_cyc);
}

int bench_loop(const bench_options *o, const char *dir)
{
    hp_scene scene;
    int rc = bench_load_layout(o->scene, &scene);
    if (rc != 0) return rc;
    hp_settings s;
    hp_settings_default(&s);
    long nt = loop_cycles(o) * o->repeat;
    static loop_row rows[N_ROWS];
    loop_buf bf = {malloc(sizeof(double) * (size_t)(N_MODES * nt)),
                   malloc(sizeof(double) * (size_t)nt), malloc(sizeof(double) * (size_t)nt),
                   malloc((size_t)(N_MODES * nt))};
    if (!bf.times || !bf.set_times || !bf.sorted || !bf.solved) {
        free(bf.times);
        free(bf.set_times);
        free(bf.sorted);
        free(bf.solved);
        fprintf(stderr, "headplan-bench: loop: out of memory\n");
        return CLI_EXIT_SOFTWARE;
    }
    int nr = 0;
    for (int b = 0; b < N_BACKENDS && rc == 0; ++b)
        for (int l = 0; l < N_LEVELS && rc == 0; ++l)
            for (int t = 0; t < N_TRACES && rc == 0; ++t) {
                if ((o->loop_backend >= 0 && (int)backends[b] != o->loop_backend) ||
                    (o->loop_level >= 0 && (int)levels[l] != o->loop_level))
                    continue;
                fprintf(stderr, "bench loop: %s %s %s\n", hp_backend_name(backends[b]),
                        hp_level_name(levels[l]), sa_loop_trace_name(t));
                rc = run_trace(o, &scene.layout, &s, levels[l], backends[b], t, rows + nr, &bf);
                nr += N_MODES;
            }
    free(bf.times);
    free(bf.set_times);
    free(bf.sorted);
    free(bf.solved);
    if (rc != 0) return rc;
    rc = bench_save_csv(
        dir, "loop.csv",
        "level,backend,trace,mode,cycles,median_us,p99_us,p999_us,max_us,"
        "ratio_median,ratio_p999,set_measured_median_us,reached,closest,"
        "time_limit,other,errors,rate_binding,clamped,overshoots,budget_us,overshoots_host,"
        "ends_per_1000,evals_per_end,slow_solving_pct,p999_cycle_median_us,"
        "ratio_p999_cycle_median",
        csv_row, rows, nr);
    printf("loop (rate %g Pa/plan, measured noise +-%g Pa, deadline %g us; ratios to the "
           "free plan of the same trace):\n",
           SA_LOOP_RATE_PA, SA_LOOP_NOISE_PA, o->loop_budget_us);
    printf("%-8s %-12s %-7s %-9s %8s %8s %8s %8s %6s %6s %7s %5s %5s %5s %6s %5s %7s\n", "level",
           "backend", "trace", "mode", "med_us", "p99_us", "p999_us", "max_us", "x_med", "x_p999",
           "set_us", "tlim", "over", "ohost", "ends/k", "slow%", "x_p999c");
    for (int i = 0; i < nr; ++i) {
        const loop_row *r = &rows[i];
        printf("%-8s %-12s %-7s %-9s %8.2f %8.2f %8.2f %8.1f %6.2f %6.2f %7.2f %5ld %5ld %5ld "
               "%6.0f %5.0f %7.2f\n",
               hp_level_name(r->level), hp_backend_name(r->backend), sa_loop_trace_name(r->trace),
               mode_names[r->mode], r->med_us, r->p99_us, r->p999_us, r->max_us, r->ratio_med,
               r->ratio_p999, r->set_med_us, r->time_limit, r->overshoots, r->overshoots_host,
               1000.0 * (double)r->ends / (double)r->cycles, r->slow_solving_pct,
               r->ratio_p999_cyc);
    }
    return rc;
}
