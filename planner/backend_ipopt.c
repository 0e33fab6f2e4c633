/* The reference backend: Ipopt 3.11 through its C interface on the full program
 * (x = [ξ (mm, deg), ri (mm)], n contact equalities), with the exact constraint Jacobian and
 * the exact Hessian of the Lagrangian from problem_eval.c.
 *
 * Facts this file relies on (docs/solver-facts.md, measured on this machine):
 * - Debian's Ipopt/MUMPS is not thread-safe, even with one problem per thread: every Ipopt
 *   call (create, options, solve, free) runs under one process-wide mutex owned here.
 * - The library must never print: `sb yes` (licence banner), print_level 0, and
 *   option_file_name "" (otherwise ./ipopt.opt silently overrides the options). Every option
 *   call's return is checked: an unknown option prints and returns false.
 * - 3.11 has no statistics API: the intermediate callback counts iterations.
 * - The C interface copies the variable bounds at creation and offers no way to change them,
 *   so the problem object is reused while ri_lo/ri_hi are bitwise unchanged and recreated
 *   (about 0.7 ms and some allocation) when they change, i.e. every cycle with rate limits.
 * - Warm start (previous point and multipliers, warm_start_init_point, tiny bound pushes and
 *   mu_init) is used when the core has said (warm_point) that x0 is the answer this object's
 *   last solve returned and that solve converged: then the stored multipliers belong to x0. */
#include "common/unconst.h"
#include "planner/backend_common.h"
#include "planner/backend_testing.h"
#include "planner/clock.h"
#include "planner/ipopt_shared.h"
#include "planner/multistart.h"

#include <IpStdCInterface.h>
#include <float.h>
#include <math.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

/* Test-only hooks (planner/backend_testing.h): inert unless a test sets them. */
static atomic_int ipopt_fault = HP_TEST_FAULT_NONE;
static atomic_int ipopt_forced = HP_TEST_NO_FORCE;

void hpi_test_ipopt_fault(int fault) { atomic_store(&ipopt_fault, fault); }
void hpi_backend_ipopt_test_hook(int fault) { hpi_test_ipopt_fault(fault); }
void hpi_test_ipopt_force_status(int code) { atomic_store(&ipopt_forced, code); }
/* Ipopt reads bounds beyond ±1e19 as infinite. */
#define IPOPT_INF 1e19
/* mu_init for a cold start (Ipopt's default) and for a warm start near the solution. */
#define MU_INIT_COLD 0.1
#define MU_INIT_WARM 1e-9
/* Ipopt's own CPU-time limit, its default (about 11.6 days): never reached, the budget is
 * read by intermediate on the plan's clock. */
#define IPOPT_NO_CPU_LIMIT 1e6

typedef struct ipopt_state {
    IpoptProblem app;
    hp_settings s;
    int n, nx;
    double ri_lo[HP_MAX_BLADDERS], ri_hi[HP_MAX_BLADDERS]; /* bounds app was built with */
    const hp_problem *pb;                                  /* during a solve only */
    int iters;
    int have_prev; /* the last solve converged: its multipliers are usable */
    int accepted;  /* the core starts the next solve from that answer (warm_point) */
    int lbfgs;     /* option "hessian_approximation" = 1 */
    double t0;     /* the plan's clock (hpi_plan_now) when this solve began: its budget's start */
    int timed_out; /* the intermediate callback stopped the solve: max_time spent */
    int rebuild;   /* an option changed: rebuild the app before the next solve */
    double mult_g[HP_MAX_BLADDERS];
    double mult_xl[HP_PROBLEM_NX_MAX], mult_xu[HP_PROBLEM_NX_MAX];
    double dense[HP_PROBLEM_NX_MAX * HP_PROBLEM_NX_MAX]; /* Hessian / Jacobian scratch */
} ipopt_state;

static Bool eval_f(Index n, Number *x, Bool new_x, Number *f, UserDataPtr u)
{
    (void)n, (void)new_x;
    const ipopt_state *st = u;
    if (atomic_load(&ipopt_fault) == HP_TEST_FAULT_NAN_OBJECTIVE) {
        *f = NAN;
        return TRUE;
    }
    return hpi_problem_objective(st->pb, x, f, NULL, NULL) == HP_OK;
}

static Bool eval_grad_f(Index n, Number *x, Bool new_x, Number *grad, UserDataPtr u)
{
    (void)n, (void)new_x;
    const ipopt_state *st = u;
    double f;
    return hpi_problem_objective(st->pb, x, &f, grad, NULL) == HP_OK;
}

static Bool eval_g(Index n, Number *x, Bool new_x, Index m, Number *g, UserDataPtr u)
{
    (void)n, (void)new_x, (void)m;
    const ipopt_state *st = u;
    if (atomic_load(&ipopt_fault) == HP_TEST_FAULT_FAIL_CONSTRAINTS) return FALSE;
    return hpi_problem_constraints(st->pb, x, g, NULL, NULL, NULL) == HP_OK;
}

/* Row k of the Jacobian touches the six pose columns and its own ri column. */
static Bool eval_jac_g(Index n, Number *x, Bool new_x, Index m, Index nele, Index *iRow,
                       Index *jCol, Number *values, UserDataPtr u)
{
    (void)n, (void)new_x, (void)nele;
    ipopt_state *st = u;
    if (!values) {
        int e = 0;
        for (int k = 0; k < m; k++) {
            for (int i = 0; i < 6; i++, e++) iRow[e] = k, jCol[e] = i;
            iRow[e] = k, jCol[e] = 6 + k, e++;
        }
        return TRUE;
    }
    if (atomic_load(&ipopt_fault) == HP_TEST_FAULT_FAIL_CONSTRAINTS) return FALSE;
    if (hpi_problem_constraints(st->pb, x, NULL, st->dense, NULL, NULL) != HP_OK) return FALSE;
    int e = 0;
    for (int k = 0; k < m; k++) {
        for (int i = 0; i < 6; i++) values[e++] = st->dense[k * st->nx + i];
        values[e++] = st->dense[k * st->nx + 6 + k];
    }
    return TRUE;
}

/* Lower triangle: the dense 6×6 pose block (21 entries) then the ri diagonal; the objective
 * and the constraints have no pose–ri cross terms. */
static Bool eval_h(Index n, Number *x, Bool new_x, Number obj_factor, Index m, Number *lambda,
                   Bool new_lambda, Index nele, Index *iRow, Index *jCol, Number *values,
                   UserDataPtr u)
{
    (void)new_x, (void)new_lambda, (void)nele;
    ipopt_state *st = u;
    if (!values) {
        int e = 0;
        for (int i = 0; i < 6; i++)
            for (int j = 0; j <= i; j++, e++) iRow[e] = i, jCol[e] = j;
        for (int k = 0; k < m; k++, e++) iRow[e] = 6 + k, jCol[e] = 6 + k;
        return TRUE;
    }
    double *h = st->dense;
    double f;
    if (hpi_problem_objective(st->pb, x, &f, NULL, h) != HP_OK) return FALSE;
    for (int i = 0; i < n * n; i++) h[i] *= obj_factor;
    if (hpi_problem_constraints(st->pb, x, NULL, NULL, lambda, h) != HP_OK) return FALSE;
    int e = 0;
    for (int i = 0; i < 6; i++)
        for (int j = 0; j <= i; j++) values[e++] = h[i * n + j];
    for (int k = 0; k < m; k++) values[e++] = h[(6 + k) * n + 6 + k];
    return TRUE;
}

static Bool intermediate(Index alg_mod, Index iter, Number obj, Number inf_pr, Number inf_du,
                         Number mu, Number d_norm, Number reg, Number alpha_du, Number alpha_pr,
                         Index ls, UserDataPtr u)
{
    (void)alg_mod, (void)obj, (void)inf_pr, (void)inf_du, (void)mu, (void)d_norm, (void)reg;
    (void)alpha_du, (void)alpha_pr, (void)ls;
    ipopt_state *st = u;
    st->iters = iter;
    /* The budget is read here at every iteration, the first included, on the planner's one
     * clock (hpi_plan_now: monotonic wall time, as the other backends read theirs), from the
     * plan's start: Ipopt's own max_cpu_time reads the process's CPU time, which counts every
     * thread (under `batch --jobs N` up to N times this plan's) and can stand still over a
     * short solve, so it is left at its never-reached default (IPOPT_NO_CPU_LIMIT). */
    if (hpi_plan_now() - st->t0 > st->s.max_time) {
        st->timed_out = 1;
        return FALSE;
    }
    return atomic_load(&ipopt_fault) == HP_TEST_FAULT_STOP ? FALSE : TRUE;
}

/* Builds st->app for bounds pb->ri_lo/ri_hi with every fixed option. Caller holds the lock
 * and has freed any previous app. */
static hp_error build_app(ipopt_state *st, const hp_problem *pb, hp_diag *d)
{
    double xl[HP_PROBLEM_NX_MAX], xu[HP_PROBLEM_NX_MAX];
    double gz[HP_MAX_BLADDERS] = {0};
    /* An uncommanded pose component (weight 0) is fixed at 0: left free, Ipopt uses it to
     * meet the contacts, and the core (which holds it at 0) then gets radii no pose holds. */
    for (int i = 0; i < 6; i++) {
        double b = pb->w[i] > 0.0 ? IPOPT_INF : 0.0;
        xl[i] = -b, xu[i] = b;
    }
    for (int k = 0; k < st->n; k++) {
        xl[6 + k] = pb->ri_lo[k];
        xu[6 + k] = pb->ri_hi[k];
        st->ri_lo[k] = pb->ri_lo[k];
        st->ri_hi[k] = pb->ri_hi[k];
    }
    st->app = CreateIpoptProblem(st->nx, xl, xu, st->n, gz, gz, 7 * st->n, 21 + st->n, 0, eval_f,
                                 eval_g, eval_grad_f, eval_jac_g, eval_h);
    if (!st->app) return hp_diag_set(d, HP_ERR_SOLVER, "ipopt: CreateIpoptProblem failed");
    const hp_settings *s = &st->s;
    hp_error e = hpi_ipopt_base_options(st->app, s->tolerance, s->max_iter, IPOPT_NO_CPU_LIMIT, d);
    if (e != HP_OK) return e;
    /* The quasi-Newton peer of the benchmarks: Ipopt then never calls eval_h. */
    if (st->lbfgs && (e = hpi_ipopt_opt_str(st->app, "hessian_approximation", "limited-memory", d)))
        return e;
    if (!SetIntermediateCallback(st->app, intermediate))
        return hp_diag_set(d, HP_ERR_SOLVER, "ipopt: SetIntermediateCallback failed");
    return HP_OK;
}

static hp_error ipopt_create(void **state, const hp_problem *pb, const hp_settings *s, hp_diag *d)
{
    if (!state || !pb || !s) return hp_diag_set(d, HP_ERR_NULL, "ipopt: NULL argument");
    *state = NULL;
    hp_error e = hpi_backend_check_problem(pb, d);
    if (e != HP_OK && e != HP_ERR_DOMAIN) return e;
    if (!(s->tolerance > 0.0) || !(s->max_iter > 0) || !(s->max_time > 0.0))
        return hp_diag_set(d, HP_ERR_INVALID, "ipopt: tolerance, max_iter, max_time must be > 0");
    ipopt_state *st = calloc(1, sizeof *st);
    if (!st) return hp_diag_set(d, HP_ERR_NOMEM, "ipopt: out of memory");
    st->s = *s;
    st->n = pb->n;
    st->nx = pb->nx;
    /* An empty ri box (rate limits) is left for solve to report; build with a valid one. */
    hp_problem tmp = *pb;
    for (int k = 0; k < pb->n; k++)
        if (!(tmp.ri_lo[k] <= tmp.ri_hi[k])) tmp.ri_hi[k] = tmp.ri_lo[k];
    hpi_ipopt_lock();
    e = build_app(st, &tmp, d);
    if (e != HP_OK && st->app) FreeIpoptProblem(st->app);
    hpi_ipopt_unlock();
    if (e != HP_OK) {
        free(st);
        return e;
    }
    *state = st;
    return HP_OK;
}

static void ipopt_destroy(void *state)
{
    ipopt_state *st = state;
    if (!st) return;
    if (st->app) {
        hpi_ipopt_lock();
        FreeIpoptProblem(st->app);
        hpi_ipopt_unlock();
    }
    free(st);
}

static hp_status map_status(enum ApplicationReturnStatus r, int timed_out, int *converged)
{
    *converged = 0;
    if (r == User_Requested_Stop && timed_out) return HP_STATUS_TIME_LIMIT;
    switch (r) {
    case Solve_Succeeded:
    case Solved_To_Acceptable_Level:
        *converged = 1;
        return HP_STATUS_REACHED; /* the core decides REACHED or CLOSEST */
    case Maximum_Iterations_Exceeded: return HP_STATUS_ITERATION_LIMIT;
    case Maximum_CpuTime_Exceeded: return HP_STATUS_TIME_LIMIT;
    case Infeasible_Problem_Detected: return HP_STATUS_INFEASIBLE_START;
    default: return HP_STATUS_SOLVER_ERROR;
    }
}

/* The active-set polish of a converged answer that binds nothing.
 *
 * Just beyond reach the remaining pose error, and with it the binding bound's multiplier z,
 * can be as small as the tolerance (1e-9 mm). Ipopt's complementarity test (slack · z <=
 * compl_inf_tol) then lets its interior point stop micrometres inside that bound, where the
 * planner's one binding threshold (HP_BINDING_TOL_MM) sees no limit and must refuse the
 * claim: on the default layout Ipopt gave solver-error in 42 of 44 directions 1e-6 beyond
 * reach. The final iterate still tells which bounds are active: on the central path every
 * slack · z is about mu, so z / slack is of order one at an active bound and ~1e-12 at an
 * inactive one. Those bounds are fixed and Ipopt solves again; the polished point replaces
 * the answer only if it passes the first-order test (hpi_backend_kkt_ok, signs of the fixed
 * bounds' multipliers included) and its objective is no worse than the interior point's (a
 * feasible point, so the optimum's objective is at most its own). Otherwise the answer is
 * left as it was, and the core labels it. The polish's solves share the plan's budgets: at
 * most max_iter iterations and max_time s on the plan's clock in all. */

/* z / slack of the bounds taken as active must exceed every other bound's by this factor. */
#define POLISH_GAP 1e4
/* A released bound is moved this fraction of its radius's range outward: at a degenerate
 * vertex (more active contacts than pose directions) a bound whose multiplier has the wrong
 * sign can still be optimal within a nanometre, where an interior point would stop
 * micrometres inside it again; without the bound the optimum is found, and lies inside. */
#define POLISH_RELAX 0.1

/* 1 when a converged answer x misses the target by more than the tolerance while every
 * radius is farther than half the binding threshold from its bounds. */
static int needs_polish(const ipopt_state *st, const hp_problem *pb, const double *x)
{
    double err = 0.0;
    for (int i = 0; i < 6; i++)
        if (pb->w[i] > 0.0) err = fmax(err, fabs(x[i] - pb->d[i]));
    if (!(err > st->s.tolerance)) return 0;
    for (int k = 0; k < st->n; k++)
        if (!(x[6 + k] - pb->ri_lo[k] > 0.5 * HP_BINDING_TOL_MM &&
              pb->ri_hi[k] - x[6 + k] > 0.5 * HP_BINDING_TOL_MM))
            return 0;
    return 1;
}

/* The bounds Ipopt's last iterate marks active: side[k] = −1 (lower), +1 (upper), 0 (free).
 * 0 when no clear gap (POLISH_GAP) separates them from the rest. */
static int pick_active(const ipopt_state *st, const hp_problem *pb, const double *x,
                       int side[HP_MAX_BLADDERS])
{
    double ratio[2 * HP_MAX_BLADDERS];
    int ord[2 * HP_MAX_BLADDERS], m = 2 * st->n;
    for (int k = 0; k < st->n; k++) {
        ratio[2 * k] = st->mult_xl[6 + k] / fmax(x[6 + k] - pb->ri_lo[k], DBL_MIN);
        ratio[2 * k + 1] = st->mult_xu[6 + k] / fmax(pb->ri_hi[k] - x[6 + k], DBL_MIN);
        side[k] = 0;
    }
    for (int j = 0; j < m; j++) { /* insertion sort, descending */
        int v = j;
        while (v > 0 && ratio[ord[v - 1]] < ratio[j]) {
            ord[v] = ord[v - 1];
            --v;
        }
        ord[v] = j;
    }
    int cut = -1;
    double best = POLISH_GAP;
    for (int j = 0; j + 1 < m; j++) {
        double a = ratio[ord[j]], b = ratio[ord[j + 1]];
        if (!(a > 0.0) || !isfinite(a)) break;
        double gap = b > 0.0 ? a / b : INFINITY;
        if (gap >= best) {
            best = gap;
            cut = j;
        }
    }
    if (cut < 0) return 0;
    for (int j = 0; j <= cut; j++) {
        int k = ord[j] / 2;
        if (side[k]) return 0; /* both bounds of one radius: no clear answer */
        side[k] = ord[j] % 2 ? 1 : -1;
    }
    return 1;
}

/* One solve with the bounds side[] = ±1 fixed (−1 lower, +1 upper), from x with those radii
 * moved onto them, and the bound on the side of side[] = ±2 (released) moved POLISH_RELAX of
 * the radius's range outward (caller holds the lock). 1 with xp converged, finite and
 * clipped into the bounds (the first-order test then sees any violation as a broken
 * contact), else 0. */
static int solve_fixed(ipopt_state *st, const hp_problem *pb, const double *x,
                       const int side[HP_MAX_BLADDERS], double *xp)
{
    double xl[HP_PROBLEM_NX_MAX], xu[HP_PROBLEM_NX_MAX];
    double gz[HP_MAX_BLADDERS] = {0}, mg[HP_MAX_BLADDERS];
    double ml[HP_PROBLEM_NX_MAX], mu_[HP_PROBLEM_NX_MAX];
    for (int i = 0; i < 6; i++) {
        double b = pb->w[i] > 0.0 ? IPOPT_INF : 0.0;
        xl[i] = -b, xu[i] = b;
    }
    memcpy(xp, x, (size_t)st->nx * sizeof *x);
    for (int k = 0; k < st->n; k++) {
        double lo = pb->ri_lo[k], hi = pb->ri_hi[k], relax = POLISH_RELAX * (hi - lo);
        xl[6 + k] = side[k] == 1 ? hi : side[k] == -2 ? lo - relax : lo;
        xu[6 + k] = side[k] == -1 ? lo : side[k] == 2 ? hi + relax : hi;
        if (side[k] == 1 || side[k] == -1) xp[6 + k] = xl[6 + k];
    }
    IpoptProblem app = CreateIpoptProblem(st->nx, xl, xu, st->n, gz, gz, 7 * st->n, 21 + st->n, 0,
                                          eval_f, eval_g, eval_grad_f, eval_jac_g, eval_h);
    if (!app) return 0;
    const hp_settings *s = &st->s;
    int iters0 = st->iters;
    enum ApplicationReturnStatus rc = Internal_Error;
    double obj;
    /* What is left of the plan's budgets (the time on the plan's clock, read by
     * intermediate). */
    int iters_left = s->max_iter - iters0;
    double time_left = s->max_time - (hpi_plan_now() - st->t0);
    if (iters_left > 0 && time_left > 0.0 &&
        hpi_ipopt_base_options(app, s->tolerance, iters_left, IPOPT_NO_CPU_LIMIT, NULL) == HP_OK &&
        SetIntermediateCallback(app, intermediate))
        rc = IpoptSolve(app, xp, NULL, &obj, mg, ml, mu_, st);
    FreeIpoptProblem(app);
    st->iters += iters0;
    int conv;
    map_status(rc, st->timed_out, &conv);
    for (int i = 0; i < st->nx; i++) conv = conv && isfinite(xp[i]);
    if (conv) hpi_backend_clip(pb, xp);
    return conv;
}

/* The polish (above): fixes the bounds Ipopt's iterate marks active and solves again; a fixed
 * bound whose multiplier comes out with the wrong sign is released and the rest solved
 * again (an active-set step), at most once per bladder. Replaces x and returns 1 when a
 * polished point passes the checks, else leaves x and returns 0. */
static int polish(ipopt_state *st, const hp_problem *pb, double *x)
{
    int side[HP_MAX_BLADDERS];
    if (!pick_active(st, pb, x, side)) return 0;
    double f_ip;
    if (hpi_problem_objective(pb, x, &f_ip, NULL, NULL) != HP_OK) return 0;
    const double feas = fmax(10.0 * st->s.tolerance, 1e-9);
    for (int round = 0; round < st->n; round++) {
        double xp[HP_PROBLEM_NX_MAX], f_pol;
        hp_kkt_measure m;
        if (!solve_fixed(st, pb, x, side, xp) ||
            hpi_problem_objective(pb, xp, &f_pol, NULL, NULL) != HP_OK ||
            !(f_pol <= f_ip * (1.0 + 1e-9)) || hpi_backend_kkt_measure(pb, xp, &m) != HP_OK)
            return 0;
        if (hpi_backend_kkt_ok(pb, xp, feas)) {
            memcpy(x, xp, (size_t)st->nx * sizeof *x);
            return 1;
        }
        /* Release the fixed bound with the most wrong-signed multiplier, if any. */
        int worst = -1;
        double wz = 0.0;
        for (int k = 0; k < st->n; k++) {
            double z = m.bound_mult[k];
            double wrong = side[k] == -1 ? -z : side[k] == 1 ? z : 0.0;
            if (wrong > wz) {
                wz = wrong;
                worst = k;
            }
        }
        if (worst < 0) return 0;
        side[worst] *= 2;
        int any = 0;
        for (int k = 0; k < st->n; k++) any |= side[k] == 1 || side[k] == -1;
        if (!any) return 0;
    }
    return 0;
}

/* One solve from xs into x (caller holds the lock; st->app is built for pb's bounds), warm
 * (the stored multipliers, tiny bound pushes) or cold, polished when it needs it; r filled.
 * *polished = 1 when the polish replaced the answer. The budget is the plan's: st->t0. */
static hp_error one_solve(ipopt_state *st, const hp_problem *pb, const double *xs, int warm,
                          double *x, hp_backend_result *r, int *polished, hp_diag *d)
{
    hp_error e = hpi_ipopt_opt_str(st->app, "warm_start_init_point", warm ? "yes" : "no", d);
    if (e == HP_OK)
        e = hpi_ipopt_opt_num(st->app, "mu_init", warm ? MU_INIT_WARM : MU_INIT_COLD, d);
    if (e != HP_OK) return e;
    st->pb = pb;
    st->iters = 0;
    st->timed_out = 0;
    *polished = 0;
    double obj;
    memcpy(x, xs, (size_t)st->nx * sizeof *x);
    enum ApplicationReturnStatus rc = IpoptSolve(st->app, x, NULL, &obj, st->mult_g, st->mult_xl,
                                                 st->mult_xu, st);
    int forced = atomic_load(&ipopt_forced);
    if (forced != HP_TEST_NO_FORCE) rc = (enum ApplicationReturnStatus)forced;
    int conv;
    map_status(rc, st->timed_out, &conv);
    int finite = 1;
    for (int i = 0; i < st->nx; i++) finite = finite && isfinite(x[i]);
    if (conv && finite && needs_polish(st, pb, x) && polish(st, pb, x)) *polished = 1;
    st->pb = NULL;

    r->raw_code = (int)rc;
    r->iterations = st->iters;
    r->status = map_status(rc, st->timed_out, &r->converged);
    if (!finite) {
        /* Never hand back NaN: the start point is at least inside the bounds. */
        memcpy(x, xs, (size_t)st->nx * sizeof *x);
        r->converged = 0;
        r->status = HP_STATUS_SOLVER_ERROR;
    }
    hpi_backend_clip(pb, x);
    return HP_OK;
}

/* A restart (hpi_multistart_solve): a cold solve; its budget is the plan's (st->t0). */
static int restart_solve(void *ctx, const hp_problem *pb, const double *x0, double left, double *x,
                         hp_backend_result *r)
{
    (void)left;
    int polished;
    return one_solve(ctx, pb, x0, 0, x, r, &polished, NULL) == HP_OK;
}

static hp_error ipopt_solve(void *state, const hp_problem *pb, const double *x0, double *x,
                            hp_backend_result *r, hp_diag *d)
{
    ipopt_state *st = state;
    if (!st || !pb || !x || !r) return hp_diag_set(d, HP_ERR_NULL, "ipopt: NULL argument");
    double xs[HP_PROBLEM_NX_MAX];
    int go;
    hp_error e = hpi_backend_begin("ipopt", pb, st->n, st->nx, x0, xs, r, &go, d);
    if (e != HP_OK || !go) return e;
    /* Warm (previous multipliers, small bound pushes) only when the core said that x0 is
     * this backend's own last converged answer (warm_point). */
    int warm = st->s.warm_start && st->have_prev && st->accepted && x0;
    st->accepted = 0;
    int same_bounds = memcmp(st->ri_lo, pb->ri_lo, (size_t)st->n * sizeof(double)) == 0 &&
                      memcmp(st->ri_hi, pb->ri_hi, (size_t)st->n * sizeof(double)) == 0;

    /* The lock is held over the first solve and its restarts, and the budget starts once it
     * is taken: time spent waiting for another thread's Ipopt is not this plan's. */
    hpi_ipopt_lock();
    st->t0 = hpi_plan_now();
    if (!same_bounds || !st->app || st->rebuild) { /* also retries after a failed rebuild */
        st->rebuild = 0;
        if (st->app) FreeIpoptProblem(st->app);
        st->app = NULL;
        e = build_app(st, pb, d);
        if (e != HP_OK) {
            if (st->app) FreeIpoptProblem(st->app);
            st->app = NULL;
        }
    }
    int polished = 0, kept = 0, ran = 0;
    if (e == HP_OK) e = one_solve(st, pb, xs, warm, x, r, &polished, d);
    if (e == HP_OK && st->s.restarts > 0) {
        /* The first solve's multipliers, for a warm start after it if it is the answer kept
         * (a restart's solve overwrites them). */
        double mg[HP_MAX_BLADDERS], ml[HP_PROBLEM_NX_MAX], mu_[HP_PROBLEM_NX_MAX];
        memcpy(mg, st->mult_g, sizeof mg);
        memcpy(ml, st->mult_xl, sizeof ml);
        memcpy(mu_, st->mult_xu, sizeof mu_);
        kept = hpi_multistart_run(pb, xs, st->s.restarts, st->t0, st->s.max_time, st->s.tolerance,
                                  restart_solve, st, x, r, &ran);
        memcpy(st->mult_g, mg, sizeof mg);
        memcpy(st->mult_xl, ml, sizeof ml);
        memcpy(st->mult_xu, mu_, sizeof mu_);
    }
    hpi_ipopt_unlock();
    if (e != HP_OK) {
        st->have_prev = 0;
        return e;
    }
    /* The stored multipliers belong to the first solve's unpolished point: the next solve
     * starts cold after a polished answer or one a restart found. */
    st->have_prev = r->converged && !polished && kept == 0;
    return HP_OK;
}

static void ipopt_warm_point(void *state, int accepted)
{
    ipopt_state *st = state;
    if (st) st->accepted = accepted;
}

/* "hessian_approximation": 0 the exact Hessian of the Lagrangian (problem_eval.c), 1 Ipopt's
 * limited-memory quasi-Newton approximation (a benchmark peer). */
static hp_error ipopt_set_option(void *state, const char *name, double value, hp_diag *d)
{
    ipopt_state *st = state;
    if (!st || !name) return hp_diag_set(d, HP_ERR_NULL, "ipopt: NULL option");
    if (strcmp(name, "hessian_approximation") == 0) {
        if (value != 0.0 && value != 1.0)
            return hp_diag_set(d, HP_ERR_INVALID,
                               "ipopt: hessian_approximation must be 0 (exact) or 1 "
                               "(limited-memory) (got %g)",
                               value);
        st->lbfgs = value == 1.0;
        st->rebuild = 1;
        st->have_prev = 0;
        return HP_OK;
    }
    return hp_diag_set(d, HP_ERR_INVALID,
                       "ipopt: unknown option '%s' (known: hessian_approximation)", name);
}

/* The load level's HOLD with its tie-breaker on Ipopt (load_ipopt.c). */
static hpi_load_solve_status ipopt_load_hold(const hp_load_model *M, const double xi[6],
                                             const double *lo, const double *hi,
                                             const double *target, const double *start,
                                             int max_iter, int stiffness, double *P, double *F,
                                             int *iterations, int *raw)
{
    return hpi_load_hold_with(hpi_load_hold_ipopt, M, xi, lo, hi, target, start, max_iter,
                              stiffness, P, F, iterations, raw);
}

const hp_backend_ops hpi_backend_ipopt_ops = {
    .name = "ipopt",
    .caps = HP_BACKEND_CERTIFIES | HP_BACKEND_WARM_STARTS | HP_BACKEND_LOAD |
            HP_BACKEND_LOAD_STIFFNESS | HP_BACKEND_ONE_START | HP_BACKEND_RESTARTS,
    .load_hold = ipopt_load_hold,
    .create = ipopt_create,
    .solve = ipopt_solve,
    .destroy = ipopt_destroy,
    .warm_point = ipopt_warm_point,
    .set_option = ipopt_set_option,
};
