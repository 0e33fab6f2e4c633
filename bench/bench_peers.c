/* headplan-bench, family "peers": the same NLP solved by the peers docs/model.md §8 names, beside
 * headplan's own backends, on the same targets, in the same run.
 *
 * Problem: the planner's NLP at the LINEAR contact level (rho = rho0 + J·xi) on o->scene,
 * variables xi (mm, deg) and the n inner radii, bounds from the same limits. Targets: the
 * planner family's binding generator (uniform ±6 mm, ±4°, fixed seed), keeping only those
 * where the direct chain fails (Ipopt needed iterations), 40 (quick: 6).
 *
 * Rows (input set "linear-nlp"): ipopt-exact-linear (the BASELINE: exact Hessian, tolerance
 * 1e-9), ipopt-lbfgs-linear (Ipopt's limited-memory quasi-Newton Hessian, the
 * hp_planner_set_option "hessian_approximation" 1 peer), realtime-linear, nlopt-slsqp-linear,
 * scipy-slsqp (bench/scipy_peer.py, analytic gradients) and scipy-slsqp-fd (SciPy's finite
 * differences). Input set "surface-nlp": ipopt-exact-surface and ipopt-lbfgs-surface, against
 * a surface-level reference. max_error: the largest difference, mm or degrees, between a
 * method's pose and Ipopt's at tolerance 1e-10 on the same level. Times: headplan's methods
 * by the timing harness (cold plans, medians over batches); SciPy's by perf_counter_ns in
 * Python around minimize(), the median over targets of each target's median over repeats.
 * A SciPy answer counts as a failure when SciPy says it failed or its contact equalities
 * are off by more than 1e-6 mm. */
#define _POSIX_C_SOURCE 200809L
#include "cli/cli_args.h"
#include "bench/bench.h"
#include "bench/bench_report.h"
#include "bench/bench_timing.h"
#include "bench/bench_settings.h"
#include "bench/bench_util.h"
#include "cli/exit_codes.h"
#include "common/unconst.h"

#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define N_FULL 40
#define N_QUICK 6
#define N_CAND 400
#define TARGET_SEED 20261123u
#define REF_TOLERANCE 1e-10
#define SCIPY_CONTACT_TOL 1e-6 /* mm */

static hp_settings settings_of(hp_backend b, hp_level l, double tol)
{
    return bench_settings(b, l, tol, 0);
}

static bench_row *new_row(bench_table *t, const char *method, const char *variant,
                          const char *param, const char *set)
{
    bench_row *r = bench_table_add(t);
    if (!r) return NULL;
    snprintf(r->method, sizeof r->method, "%s", method);
    snprintf(r->family, sizeof r->family, "peers");
    snprintf(r->variant, sizeof r->variant, "%s", variant);
    snprintf(r->parameter, sizeof r->parameter, "%s", param);
    snprintf(r->input_set, sizeof r->input_set, "%s", set);
    return r;
}

/* Plans every target with p and compares with ref (scaled poses compared in mm/deg). */
static void accuracy(hp_planner *p, const hp_layout *L, const double (*tg)[6], long n,
                     const double (*ref)[6], bench_row *row)
{
    double worst = -1, viol = 0;
    long wk = 0;
    row->failures = 0;
    for (long k = 0; k < n; ++k) {
        hp_result r;
        hp_planner_reset(p);
        if (hp_plan(p, tg[k], &r) != HP_OK ||
            (r.status != HP_STATUS_REACHED && r.status != HP_STATUS_CLOSEST)) {
            row->failures++;
            continue;
        }
        double e = bench_pose_diff(r.achieved, ref[k], r.commanded);
        if (e > worst) worst = e, wk = k;
        double v = bench_limit_violation(L, &r);
        if (v > viol) viol = v;
    }
    row->inputs = n;
    row->max_error = worst < 0 ? NAN : worst;
    row->max_violation = viol;
    snprintf(row->worst, sizeof row->worst, "target=%ld", wk);
}

/* The problem data for scipy_peer.py (mm, degrees). Returns 0 or -1. */
static int write_problem(const char *path, const hp_layout *L, const bench_bounds *b,
                         const int commanded[6], const double (*tg)[6], long n, int repeats)
{
    double rho[HP_MAX_BLADDERS], J[HP_MAX_BLADDERS * 6], x0[6] = {0};
    if (hp_contact_eval(L, HP_LEVEL_LINEAR, x0, rho, J, NULL) != HP_OK) return -1;
    json_t *o = json_object(), *w = json_array(), *jj = json_array(), *r0 = json_array(),
           *Ri = json_array(), *Ro = json_array(), *lo = json_array(), *hi = json_array(),
           *ts = json_array();
    for (int i = 0; i < 6; ++i) json_array_append_new(w, json_real(commanded[i] ? 1.0 : 0.0));
    for (int k = 0; k < L->n; ++k) {
        json_t *row = json_array();
        for (int i = 0; i < 6; ++i)
            json_array_append_new(
                row, json_real(i < 3 ? J[k * 6 + i] : J[k * 6 + i] * 1e3 * BENCH_PI / 180));
        json_array_append_new(jj, row);
        json_array_append_new(r0, json_real(rho[k] * 1e3));
        json_array_append_new(Ri, json_real(L->bladders[k].iab.Ri * 1e3));
        json_array_append_new(Ro, json_real(L->bladders[k].iab.Ro * 1e3));
        json_array_append_new(lo, json_real(b->ri_lo[k] * 1e3));
        json_array_append_new(hi, json_real(b->ri_hi[k] * 1e3));
    }
    for (long t = 0; t < n; ++t) {
        json_t *row = json_array();
        for (int i = 0; i < 6; ++i)
            json_array_append_new(
                row, json_real(commanded[i] ? tg[t][i] * (i < 3 ? 1e3 : 180 / BENCH_PI) : 0.0));
        json_array_append_new(ts, row);
    }
    json_object_set_new(o, "n", json_integer(L->n));
    json_object_set_new(o, "w", w);
    json_object_set_new(o, "J", jj);
    json_object_set_new(o, "rho0", r0);
    json_object_set_new(o, "Ri", Ri);
    json_object_set_new(o, "Ro", Ro);
    json_object_set_new(o, "ri_lo", lo);
    json_object_set_new(o, "ri_hi", hi);
    json_object_set_new(o, "ftol", json_real(1e-12));
    json_object_set_new(o, "maxiter", json_integer(500));
    json_object_set_new(o, "repeats", json_integer(repeats));
    json_object_set_new(o, "targets", ts);
    int rc = json_dump_file(o, path,
                            JSON_INDENT(1) | JSON_PRESERVE_ORDER | JSON_REAL_PRECISION(17));
    json_decref(o);
    return rc == 0 ? 0 : -1;
}

static int cmp_dbl(const void *a, const void *b)
{
    return (*(const double *)a > *(const double *)b) - (*(const double *)a < *(const double *)b);
}

/* Reads scipy_peer.py's CSV into one row per variant. Returns 0 or an exit status. */
static int read_scipy(const char *path, const hp_layout *L, const bench_bounds *b,
                      const int commanded[6], long n, const double (*ref)[6], bench_table *t)
{
    static const char *const variants[2] = {"analytic", "fd"};
    FILE *f = fopen(path, "r");
    if (!f) {
        cli_fail(0, "bench", "peers: the SciPy peer wrote no '%s'", path);
        return CLI_EXIT_SOFTWARE;
    }
    double rho0[HP_MAX_BLADDERS], J[HP_MAX_BLADDERS * 6], z[6] = {0};
    hp_contact_eval(L, HP_LEVEL_LINEAR, z, rho0, J, NULL);
    bench_row *rows[2];
    double *times = calloc((size_t)n * 2, sizeof *times);
    long nt[2] = {0, 0}, seen[2] = {0, 0};
    double worst[2] = {-1, -1}, viol[2] = {0, 0};
    long wk[2] = {0, 0}, fails[2] = {0, 0};
    char line[4096];
    int rc = times ? 0 : CLI_EXIT_SOFTWARE;
    if (!fgets(line, sizeof line, f)) rc = CLI_EXIT_SOFTWARE;
    while (rc == 0 && fgets(line, sizeof line, f)) {
        char *p = line, *e;
        int v = strncmp(p, "analytic,", 9) == 0 ? 0 : strncmp(p, "fd,", 3) == 0 ? 1 : -1;
        if (v < 0) {
            rc = CLI_EXIT_SOFTWARE;
            break;
        }
        p = strchr(p, ',') + 1;
        long k = strtol(p, &e, 10), ok, nit;
        ok = strtol(e + 1, &e, 10);
        nit = strtol(e + 1, &e, 10);
        (void)nit;
        double tns = strtod(e + 1, &e), x[6 + HP_MAX_BLADDERS];
        for (int i = 0; i < 6 + L->n; ++i) x[i] = strtod(e + 1, &e);
        if (k < 0 || k >= n || !isfinite(tns)) {
            rc = CLI_EXIT_SOFTWARE;
            break;
        }
        seen[v]++;
        times[v * n + nt[v]++] = tns;
        /* Contact equalities and bounds of the SciPy answer (mm). */
        double cviol = 0, bviol = 0;
        for (int q = 0; q < L->n; ++q) {
            const hp_iab *m = &L->bladders[q].iab;
            double ri = x[6 + q], Ri = m->Ri * 1e3, Ro = m->Ro * 1e3;
            double ro = cbrt(Ro * Ro * Ro - Ri * Ri * Ri + ri * ri * ri), rho = rho0[q] * 1e3;
            for (int i = 0; i < 6; ++i)
                rho += (i < 3 ? J[q * 6 + i] : J[q * 6 + i] * 1e3 * BENCH_PI / 180) * x[i];
            cviol = fmax(cviol, fabs(ro - rho));
            double span = (b->ri_hi[q] - b->ri_lo[q]) * 1e3;
            bviol = fmax(bviol, fmax(b->ri_lo[q] * 1e3 - ri, ri - b->ri_hi[q] * 1e3) / span);
        }
        if (!ok || !(cviol <= SCIPY_CONTACT_TOL)) {
            fails[v]++;
            continue;
        }
        if (bviol > viol[v]) viol[v] = bviol;
        double xi[6];
        bench_to_si(x, xi);
        double err = bench_pose_diff(xi, ref[k], commanded);
        if (err > worst[v]) worst[v] = err, wk[v] = k;
    }
    fclose(f);
    if (rc == 0 && (seen[0] != n || seen[1] != n)) rc = CLI_EXIT_SOFTWARE;
    if (rc) {
        cli_fail(0, "bench", "peers: '%s' is malformed or incomplete", path);
        free(times);
        return rc;
    }
    for (int v = 0; v < 2; ++v) {
        char name[48];
        snprintf(name, sizeof name, v ? "scipy-slsqp-fd" : "scipy-slsqp");
        if (!(rows[v] = new_row(t, name, "scipy-slsqp", variants[v], "linear-nlp"))) {
            free(times);
            return CLI_EXIT_SOFTWARE;
        }
        qsort(times + v * n, (size_t)nt[v], sizeof *times, cmp_dbl);
        rows[v]->median_ns = bench_percentile(times + v * n, nt[v], 0.5);
        rows[v]->p99_ns = bench_percentile(times + v * n, nt[v], 0.99);
        rows[v]->max_error = worst[v] < 0 ? NAN : worst[v];
        rows[v]->max_violation = viol[v];
        rows[v]->failures = fails[v];
        rows[v]->inputs = n;
        rows[v]->samples = nt[v];
        rows[v]->batch = 1;
        snprintf(rows[v]->worst, sizeof rows[v]->worst, "target=%ld", wk[v]);
        fprintf(stderr, "bench peers: %-22s %12.0f ns  max error %.2e  failures %ld\n", name,
                rows[v]->median_ns, rows[v]->max_error, rows[v]->failures);
    }
    free(times);
    return 0;
}

int bench_peers(const bench_options *o, bench_table *t)
{
    hp_scene scene;
    int rc = bench_load_layout(o->scene, &scene);
    if (rc) return rc;
    const hp_layout *L = &scene.layout;
    bench_bounds b;
    if (bench_bounds_of(L, &b) != 0) {
        cli_fail(0, "bench", "peers: %s: a bladder has no valid radius interval", o->scene);
        return CLI_EXIT_DATAERR;
    }
    long want = o->quick ? N_QUICK : N_FULL, n = 0;
    static double tg[N_FULL][6], ref_lin[N_FULL][6], ref_sur[N_FULL][6];
    static long perm[N_FULL];
    int commanded[6] = {1, 1, 1, 1, 1, 1};
    hp_planner *pl, *ps;
    hp_settings sl = settings_of(HP_BACKEND_IPOPT, HP_LEVEL_LINEAR, REF_TOLERANCE);
    hp_settings ss = settings_of(HP_BACKEND_IPOPT, HP_LEVEL_SURFACE, REF_TOLERANCE);
    if ((rc = bench_planner_new(L, &sl, &pl))) return rc;
    if ((rc = bench_planner_new(L, &ss, &ps))) {
        hp_planner_destroy(pl);
        return rc;
    }
    fprintf(stderr, "bench peers: reference answers (ipopt, exact Hessian, tolerance %g)\n",
            REF_TOLERANCE);
    uint64_t s = TARGET_SEED;
    for (int c = 0; c < N_CAND && n < want; ++c) {
        double x[6];
        for (int i = 0; i < 6; ++i) {
            double u = 2 * bench_urand(&s) - 1;
            x[i] = i < 3 ? u * 6.0 * 1e-3 : u * 4.0 * (BENCH_PI / 180.0);
        }
        hp_result r1, r2;
        hp_planner_reset(pl);
        hp_planner_reset(ps);
        if (hp_plan(pl, x, &r1) != HP_OK || r1.iterations == 0 ||
            (r1.status != HP_STATUS_REACHED && r1.status != HP_STATUS_CLOSEST) ||
            hp_plan(ps, x, &r2) != HP_OK ||
            (r2.status != HP_STATUS_REACHED && r2.status != HP_STATUS_CLOSEST))
            continue;
        memcpy(tg[n], x, sizeof x);
        memcpy(ref_lin[n], r1.achieved, sizeof x);
        memcpy(ref_sur[n], r2.achieved, sizeof x);
        for (int i = 0; i < 6; ++i) commanded[i] = r1.commanded[i];
        ++n;
    }
    hp_planner_destroy(pl);
    hp_planner_destroy(ps);
    if (n < want) {
        cli_fail(0, "bench", "peers: only %ld of %ld binding targets found", n, want);
        return CLI_EXIT_SOFTWARE;
    }
    bench_shuffle(perm, n, o->seed);

    /* The SciPy peer first: a child process, so nothing of ours runs beside it. */
    char jpath[4200], cpath[4200];
    snprintf(jpath, sizeof jpath, "%s/peers_problem.json", o->out_dir);
    snprintf(cpath, sizeof cpath, "%s/peers_scipy.csv", o->out_dir);
    if (write_problem(jpath, L, &b, commanded, (const double(*)[6])tg, n, o->quick ? 1 : 5) != 0) {
        cli_fail(0, "bench", "cannot write '%s'", jpath);
        return CLI_EXIT_CANTCREAT;
    }
    fprintf(stderr, "bench peers: %s %s (%ld targets)\n", o->python, o->peer_script, n);
    char *const argv[] = {hpi_unconst(o->python), hpi_unconst(o->peer_script), jpath, cpath, NULL};
    int st = bench_run_child(argv, NULL, 0);
    if (st != 0) {
        cli_fail(0, "bench", "peers: '%s %s' failed (exit status %d)%s", o->python, o->peer_script,
                 st, st == 3 ? ": SciPy is missing" : "");
        return CLI_EXIT_SOFTWARE;
    }

    typedef struct {
        const char *name, *variant, *param, *set;
        hp_backend b;
        hp_level l;
        int lbfgs;
    } peer_method;
    static const peer_method ms[] = {
        {"ipopt-exact-linear", "ipopt-exact", "linear", "linear-nlp", HP_BACKEND_IPOPT,
         HP_LEVEL_LINEAR, 0},
        {"ipopt-lbfgs-linear", "ipopt-lbfgs", "linear", "linear-nlp", HP_BACKEND_IPOPT,
         HP_LEVEL_LINEAR, 1},
        {"realtime-linear", "headplan-other", "linear", "linear-nlp", HP_BACKEND_REALTIME,
         HP_LEVEL_LINEAR, 0},
        {"nlopt-slsqp-linear", "headplan-other", "linear", "linear-nlp", HP_BACKEND_NLOPT_SLSQP,
         HP_LEVEL_LINEAR, 0},
        {"ipopt-exact-surface", "ipopt-exact", "surface", "surface-nlp", HP_BACKEND_IPOPT,
         HP_LEVEL_SURFACE, 0},
        {"ipopt-lbfgs-surface", "ipopt-lbfgs", "surface", "surface-nlp", HP_BACKEND_IPOPT,
         HP_LEVEL_SURFACE, 1},
    };
    /* Every planner is created and checked first, then all are timed together in rounds
     * (bench_time_set), so a slow spell of the host falls on every method alike. */
    enum { NM = sizeof ms / sizeof ms[0] };
    hp_planner *planners[NM];
    bench_plan_ctx ctx[NM];
    bench_timed timed[NM];
    size_t rowi[NM]; /* row indices: adding rows may move the table */
    size_t made = 0;
    for (size_t i = 0; i < NM && rc == 0; ++i) {
        const peer_method *m = &ms[i];
        bench_row *row = new_row(t, m->name, m->variant, m->param, m->set);
        if (!row) {
            rc = CLI_EXIT_SOFTWARE;
            break;
        }
        rowi[i] = t->n - 1;
        hp_settings st2 = settings_of(m->b, m->l, 1e-9);
        if ((rc = bench_planner_new(L, &st2, &planners[i]))) break;
        made = i + 1;
        /* The quasi-Newton peer: a backend option, not a settings field. */
        if (m->lbfgs && hp_planner_set_option(planners[i], "hessian_approximation", 1) != HP_OK) {
            fprintf(stderr, "headplan-bench: peers: %s\n", hp_planner_error(planners[i]));
            rc = CLI_EXIT_SOFTWARE;
            break;
        }
        accuracy(planners[i], L, (const double(*)[6])tg, n,
                 (const double(*)[6])(m->l == HP_LEVEL_LINEAR ? ref_lin : ref_sur), row);
        ctx[i] = (bench_plan_ctx){planners[i], (const double(*)[6])tg, n, perm, 0, 0};
        timed[i] = (bench_timed){.fn = bench_plan_batch, .ctx = &ctx[i]};
    }
    if (rc == 0) {
        fprintf(stderr, "bench peers: timing %d methods in %d rounds\n", (int)NM, o->rounds);
        if (bench_time_set(o, timed, (int)NM) != 0) rc = CLI_EXIT_SOFTWARE;
    }
    for (size_t i = 0; i < NM && rc == 0; ++i) {
        bench_row *row = &t->rows[rowi[i]];
        bench_row_set_timing(row, &timed[i].out);
        fprintf(stderr, "bench peers: %-22s %12.0f ns  max error %.2e  failures %ld\n", ms[i].name,
                row->median_ns, row->max_error, row->failures);
    }
    for (size_t i = 0; i < made; ++i) hp_planner_destroy(planners[i]);
    if (rc == 0) rc = read_scipy(cpath, L, &b, commanded, n, (const double(*)[6])ref_lin, t);
    t->baseline = "ipopt-exact-linear";
    return rc;
}
