/* The general-purpose backends (Ipopt, NLopt SLSQP, NLopt COBYLA) through their ops tables on
 * the default layout: exact answers for reachable targets, agreement on the closest answer
 * for an unreachable one, limits kept, status mapping, determinism, and Ipopt from two
 * threads at once (the process-wide mutex). */
#include "support/test_util.h"

#include "planner/backend_common.h"
#include "planner/backend_testing.h"
#include "planner/problem.h"
#include "support/backend_fixture.h"

#include <pthread.h>
#include <stdlib.h>

static hp_layout L;

static int setup(void **st)
{
    (void)st;
    return fx_layout(&L) == HP_OK ? 0 : -1;
}

static void settings(hp_settings *s, double tol)
{
    memset(s, 0, sizeof *s);
    s->backend = HP_BACKEND_IPOPT;
    s->level = HP_LEVEL_SURFACE;
    s->tolerance = tol;
    s->max_iter = 200;
    s->max_time = 10.0; /* generous: budgets are not what these tests test */
    s->weight_mm_per_deg = 1.0;
    s->warm_start = 1;
}

/* The nominal state (ξ = 0, every ri = Ri): a start away from the answer. */
static void nominal(const hp_problem *pb, double *x0)
{
    memset(x0, 0, (size_t)pb->nx * sizeof *x0);
    for (int k = 0; k < pb->n; k++) x0[6 + k] = FX_RI * 1e3;
}

static void solve_with(const hp_backend_ops *ops, const hp_problem *pb, const hp_settings *s,
                       const double *x0, double *x, hp_backend_result *r)
{
    void *state = NULL;
    hp_diag d = {{0}};
    hp_error e = ops->create(&state, pb, s, &d);
    if (e != HP_OK) print_error("%s create: %s\n", ops->name, d.text);
    assert_int_equal(e, HP_OK);
    e = ops->solve(state, pb, x0, x, r, &d);
    if (e != HP_OK) print_error("%s solve: %s\n", ops->name, d.text);
    assert_int_equal(e, HP_OK);
    ops->destroy(state);
}

/* Every returned radius inside its bounds, every value finite. */
static void assert_in_bounds(const hp_problem *pb, const double *x)
{
    for (int i = 0; i < pb->nx; i++) assert_true(isfinite(x[i]));
    for (int k = 0; k < pb->n; k++) {
        assert_true(x[6 + k] >= pb->ri_lo[k]);
        assert_true(x[6 + k] <= pb->ri_hi[k]);
    }
}

static double max_contact_violation(const hp_problem *pb, const double *x)
{
    double c[HP_MAX_BLADDERS], worst = 0.0;
    assert_int_equal(hpi_problem_constraints(pb, x, c, NULL, NULL, NULL), HP_OK);
    for (int k = 0; k < pb->n; k++) worst = fmax(worst, fabs(c[k]));
    return worst;
}

/* Reachable targets: a few mm and about a degree, well inside every limit (checked). The
 * default layout reaches only about ±2.2 mm laterally (p_min = −5 kPa compresses a side
 * bladder's outer radius by 2.2 mm at most), so lateral components stay below that. */
static const double reachable[3][6] = {
    {1.2, -1.5, 1.0, 0.8, -0.6, 1.0},
    {-1.0, 1.0, -1.0, -1.0, 0.5, -0.7},
    {0.5, 2.5, 2.5, 0.3, 1.0, 0.2},
};

/* Pose error tolerated per backend (mm or deg), with the solver tolerance it runs at:
 * - Ipopt, tol 1e-12: Newton steps on exact second derivatives converge quadratically, so
 *   the last step leaves an error far below tol; 1e-9 is the contract (docs/solver-facts.md measured
 *   5.5e-6 mm at tol 1e-8).
 * - SLSQP, xtol 1e-12: superlinear BFGS-SQP; stops when the step is below xtol, by which
 *   time the error is about that size; 1e-8 leaves room for the last BFGS step.
 * - COBYLA, xtol 1e-7: linear models, a trust radius shrinking to xtol; the pose it stops at
 *   is within a few final trust radii of the optimum (measured 1.5e-7): 1e-6. */
typedef struct case_spec {
    const hp_backend_ops *ops;
    double tol, pose_err, contact_err;
} case_spec;

static void reachable_exact(void **st)
{
    (void)st;
    const case_spec cases[3] = {
        {&hpi_backend_ipopt_ops, 1e-12, 1e-9, 1e-9},
        {&hpi_backend_nlopt_slsqp_ops, 1e-12, 1e-8, 1e-9},
        /* COBYLA's contacts hold by construction (ri from ρ): only rounding */
        {&hpi_backend_nlopt_cobyla_ops, 1e-7, 1e-6, 1e-9},
    };
    for (int lv = HP_LEVEL_LINEAR; lv <= HP_LEVEL_SURFACE; lv += 2)
        for (int t = 0; t < 3; t++) {
            hp_problem pb;
            hp_geom G;
            assert_int_equal(fx_problem(&L, &G, (hp_level)lv, reachable[t], &pb), HP_OK);
            /* Precondition: the direct chain is inside every limit (strictly, by 0.1 mm). */
            double xs[HP_PROBLEM_NX_MAX];
            assert_int_equal(hpi_backend_default_start(&pb, xs), HP_OK);
            for (int k = 0; k < pb.n; k++) {
                assert_true(xs[6 + k] > pb.ri_lo[k] + 0.1);
                assert_true(xs[6 + k] < pb.ri_hi[k] - 0.1);
            }
            double x0[HP_PROBLEM_NX_MAX];
            nominal(&pb, x0);
            for (int c = 0; c < 3; c++) {
                hp_settings s;
                settings(&s, cases[c].tol);
                double x[HP_PROBLEM_NX_MAX];
                hp_backend_result r;
                solve_with(cases[c].ops, &pb, &s, x0, x, &r);
                double perr = 0.0;
                for (int i = 0; i < 6; i++) perr = fmax(perr, fabs(x[i] - pb.d[i]));
                double cerr = max_contact_violation(&pb, x);
                print_message("%-13s %-7s target %d: status %d raw %d evals/iters %d pose err "
                              "%.2e contact %.2e\n",
                              cases[c].ops->name, hp_level_name((hp_level)lv), t, r.status,
                              r.raw_code, r.iterations, perr, cerr);
                assert_int_equal(r.converged, 1);
                assert_int_equal(r.status, HP_STATUS_REACHED);
                assert_true(r.iterations > 0);
                assert_true(perr <= cases[c].pose_err);
                assert_true(cerr <= cases[c].contact_err);
                assert_in_bounds(&pb, x);
            }
        }
}

/* 30 mm lateral is far beyond the stretch and pressure limits (the side bladders can move
 * the head ~10 mm). Ipopt and SLSQP solve the same program with different methods: their
 * answers must agree, satisfy first-order optimality (hpi_backend_kkt_ok), keep every limit,
 * and bind the same bladders. */
static void unreachable_closest(void **st)
{
    (void)st;
    const double d[6] = {30.0, 0, 0, 0, 0, 0};
    hp_problem pb;
    hp_geom G;
    assert_int_equal(fx_problem(&L, &G, HP_LEVEL_SURFACE, d, &pb), HP_OK);
    hp_settings s;
    settings(&s, 1e-12);
    double x0[HP_PROBLEM_NX_MAX], xi[HP_PROBLEM_NX_MAX], xs[HP_PROBLEM_NX_MAX];
    nominal(&pb, x0);
    hp_backend_result ri, rs;
    solve_with(&hpi_backend_ipopt_ops, &pb, &s, x0, xi, &ri);
    solve_with(&hpi_backend_nlopt_slsqp_ops, &pb, &s, x0, xs, &rs);
    assert_int_equal(ri.converged, 1);
    assert_int_equal(rs.converged, 1);
    assert_in_bounds(&pb, xi);
    assert_in_bounds(&pb, xs);
    /* The answer moved toward the target but not to it. */
    assert_true(xi[0] > 1.0 && xi[0] < 29.0);
    /* Ipopt (Newton on exact second derivatives) stops at a KKT point to rounding: the
     * Lagrangian's gradient below 1e-9 (measured 7.5e-11, |∇f| = 60). SLSQP (BFGS) stops when
     * f stalls; its gradient residual measured between 2.3e-8 and 1.4e-6 as the upstream
     * kinematics' rounding changed, with the contacts violated by ~1e-12 mm (violation times
     * multipliers, ~30, can put its f *below* Ipopt's). With Lagrangian curvature ~2 a 1.4e-6
     * residual moves x by ~7e-7: agreement within 1e-5 is SLSQP's accuracy with a 10× margin,
     * and still 4e-6 of the 2.3 mm answer. */
    hp_kkt_measure mi, ms;
    assert_int_equal(hpi_backend_kkt_measure(&pb, xi, &mi), HP_OK);
    assert_int_equal(hpi_backend_kkt_measure(&pb, xs, &ms), HP_OK);
    print_message("KKT residual: ipopt %.2e, slsqp %.2e; contact violation ipopt %.2e, slsqp "
                  "%.2e mm\n",
                  mi.stationarity, ms.stationarity, mi.feasibility, ms.feasibility);
    assert_true(mi.stationarity <= 1e-9);
    assert_true(mi.wrong_sign == 0.0 && ms.wrong_sign == 0.0);
    double worst = 0.0;
    for (int i = 0; i < pb.nx; i++) worst = fmax(worst, fabs(xi[i] - xs[i]));
    print_message("closest: ipopt x = %.6f mm (iters %d), slsqp x = %.6f mm (evals %d); max "
                  "difference %.2e\n",
                  xi[0], ri.iterations, xs[0], rs.iterations, worst);
    assert_true(worst <= 1e-5);
    assert_true(max_contact_violation(&pb, xi) <= 1e-9);
    assert_true(max_contact_violation(&pb, xs) <= 1e-9);
    assert_true(hpi_backend_kkt_ok(&pb, xi, 1e-9));
    assert_true(hpi_backend_kkt_ok(&pb, xs, 1e-9));
    /* ...and the test rejects the (feasible) nominal start, which is not stationary, and a
     * point with one binding bladder moved 0.01 mm off its bound (contact then broken). */
    assert_false(hpi_backend_kkt_ok(&pb, x0, 1e-9));
    double xm[HP_PROBLEM_NX_MAX];
    memcpy(xm, xi, sizeof xm);
    for (int k = 0; k < pb.n; k++)
        if (xm[6 + k] - pb.ri_lo[k] <= 1e-6) {
            xm[6 + k] += 0.01;
            break;
        }
    assert_false(hpi_backend_kkt_ok(&pb, xm, 1e-9));
    /* Binding bladders: those at a bound (1e-6 mm). Same set for both, and at least one. */
    int nbind = 0;
    for (int k = 0; k < pb.n; k++) {
        int bi = xi[6 + k] - pb.ri_lo[k] <= 1e-6 || pb.ri_hi[k] - xi[6 + k] <= 1e-6;
        int bs = xs[6 + k] - pb.ri_lo[k] <= 1e-6 || pb.ri_hi[k] - xs[6 + k] <= 1e-6;
        assert_int_equal(bi, bs);
        nbind += bi;
        if (bi)
            print_message("  binding: %s ri %.6f mm in [%.6f, %.6f]\n", L.bladders[k].name,
                          xi[6 + k], pb.ri_lo[k], pb.ri_hi[k]);
    }
    assert_true(nbind >= 1);
    /* Releasing the binding bounds must let the pose error fall: they really bind. */
    hp_problem wide = pb;
    for (int k = 0; k < pb.n; k++) {
        wide.ri_lo[k] = 0.5 * FX_RI * 1e3;
        wide.ri_hi[k] = 2.0 * FX_RI * 1e3;
    }
    double xw[HP_PROBLEM_NX_MAX];
    hp_backend_result rw;
    solve_with(&hpi_backend_ipopt_ops, &wide, &s, x0, xw, &rw);
    double fb, fw;
    assert_int_equal(hpi_problem_objective(&pb, xi, &fb, NULL, NULL), HP_OK);
    assert_int_equal(hpi_problem_objective(&wide, xw, &fw, NULL, NULL), HP_OK);
    assert_true(fw < fb);
}

/* Same input twice -> bit-identical output, each backend, fresh objects and one reused. */
static void deterministic(void **st)
{
    (void)st;
    const hp_backend_ops *ops[3] = {&hpi_backend_ipopt_ops, &hpi_backend_nlopt_slsqp_ops,
                                    &hpi_backend_nlopt_cobyla_ops};
    const double d[6] = {12.0, -4.0, 3.0, 2.0, -2.0, 3.0}; /* partly unreachable */
    hp_problem pb;
    hp_geom G;
    assert_int_equal(fx_problem(&L, &G, HP_LEVEL_SURFACE, d, &pb), HP_OK);
    double x0[HP_PROBLEM_NX_MAX];
    nominal(&pb, x0);
    for (int b = 0; b < 3; b++) {
        hp_settings s;
        settings(&s, 1e-8);
        s.warm_start = 0;
        double xa[HP_PROBLEM_NX_MAX], xb[HP_PROBLEM_NX_MAX], xc[HP_PROBLEM_NX_MAX];
        hp_backend_result ra, rb, rc;
        solve_with(ops[b], &pb, &s, x0, xa, &ra);
        solve_with(ops[b], &pb, &s, x0, xb, &rb);
        assert_memory_equal(xa, xb, (size_t)pb.nx * sizeof *xa);
        assert_int_equal(ra.raw_code, rb.raw_code);
        assert_int_equal(ra.iterations, rb.iterations);
        void *state;
        assert_int_equal(ops[b]->create(&state, &pb, &s, NULL), HP_OK);
        assert_int_equal(ops[b]->solve(state, &pb, x0, xc, &rc, NULL), HP_OK);
        assert_int_equal(ops[b]->solve(state, &pb, x0, xc, &rc, NULL), HP_OK);
        ops[b]->destroy(state);
        assert_memory_equal(xa, xc, (size_t)pb.nx * sizeof *xa);
    }
}

/* ---- two threads, each with its own Ipopt problem ---- */

#define THREAD_SOLVES 20

typedef struct job {
    int first; /* index of the first target */
    double x[THREAD_SOLVES][HP_PROBLEM_NX_MAX];
    int ok;
} job;

static void target(int i, double d[6])
{
    /* alternating reachable and unreachable targets */
    for (int j = 0; j < 6; j++) d[j] = (i % 2 ? 8.0 : 1.5) * sin(1.0 + i * 0.7 + j * 1.3);
}

static void *run_job(void *arg)
{
    job *jb = arg;
    hp_settings s;
    settings(&s, 1e-10);
    s.warm_start = 0;
    jb->ok = 1;
    double d[6];
    target(jb->first, d);
    hp_problem pb;
    hp_geom G;
    if (fx_problem(&L, &G, HP_LEVEL_SURFACE, d, &pb) != HP_OK) return jb->ok = 0, NULL;
    void *state;
    if (hpi_backend_ipopt_ops.create(&state, &pb, &s, NULL) != HP_OK) return jb->ok = 0, NULL;
    for (int i = 0; i < THREAD_SOLVES; i++) {
        target(jb->first + i, d);
        memcpy(pb.d, d, sizeof d);
        hp_backend_result r;
        double x0[HP_PROBLEM_NX_MAX];
        nominal(&pb, x0);
        if (hpi_backend_ipopt_ops.solve(state, &pb, x0, jb->x[i], &r, NULL) != HP_OK ||
            !r.converged)
            jb->ok = 0;
    }
    hpi_backend_ipopt_ops.destroy(state);
    return NULL;
}

static void ipopt_two_threads(void **st)
{
    (void)st;
    static job serial[2], par[2];
    serial[0].first = par[0].first = 0;
    serial[1].first = par[1].first = 100;
    run_job(&serial[0]);
    run_job(&serial[1]);
    pthread_t th[2];
    for (int t = 0; t < 2; t++) assert_int_equal(pthread_create(&th[t], NULL, run_job, &par[t]), 0);
    for (int t = 0; t < 2; t++) assert_int_equal(pthread_join(th[t], NULL), 0);
    for (int t = 0; t < 2; t++) {
        assert_true(serial[t].ok);
        assert_true(par[t].ok);
        assert_memory_equal(serial[t].x, par[t].x, sizeof serial[t].x);
    }
}

/* ---- status mapping and faults ---- */

static void ipopt_iteration_limit_and_faults(void **st)
{
    (void)st;
    const double d[6] = {20.0, 5.0, -5.0, 3.0, 3.0, -3.0};
    hp_problem pb;
    hp_geom G;
    assert_int_equal(fx_problem(&L, &G, HP_LEVEL_SURFACE, d, &pb), HP_OK);
    double x0[HP_PROBLEM_NX_MAX], x[HP_PROBLEM_NX_MAX];
    nominal(&pb, x0);
    hp_settings s;
    settings(&s, 1e-12);
    s.max_iter = 2;
    hp_backend_result r;
    solve_with(&hpi_backend_ipopt_ops, &pb, &s, x0, x, &r);
    assert_int_equal(r.status, HP_STATUS_ITERATION_LIMIT);
    assert_int_equal(r.raw_code, -1); /* Maximum_Iterations_Exceeded */
    assert_int_equal(r.converged, 0);
    assert_in_bounds(&pb, x);

    settings(&s, 1e-12);
    const int faults[2] = {HP_TEST_FAULT_NAN_OBJECTIVE, HP_TEST_FAULT_FAIL_CONSTRAINTS};
    for (int f = 0; f < 2; f++) {
        hpi_backend_ipopt_test_hook(faults[f]);
        solve_with(&hpi_backend_ipopt_ops, &pb, &s, x0, x, &r);
        hpi_backend_ipopt_test_hook(HP_TEST_FAULT_NONE);
        print_message("fault %d: status %d raw %d\n", faults[f], r.status, r.raw_code);
        assert_int_equal(r.converged, 0);
        assert_int_equal(r.status, HP_STATUS_SOLVER_ERROR);
        assert_in_bounds(&pb, x);
    }
    /* Empty bounds (e.g. contradictory rate limits): reported, solver not run. */
    pb.ri_lo[3] = pb.ri_hi[3] + 0.5;
    const hp_backend_ops *ops[3] = {&hpi_backend_ipopt_ops, &hpi_backend_nlopt_slsqp_ops,
                                    &hpi_backend_nlopt_cobyla_ops};
    for (int b = 0; b < 3; b++) {
        solve_with(ops[b], &pb, &s, x0, x, &r);
        assert_int_equal(r.status, HP_STATUS_INFEASIBLE_START);
        assert_int_equal(r.converged, 0);
    }
}

static void nlopt_iteration_limit(void **st)
{
    (void)st;
    const double d[6] = {20.0, 5.0, -5.0, 3.0, 3.0, -3.0};
    hp_problem pb;
    hp_geom G;
    assert_int_equal(fx_problem(&L, &G, HP_LEVEL_SURFACE, d, &pb), HP_OK);
    double x0[HP_PROBLEM_NX_MAX], x[HP_PROBLEM_NX_MAX];
    nominal(&pb, x0);
    hp_settings s;
    settings(&s, 1e-12);
    s.max_iter = 1;
    hp_backend_result r;
    solve_with(&hpi_backend_nlopt_slsqp_ops, &pb, &s, x0, x, &r);
    assert_int_equal(r.status, HP_STATUS_ITERATION_LIMIT);
    assert_int_equal(r.raw_code, 5); /* NLOPT_MAXEVAL_REACHED */
    assert_in_bounds(&pb, x);
    solve_with(&hpi_backend_nlopt_cobyla_ops, &pb, &s, x0, x, &r);
    assert_int_equal(r.status, HP_STATUS_ITERATION_LIMIT);
    assert_in_bounds(&pb, x);
}

/* New bounds (rate limits) on the same object: the problem is rebuilt and the answer is the
 * one a fresh object gives, bit for bit. */
static void ipopt_bounds_change(void **st)
{
    (void)st;
    const double d[6] = {1.5, 0.0, -1.0, 0.5, 0.0, 0.5};
    hp_problem pb;
    hp_geom G;
    assert_int_equal(fx_problem(&L, &G, HP_LEVEL_SURFACE, d, &pb), HP_OK);
    hp_settings s;
    settings(&s, 1e-12);
    double x0[HP_PROBLEM_NX_MAX], x1[HP_PROBLEM_NX_MAX], x2[HP_PROBLEM_NX_MAX];
    nominal(&pb, x0);
    void *state;
    assert_int_equal(hpi_backend_ipopt_ops.create(&state, &pb, &s, NULL), HP_OK);
    hp_backend_result r1, r2;
    assert_int_equal(hpi_backend_ipopt_ops.solve(state, &pb, x0, x1, &r1, NULL), HP_OK);
    assert_true(r1.converged);
    /* a rate limit: every radius within 0.5 mm of nominal, which makes d unreachable */
    for (int k = 0; k < pb.n; k++) {
        pb.ri_lo[k] = fmax(pb.ri_lo[k], 26.5);
        pb.ri_hi[k] = fmin(pb.ri_hi[k], 27.5);
    }
    assert_int_equal(hpi_backend_ipopt_ops.solve(state, &pb, x0, x1, &r1, NULL), HP_OK);
    hpi_backend_ipopt_ops.destroy(state);
    solve_with(&hpi_backend_ipopt_ops, &pb, &s, x0, x2, &r2);
    assert_true(r1.converged && r2.converged);
    assert_memory_equal(x1, x2, (size_t)pb.nx * sizeof *x1);
    assert_in_bounds(&pb, x1);
    int at_bound = 0;
    for (int k = 0; k < pb.n; k++)
        at_bound += x1[6 + k] - pb.ri_lo[k] <= 1e-6 || pb.ri_hi[k] - x1[6 + k] <= 1e-6;
    assert_true(at_bound >= 1);
}

/* Warm start: re-solving from the previous answer (same object, target moved slightly)
 * converges to the new exact answer and needs no more iterations than a cold start. */
static void ipopt_warm_start(void **st)
{
    (void)st;
    hp_problem pb;
    hp_geom G;
    assert_int_equal(fx_problem(&L, &G, HP_LEVEL_SURFACE, reachable[0], &pb), HP_OK);
    hp_settings s;
    settings(&s, 1e-12);
    void *state;
    assert_int_equal(hpi_backend_ipopt_ops.create(&state, &pb, &s, NULL), HP_OK);
    double x0[HP_PROBLEM_NX_MAX], x1[HP_PROBLEM_NX_MAX], x2[HP_PROBLEM_NX_MAX];
    nominal(&pb, x0);
    hp_backend_result r1, r2, rc;
    assert_int_equal(hpi_backend_ipopt_ops.solve(state, &pb, x0, x1, &r1, NULL), HP_OK);
    assert_true(r1.converged);
    pb.d[0] += 0.1;
    pb.d[4] -= 0.05;
    assert_int_equal(hpi_backend_ipopt_ops.solve(state, &pb, x1, x2, &r2, NULL), HP_OK);
    assert_true(r2.converged);
    for (int i = 0; i < 6; i++) hp_assert_close(x2[i], pb.d[i], 0.0, 1e-9);
    /* cold from the same point, for comparison */
    double x3[HP_PROBLEM_NX_MAX];
    s.warm_start = 0;
    solve_with(&hpi_backend_ipopt_ops, &pb, &s, x1, x3, &rc);
    print_message("warm start: %d iterations; cold from the same point: %d\n", r2.iterations,
                  rc.iterations);
    assert_true(r2.iterations <= rc.iterations);
    hpi_backend_ipopt_ops.destroy(state);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(reachable_exact),
        cmocka_unit_test(unreachable_closest),
        cmocka_unit_test(deterministic),
        cmocka_unit_test(ipopt_two_threads),
        cmocka_unit_test(ipopt_iteration_limit_and_faults),
        cmocka_unit_test(nlopt_iteration_limit),
        cmocka_unit_test(ipopt_bounds_change),
        cmocka_unit_test(ipopt_warm_start),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
