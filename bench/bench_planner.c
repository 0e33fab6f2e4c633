/* headplan-bench, family "planner": every backend × contact fidelity level × tolerance, and
 * the direct-chain fast path, on the same targets of one layout scene.
 *
 * Targets: a fixed set (seeded, independent of --seed) in two groups. "Binding" targets
 * (uniform in ±6 mm, ±4° per axis) make a pressure or stretch limit bind, so a solver runs;
 * every backend row is measured on them. "Reachable" targets (±0.5 mm, ±0.3°) are answered
 * by the direct chain alone; the fast-path rows are measured on them.
 *
 * Accuracy, always through the exact model: the returned pressures go through the bladder
 * FK (pressure -> inner radius), the volume law (-> outer radius) and the contact FK at the
 * SURFACE level (-> pose). max_error is the largest difference, in mm or degrees over the
 * six axes, between that pose and the reference answer's (Ipopt, surface level, tolerance
 * 1e-10, sent through the same round trip). model_error is the largest difference between
 * that pose and the pose the method claimed (result.achieved): what its fidelity level
 * costs. max_violation is the worst pressure or stretch limit violation as a fraction of
 * the limit's span (the planner promises 0). Every plan is cold: hp_planner_reset before
 * each, warm start off, so the order of the targets does not matter; except on the
 * "trace" rows: the realtime backend at each level with warm start on, walking a drift
 * (N_TRACE rows, in order, no reset) from the nominal pose out to a correction where
 * limits bind and back, as the control loop plans it.
 *
 * What restarts cost (docs/planner.md, Restarts): Ipopt and NLopt SLSQP at the surface level,
 * tolerance 1e-9, with restarts 0 (one start, "-r0") beside their default rows, on the
 * binding targets and on the reachable ones ("-reach": the direct chain answers them, so no
 * restart runs), timed in the same rounds as every other row. */
#include "cli/cli_args.h"
#include "bench/bench.h"
#include "bench/bench_settings.h"
#include "bench/bench_timing.h"
#include "bench/bench_util.h"
#include "cli/exit_codes.h"
#include "headplan/hp_planner.h"
#include "headplan/hp_scene.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define N_BIND_FULL 40
#define N_BIND_QUICK 4
#define N_REACH 40
/* The trace: xi(j) = (1 − cos 2πj/N)/2 · TRACE_PEAK (mm, deg), N_TRACE rows (a 40 s
 * cycle at 10 Hz; successive rows at most 0.05 mm / 0.01 deg apart). */
#define N_TRACE 400
#define N_TRACE_QUICK 40
#define N_TARGETS_MAX (N_BIND_FULL + N_REACH + N_TRACE)
#define REF_TOLERANCE 1e-10
#define TARGET_SEED 20261123u

/* Targets in SI: translations within ±mm, rotations within ±deg, per axis. */
static void make_targets(double (*t)[6], long n, double mm, double deg, uint64_t *s)
{
    for (long k = 0; k < n; ++k)
        for (int i = 0; i < 6; ++i) {
            double u = 2 * bench_urand(s) - 1;
            t[k][i] = i < 3 ? u * mm * 1e-3 : u * deg * (BENCH_PI / 180.0);
        }
}

typedef struct {
    hp_backend backend; /* HP_BACKEND_COUNT_: the fast path (realtime on reachable targets) */
    hp_level level;
    double tol;
    int trace;    /* 1: the warm trace */
    int restarts; /* settings.restarts; -1: the default */
    int reach;    /* 1: a backend row on the reachable targets */
} plan_method;

static int create(const hp_layout *L, hp_backend b, hp_level level, double tol, int warm,
                  int restarts, hp_planner **p)
{
    hp_settings s = bench_settings(b, level, tol, warm);
    if (restarts >= 0) s.restarts = restarts;
    hp_diag d;
    if (hp_planner_create(L, &s, p, &d) != HP_OK) {
        cli_fail(0, "bench", "planner (%s, %s, tolerance %g): %s", hp_backend_name(b),
                 hp_level_name(level), tol, d.text);
        return CLI_EXIT_SOFTWARE;
    }
    return 0;
}

/* The reference round-trip pose of every target. */
static int reference(const hp_layout *L, const double (*t)[6], long n, double (*ref)[6])
{
    hp_planner *p;
    int rc = create(L, HP_BACKEND_IPOPT, HP_LEVEL_SURFACE, REF_TOLERANCE, 0, -1, &p);
    for (long k = 0; k < n && rc == 0; ++k) {
        hp_result r;
        hp_planner_reset(p);
        if (hp_plan(p, t[k], &r) != HP_OK ||
            (r.status != HP_STATUS_REACHED && r.status != HP_STATUS_CLOSEST) ||
            bench_round_trip(L, HP_LEVEL_SURFACE, &r, ref[k], NULL) != HP_OK) {
            cli_fail(0, "bench", "the reference (ipopt, surface) failed on target %ld: %s", k,
                     hp_planner_error(p));
            rc = CLI_EXIT_SOFTWARE;
        }
    }
    hp_planner_destroy(p);
    return rc;
}

static void measure_accuracy(hp_planner *p, const hp_layout *L, const double (*t)[6],
                             const double (*ref)[6], long n, int warm, bench_row *row,
                             double *model_error)
{
    double worst = -1, model = 0, viol = 0;
    long wk = 0;
    const char *first_failure = NULL;
    row->failures = 0;
    for (long k = 0; k < n; ++k) {
        hp_result r;
        double xi[6];
        if (!warm || k == 0) hp_planner_reset(p);
        hp_error pe = hp_plan(p, t[k], &r);
        if (pe != HP_OK || (r.status != HP_STATUS_REACHED && r.status != HP_STATUS_CLOSEST) ||
            bench_round_trip(L, HP_LEVEL_SURFACE, &r, xi, NULL) != HP_OK) {
            if (!first_failure)
                first_failure = pe != HP_OK ? hp_error_name(pe)
                                : (r.status != HP_STATUS_REACHED && r.status != HP_STATUS_CLOSEST)
                                    ? hp_status_name(r.status)
                                    : "round-trip";
            row->failures++;
            continue;
        }
        double e = bench_pose_diff(xi, ref[k], NULL);
        double me = bench_pose_diff(xi, r.achieved, NULL);
        double v = bench_limit_violation(L, &r);
        if (e > worst) {
            worst = e;
            wk = k;
        }
        if (me > model) model = me;
        if (v > viol) viol = v;
    }
    row->inputs = n;
    row->max_error = worst < 0 ? NAN : worst;
    row->max_violation = viol;
    *model_error = model;
    /* The first failure's status says why (e.g. "iteration-limit"). */
    snprintf(row->worst, sizeof row->worst, "target=%ld%s%s", wk,
             first_failure ? ";first_failure=" : "", first_failure ? first_failure : "");
}

int bench_planner(const bench_options *o, bench_table *t)
{
    hp_scene scene;
    hp_diag d;
    if (hp_scene_file_kind(o->scene) != HP_SCENE_LAYOUT) {
        cli_fail(0, "bench", "--scene: %s: not a layout scene", o->scene);
        return CLI_EXIT_DATAERR;
    }
    if (hp_scene_load(o->scene, &scene, &d) != HP_OK) {
        cli_fail(0, "bench", "--scene: %s", d.text);
        return CLI_EXIT_NOINPUT;
    }
    const hp_layout *L = &scene.layout;
    static double targets[N_TARGETS_MAX][6], ref[N_TARGETS_MAX][6];
    static long perm_bind[N_BIND_FULL], perm_reach[N_REACH];
    long n_bind = o->quick ? N_BIND_QUICK : N_BIND_FULL, n_reach = o->quick ? 4 : N_REACH;
    uint64_t s = TARGET_SEED;
    make_targets(targets, N_BIND_FULL, 6.0, 4.0, &s);
    make_targets(targets + N_BIND_FULL, N_REACH, 0.5, 0.3, &s);
    long n_trace = o->quick ? N_TRACE_QUICK : N_TRACE;
    double(*trace)[6] = targets + N_BIND_FULL + N_REACH;
    static const double peak[6] = {6.0, 3.6, -4.5, 1.5, 0.6, -0.9}; /* mm, deg */
    for (long j = 0; j < n_trace; ++j) {
        double f = 0.5 * (1.0 - cos(2.0 * BENCH_PI * (double)j / (double)n_trace));
        for (int i = 0; i < 6; ++i) trace[j][i] = f * peak[i] * (i < 3 ? 1e-3 : BENCH_PI / 180.0);
    }
    bench_shuffle(perm_bind, n_bind, o->seed);
    bench_shuffle(perm_reach, n_reach, o->seed);

    fprintf(stderr, "bench planner: reference answers (ipopt, surface, tolerance %g)\n",
            REF_TOLERANCE);
    int rc = reference(L, (const double(*)[6])targets, n_bind, ref);
    if (rc == 0)
        rc = reference(L, (const double(*)[6])targets + N_BIND_FULL, n_reach, ref + N_BIND_FULL);
    if (rc == 0) rc = reference(L, (const double(*)[6])trace, n_trace, ref + N_BIND_FULL + N_REACH);
    if (rc) return rc;

    plan_method ms[64];
    int nm = 0;
    static const hp_level levels[] = {HP_LEVEL_LINEAR, HP_LEVEL_PLANE, HP_LEVEL_SURFACE};
    static const double tols[] = {1e-4, 1e-9};
    for (int l = 0; l < 3; ++l)
        ms[nm++] = (plan_method){HP_BACKEND_COUNT_, levels[l], 1e-9, 0, -1, 0};
    for (int l = 0; l < 3; ++l)
        ms[nm++] = (plan_method){HP_BACKEND_REALTIME, levels[l], 1e-9, 1, -1, 0};
    for (int b = 0; b < HP_BACKEND_COUNT_; ++b)
        for (int l = 0; l < 3; ++l)
            for (int k = 0; k < 2; ++k)
                ms[nm++] = (plan_method){(hp_backend)b, levels[l], tols[k], 0, -1, 0};
    static const hp_backend restarting[] = {HP_BACKEND_IPOPT, HP_BACKEND_NLOPT_SLSQP};
    for (int b = 0; b < 2; ++b) {
        ms[nm++] = (plan_method){restarting[b], HP_LEVEL_SURFACE, 1e-9, 0, 0, 0};
        ms[nm++] = (plan_method){restarting[b], HP_LEVEL_SURFACE, 1e-9, 0, -1, 1};
        ms[nm++] = (plan_method){restarting[b], HP_LEVEL_SURFACE, 1e-9, 0, 0, 1};
    }

    /* Every method's planner is created and its accuracy measured first; then all are timed
     * together, in rounds (bench_time_set), so that a slow spell of the host falls on every
     * method alike. The planners stay alive until the last round. */
    static hp_planner *planners[64];
    static bench_plan_ctx ctx[64];
    static bench_timed timed[64];
    size_t rowi[64]; /* row indices: adding rows may move the table */
    int made = 0;
    for (int i = 0; i < nm && rc == 0; ++i) {
        const plan_method *m = &ms[i];
        int fast = m->backend == HP_BACKEND_COUNT_, tr = m->trace, reach = fast || m->reach;
        bench_row *row = bench_table_add(t);
        if (!row) {
            cli_fail(0, "bench", "out of memory");
            rc = CLI_EXIT_SOFTWARE;
            break;
        }
        rowi[i] = t->n - 1;
        snprintf(row->family, sizeof row->family, "planner");
        snprintf(row->input_set, sizeof row->input_set, "%s",
                 reach ? "reachable"
                 : tr  ? "trace"
                       : "binding");
        if (tr) {
            snprintf(row->method, sizeof row->method, "trace-realtime-%s", hp_level_name(m->level));
            snprintf(row->variant, sizeof row->variant, "warm-trace");
            snprintf(row->parameter, sizeof row->parameter, "%s", hp_level_name(m->level));
        } else if (fast) {
            snprintf(row->method, sizeof row->method, "fastpath-%s", hp_level_name(m->level));
            snprintf(row->variant, sizeof row->variant, "fast-path");
            snprintf(row->parameter, sizeof row->parameter, "%s", hp_level_name(m->level));
        } else {
            snprintf(row->method, sizeof row->method, "%s-%s-%.0e%s%s", hp_backend_name(m->backend),
                     hp_level_name(m->level), m->tol, m->reach ? "-reach" : "",
                     m->restarts == 0 ? "-r0" : "");
            snprintf(row->variant, sizeof row->variant, "%s", hp_backend_name(m->backend));
            snprintf(row->parameter, sizeof row->parameter, "%s/%.0e", hp_level_name(m->level),
                     m->tol);
        }
        fprintf(stderr, "bench planner: [%2d/%d] %-24s", i + 1, nm, row->method);
        if ((rc = create(L, fast ? HP_BACKEND_REALTIME : m->backend, m->level, m->tol, tr,
                         m->restarts, &planners[i])))
            break;
        made = i + 1;
        long off = reach ? N_BIND_FULL : tr ? N_BIND_FULL + N_REACH : 0;
        const double(*tg)[6] = (const double(*)[6])targets + off;
        long n = reach ? n_reach : tr ? n_trace : n_bind;
        measure_accuracy(planners[i], L, tg, (const double(*)[6])ref + off, n, tr, row,
                         &row->model_error);
        ctx[i] = (bench_plan_ctx){planners[i], tg, n, reach ? perm_reach : tr ? NULL : perm_bind,
                                  0,           tr};
        timed[i] = (bench_timed){.fn = bench_plan_batch, .ctx = &ctx[i]};
        fprintf(stderr, "  max error %.2e  failures %ld\n", row->max_error, row->failures);
    }
    if (rc == 0) {
        fprintf(stderr, "bench planner: timing %d methods in %d rounds\n", nm, o->rounds);
        if (bench_time_set(o, timed, nm) != 0) rc = CLI_EXIT_SOFTWARE;
    }
    for (int i = 0; i < nm && rc == 0; ++i) {
        bench_row *row = &t->rows[rowi[i]];
        bench_row_set_timing(row, &timed[i].out);
        fprintf(stderr, "bench planner: %-24s %12.0f ns\n", row->method, row->median_ns);
    }
    for (int i = 0; i < made; ++i) hp_planner_destroy(planners[i]);
    t->baseline = "ipopt-surface-1e-09";
    return rc;
}
