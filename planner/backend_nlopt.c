/* Comparison backends through NLopt 2.7.1.
 *
 * SLSQP works on the full program of problem.h (x = [ξ (mm, deg), ri (mm)], n contact
 * equalities with a tolerance each, ri bounds): the same program Ipopt solves, so the two can
 * be compared point for point.
 *
 * COBYLA works on the reduced program: variables ξ only, objective Σ w (ξ − d)² (plus the
 * pressure tie-breaker evaluated at the implied radii), and 2n inequalities
 * ro_lo_k <= ρ_k(ξ) <= ro_hi_k; the radii come afterwards from the inverse volume law
 * ri_k = ri(ρ_k(ξ)). COBYLA turns each equality into two opposed inequalities and then
 * crawls along the contact manifold with linear models (docs/solver-facts.md: up to 2.4 mm wrong on the
 * full form); the reduced form has 6 variables instead of 14 and only inequalities, which is
 * what COBYLA's linear-programming steps handle well, and its contacts hold exactly by
 * construction.
 *
 * Determinism: nlopt_srand(HP_NLOPT_SEED) right before every optimisation (otherwise NLopt
 * seeds from the clock). Budget: max_time is NLopt's wall-clock maxtime; an NLopt "iteration"
 * here is one evaluation: SLSQP gets maxeval = 4·max_iter (an SQP iteration is one gradient
 * plus a short line search), COBYLA maxeval = (6 + 1)·max_iter (one simplex worth of
 * evaluations per iteration). Reported iterations are evaluations (nlopt_get_numevals). */
#include "planner/backend_common.h"
#include "common/units.h"
#include "planner/backend_testing.h"
#include "planner/clock.h"
#include "planner/multistart.h"

#include <math.h>
#include <nlopt.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

/* Seed of NLopt's random number generator: any fixed value gives reproducible runs. */
#define HP_NLOPT_SEED 20200531UL
#define SLSQP_EVALS_PER_ITER 4
/* Smallest per-constraint tolerance handed to NLopt [mm] (see create_common). */
#define HP_NLOPT_CONTACT_TOL_MIN 1e-10
/* Largest solver tolerance [mm, deg] handed to NLopt, whatever the pose tolerance: its
 * contacts, steps and objective changes are the solve's precision, not the clinical
 * acceptance. A pose tolerance of 0.05 mm used as the contact tolerance let SLSQP return
 * radii 0.05 mm off their contacts, which then held no pose (SOLVER_ERROR); from 1e-8 on,
 * SLSQP's curved-level answers stopped short and came back ITERATION_LIMIT. So a looser
 * tolerance is solved as the default one (measured clean: 60 binding targets per level). */
#define HP_NLOPT_SOLVE_TOL_MAX HP_DEFAULT_TOLERANCE
#define COBYLA_EVALS_PER_ITER 7
/* COBYLA's largest initial trust radius: 1 mm / 1 degree, the size of a typical correction.
 * A solve whose every outer-radius window is narrower starts from the widest window
 * instead (cobyla_step). */
#define COBYLA_INITIAL_STEP 1.0
/* The floor of a COBYLA constraint's scale [mm] (cobyla_scale): a window narrower than the
 * binding tolerance is a held bladder, not a range to resolve. */
#define COBYLA_SCALE_MIN HP_BINDING_TOL_MM

typedef struct nlopt_state {
    nlopt_opt opt;
    int reduced; /* 1: COBYLA's 6-variable form */
    int n, nx;
    hp_settings s;
    const hp_problem *pb; /* during a solve only */
    int eval_failed;
    /* COBYLA: each bladder's constraints are divided by this [mm] (cobyla_scale). */
    double csc[HP_MAX_BLADDERS];
} nlopt_state;

/* Test-only hooks (planner/backend_testing.h): inert unless a test sets them. */
static atomic_int nlopt_fault = HP_TEST_FAULT_NONE;
static atomic_int nlopt_forced = HP_TEST_NO_FORCE;

void hpi_test_nlopt_fault(int fault) { atomic_store(&nlopt_fault, fault); }
void hpi_test_nlopt_force_result(int code) { atomic_store(&nlopt_forced, code); }

static void eval_fail(nlopt_state *st)
{
    st->eval_failed = 1;
    nlopt_force_stop(st->opt);
}

/* ---- full program (SLSQP) ---- */

/* On a failed evaluation every output NLopt reads is still written (SLSQP reads the
 * gradient even after a forced stop), so nothing uninitialised reaches it. */
static double full_objective(unsigned nx, const double *x, double *grad, void *data)
{
    nlopt_state *st = data;
    double f;
    int nan_fault = atomic_load(&nlopt_fault) == HP_TEST_FAULT_NAN_OBJECTIVE;
    if (nan_fault || hpi_problem_objective(st->pb, x, &f, grad, NULL) != HP_OK || !isfinite(f)) {
        if (grad)
            for (unsigned i = 0; i < nx; i++) grad[i] = 0.0;
        /* A NaN objective stops the solve as a failure: SLSQP would otherwise go on from
         * numbers it cannot compare. */
        eval_fail(st);
        return nan_fault ? NAN : HUGE_VAL;
    }
    return f;
}

static void full_constraints(unsigned m, double *c, unsigned nx, const double *x, double *grad,
                             void *data)
{
    nlopt_state *st = data;
    if (atomic_load(&nlopt_fault) == HP_TEST_FAULT_FAIL_CONSTRAINTS ||
        hpi_problem_constraints(st->pb, x, c, grad, NULL, NULL) != HP_OK) {
        for (unsigned k = 0; k < m; k++) c[k] = HUGE_VAL;
        if (grad)
            for (unsigned i = 0; i < m * nx; i++) grad[i] = 0.0;
        eval_fail(st);
    }
}

/* ---- reduced program (COBYLA) ---- */

/* Contact distances [mm] at scaled pose x. */
static hp_error reduced_rho(const hp_problem *pb, const double *x, double *rho_mm)
{
    double xi[6];
    for (int i = 0; i < 6; i++) xi[i] = x[i] * hpi_pose_si_per_scaled(i);
    hp_error e = hpi_contact_eval_g(pb->layout, pb->geom, pb->level, xi, rho_mm, NULL, NULL);
    if (e != HP_OK) return e;
    for (int k = 0; k < pb->n; k++) rho_mm[k] *= 1e3;
    return HP_OK;
}

/* Full x (nx) from the pose: ri_k from ρ_k clipped into [ro_lo_k, ro_hi_k]. */
static hp_error reduced_expand(const hp_problem *pb, const double *xi6, double *x)
{
    double rho[HP_MAX_BLADDERS];
    hp_error e = reduced_rho(pb, xi6, rho);
    if (e != HP_OK) return e;
    memcpy(x, xi6, 6 * sizeof *x);
    for (int k = 0; k < pb->n; k++) {
        double ro = fmin(fmax(rho[k], pb->ro_lo[k]), pb->ro_hi[k]);
        double ri;
        e = hp_iab_ri(&pb->layout->bladders[k].iab, ro * 1e-3, &ri);
        if (e != HP_OK) return e;
        x[6 + k] = ri * 1e3;
    }
    hpi_backend_clip(pb, x);
    return HP_OK;
}

static double reduced_objective(unsigned n6, const double *x, double *grad, void *data)
{
    (void)n6, (void)grad; /* derivative-free */
    nlopt_state *st = data;
    const hp_problem *pb = st->pb;
    double f = 0.0;
    if (atomic_load(&nlopt_fault) == HP_TEST_FAULT_NAN_OBJECTIVE) {
        eval_fail(st);
        return NAN;
    }
    for (int i = 0; i < 6; i++) f += pb->w[i] * (x[i] - pb->d[i]) * (x[i] - pb->d[i]);
    if (pb->mu > 0.0) {
        double full[HP_PROBLEM_NX_MAX];
        double fo;
        if (reduced_expand(pb, x, full) != HP_OK ||
            hpi_problem_objective(pb, full, &fo, NULL, NULL) != HP_OK) {
            eval_fail(st);
            return HUGE_VAL;
        }
        f = fo; /* same pose term, plus the pressure term at the implied radii */
    }
    return f;
}

static void reduced_constraints(unsigned m, double *c, unsigned n6, const double *x, double *grad,
                                void *data)
{
    (void)n6, (void)grad;
    nlopt_state *st = data;
    const hp_problem *pb = st->pb;
    double rho[HP_MAX_BLADDERS];
    if (atomic_load(&nlopt_fault) == HP_TEST_FAULT_FAIL_CONSTRAINTS ||
        reduced_rho(pb, x, rho) != HP_OK) {
        for (unsigned k = 0; k < m; k++) c[k] = HUGE_VAL;
        eval_fail(st);
        return;
    }
    for (int k = 0; k < pb->n; k++) {
        c[2 * k] = (pb->ro_lo[k] - rho[k]) / st->csc[k];
        c[2 * k + 1] = (rho[k] - pb->ro_hi[k]) / st->csc[k];
    }
}

/* ---- lifecycle ---- */

static hp_error nl(nlopt_result r, const char *what, hp_diag *d)
{
    if (r < 0) return hp_diag_set(d, HP_ERR_SOLVER, "nlopt: %s failed (%d)", what, (int)r);
    return HP_OK;
}

/* The tolerance of each contact constraint handed to NLopt [mm]. NLopt's SLSQP returns the
 * best *feasible* point it met, feasible meaning |c_k| <= tol_k: below ~1e-10 mm (3 ulp-ish
 * of rounding in ρ and ro near 30 mm, amplified by the linearisation error of each step) no
 * iterate may qualify and it hands back the start point. Hence the floor. */
static double contact_tol(const hp_settings *s)
{
    return fmax(fmin(s->tolerance, HP_NLOPT_SOLVE_TOL_MAX), HP_NLOPT_CONTACT_TOL_MIN);
}

static hp_error create_common(void **state, const hp_problem *pb, const hp_settings *s, hp_diag *d,
                              int reduced)
{
    if (!state || !pb || !s) return hp_diag_set(d, HP_ERR_NULL, "nlopt: NULL argument");
    *state = NULL;
    hp_error e = hpi_backend_check_problem(pb, d);
    if (e != HP_OK && e != HP_ERR_DOMAIN) return e;
    if (!(s->tolerance > 0.0) || !(s->max_iter > 0) || !(s->max_time > 0.0))
        return hp_diag_set(d, HP_ERR_INVALID, "nlopt: tolerance, max_iter, max_time must be > 0");
    nlopt_state *st = calloc(1, sizeof *st);
    if (!st) return hp_diag_set(d, HP_ERR_NOMEM, "nlopt: out of memory");
    st->reduced = reduced;
    st->n = pb->n;
    st->nx = pb->nx;
    st->s = *s;
    unsigned nv = reduced ? 6u : (unsigned)pb->nx;
    st->opt = nlopt_create(reduced ? NLOPT_LN_COBYLA : NLOPT_LD_SLSQP, nv);
    if (!st->opt) {
        free(st);
        return hp_diag_set(d, HP_ERR_NOMEM, "nlopt: nlopt_create failed");
    }
    const double stol = fmin(s->tolerance, HP_NLOPT_SOLVE_TOL_MAX);
    double tol[2 * HP_MAX_BLADDERS];
    for (int k = 0; k < 2 * HP_MAX_BLADDERS; k++) tol[k] = contact_tol(s);
    for (int k = 0; k < HP_MAX_BLADDERS; k++) st->csc[k] = 1.0;
    double xtol[HP_PROBLEM_NX_MAX];
    for (int i = 0; i < HP_PROBLEM_NX_MAX; i++) xtol[i] = stol;
    int evals_per_iter = reduced ? COBYLA_EVALS_PER_ITER : SLSQP_EVALS_PER_ITER;
    int maxeval = s->max_iter > 100000000 / evals_per_iter ? 100000000
                                                           : s->max_iter * evals_per_iter;
    /* f = Σ w (x − d)²: a change below tolerance² in f is a change below tolerance in x. */
    double ftol = stol * stol;
    if ((e = nl(reduced ? nlopt_set_min_objective(st->opt, reduced_objective, st)
                        : nlopt_set_min_objective(st->opt, full_objective, st),
                "set_min_objective", d)) ||
        (e = nl(reduced ? nlopt_add_inequality_mconstraint(st->opt, 2u * (unsigned)pb->n,
                                                           reduced_constraints, st, tol)
                        : nlopt_add_equality_mconstraint(st->opt, (unsigned)pb->n, full_constraints,
                                                         st, tol),
                "add constraints", d)) ||
        (e = nl(nlopt_set_xtol_abs(st->opt, xtol), "set_xtol_abs", d)) ||
        (e = nl(nlopt_set_ftol_abs(st->opt, ftol), "set_ftol_abs", d)) ||
        (e = nl(nlopt_set_maxeval(st->opt, maxeval), "set_maxeval", d)) ||
        (e = nl(nlopt_set_maxtime(st->opt, s->max_time), "set_maxtime", d))) {
        nlopt_destroy(st->opt);
        free(st);
        return e;
    }
    *state = st;
    return HP_OK;
}

static hp_error slsqp_create(void **state, const hp_problem *pb, const hp_settings *s, hp_diag *d)
{
    return create_common(state, pb, s, d, 0);
}

static hp_error cobyla_create(void **state, const hp_problem *pb, const hp_settings *s, hp_diag *d)
{
    return create_common(state, pb, s, d, 1);
}

static void nlopt_state_destroy(void *state)
{
    nlopt_state *st = state;
    if (!st) return;
    nlopt_destroy(st->opt);
    free(st);
}

/* COBYLA's initial trust radius [mm, deg] for pb. Each ρ_k moves about as far as the pose
 * (unit-scale contact Jacobian rows), so under rate limits the pose can move about as far
 * as the widest outer-radius window allows. A first simplex of 1 mm around windows of
 * 1e-3 mm (rate limits of about 1 Pa) lies almost wholly outside them: COBYLA then spent
 * its budget shrinking it (iteration-limit) or stopped at a vertex still 2e-5 mm from the
 * bounds it should bind (its answer failed the planner's first-order check). */
static double cobyla_step(const hp_problem *pb)
{
    double widest = 0.0;
    for (int k = 0; k < pb->n; k++) widest = fmax(widest, pb->ro_hi[k] - pb->ro_lo[k]);
    return widest > 0.0 ? fmin(COBYLA_INITIAL_STEP, widest) : COBYLA_INITIAL_STEP;
}

/* COBYLA's constraint scales for pb: each bladder's pair divided by its outer-radius window
 * [mm] when that is narrower than 1 mm (floored at COBYLA_SCALE_MIN), with its tolerance
 * divided alike (the same contact tolerance in mm). COBYLA weighs constraint values against
 * the objective's in its merit function and linear models; under rate limits of about 1e-2 Pa
 * the windows are ~1e-5 mm wide, and unscaled constraint values of that size against an
 * objective of order 1 let it wander: one plan at a 0.0112 Pa rate took 2321 evaluations and
 * ended at a point the planner's first-order check refused, where scaled it takes 99 (and the
 * largest of test_rate_window's 160 COBYLA plans 787, within its 1400). Windows of 1 mm and
 * more (no rate limit binds that tight) keep scale 1: the program is the one without it.
 * The constraints are handed to NLopt again only when a scale changed. */
static hp_error cobyla_scale(nlopt_state *st, const hp_problem *pb, hp_diag *d)
{
    double sc[HP_MAX_BLADDERS];
    int changed = 0;
    for (int k = 0; k < pb->n; k++) {
        sc[k] = fmin(1.0, fmax(pb->ro_hi[k] - pb->ro_lo[k], COBYLA_SCALE_MIN));
        changed |= sc[k] != st->csc[k];
    }
    if (!changed) return HP_OK;
    double tol[2 * HP_MAX_BLADDERS];
    for (int k = 0; k < pb->n; k++) {
        st->csc[k] = sc[k];
        tol[2 * k] = tol[2 * k + 1] = contact_tol(&st->s) / sc[k];
    }
    hp_error e = nl(nlopt_remove_inequality_constraints(st->opt), "remove constraints", d);
    if (e == HP_OK)
        e = nl(nlopt_add_inequality_mconstraint(st->opt, 2u * (unsigned)pb->n, reduced_constraints,
                                                st, tol),
               "add constraints", d);
    return e;
}

static hp_status map_result(nlopt_result r, int *converged)
{
    *converged = 0;
    switch (r) {
    case NLOPT_SUCCESS:
    case NLOPT_STOPVAL_REACHED:
    case NLOPT_FTOL_REACHED:
    case NLOPT_XTOL_REACHED:
        *converged = 1;
        return HP_STATUS_REACHED; /* the core decides REACHED or CLOSEST */
    case NLOPT_MAXEVAL_REACHED: return HP_STATUS_ITERATION_LIMIT;
    case NLOPT_MAXTIME_REACHED: return HP_STATUS_TIME_LIMIT;
    default: /* FAILURE, INVALID_ARGS, OUT_OF_MEMORY, FORCED_STOP; ROUNDOFF checked by caller */
        return HP_STATUS_SOLVER_ERROR;
    }
}

/* One optimisation from xs; the point in v (nx values, inside the radius bounds), r's
 * status, raw code, iterations and converged flag set as nlopt_solve reports them. */
static void one_solve(nlopt_state *st, const hp_problem *pb, const double *xs, double *v,
                      hp_backend_result *r)
{
    memcpy(v, xs, (size_t)st->nx * sizeof *v);
    st->pb = pb;
    st->eval_failed = 0;
    nlopt_srand(HP_NLOPT_SEED);
    double fmin = HUGE_VAL;
    nlopt_result rc = nlopt_optimize(st->opt, v, &fmin);
    st->pb = NULL;
    int forced = atomic_load(&nlopt_forced);
    if (forced != HP_TEST_NO_FORCE) rc = (nlopt_result)forced;

    r->raw_code = (int)rc;
    r->iterations = nlopt_get_numevals(st->opt);
    r->status = map_result(rc, &r->converged);

    /* After a failed evaluation the point is not read at all (NLopt may have left it
     * built from numbers it never computed). */
    int finite = !st->eval_failed;
    for (int i = 0; finite && i < (st->reduced ? 6 : st->nx); i++) finite = isfinite(v[i]);
    if (finite && st->reduced) {
        double full[HP_PROBLEM_NX_MAX];
        if (reduced_expand(pb, v, full) == HP_OK) memcpy(v, full, (size_t)st->nx * sizeof *v);
        else finite = 0;
    }
    if (!finite || st->eval_failed) {
        memcpy(v, xs, (size_t)st->nx * sizeof *v);
        r->converged = 0;
        r->status = HP_STATUS_SOLVER_ERROR;
    } else if (rc == NLOPT_ROUNDOFF_LIMITED) {
        /* Ambiguous (docs/solver-facts.md): accept the point only if it is feasible and stationary.
         * Feasibility to 10× the constraint tolerance (1e-9 mm at least): SLSQP's last step
         * is limited by rounding at about that level. */
        double stol = st->s.tolerance < HP_NLOPT_SOLVE_TOL_MAX ? st->s.tolerance
                                                               : HP_NLOPT_SOLVE_TOL_MAX;
        if (hpi_backend_kkt_ok(pb, v, fmax(10.0 * stol, 1e-9))) {
            r->converged = 1;
            r->status = HP_STATUS_REACHED;
        }
    }
    hpi_backend_clip(pb, v);
}

/* One restart (hpi_multistart_solve): SLSQP from x0 with what is left of the budget. */
static int restart_solve(void *ctx, const hp_problem *pb, const double *x0, double left, double *x,
                         hp_backend_result *r)
{
    nlopt_state *st = ctx;
    if (nlopt_set_maxtime(st->opt, left) < 0) return 0;
    one_solve(st, pb, x0, x, r);
    return 1;
}

/* SLSQP cannot tell a local minimum from the closest pose (its stopping tests say nothing
 * about other minima), and the closest pose of a far target can be any of several vertices
 * of the limits (docs/planner.md, Restarts): after a converged answer v that binds a limit
 * it solves again from settings.restarts deterministic starts while max_time lasts
 * (hpi_multistart_run). t0 is when the solve began (the budget is the whole solve's). */
static void restart(nlopt_state *st, const hp_problem *pb, const double *xs, double t0, double *v,
                    hp_backend_result *r)
{
    /* The solve's tolerance, not the pose tolerance: a looser pose tolerance is solved as
     * the default one (create_common), restarts included. */
    const double stol = fmin(st->s.tolerance, HP_NLOPT_SOLVE_TOL_MAX);
    int ran;
    hpi_multistart_run(pb, xs, st->s.restarts, t0, st->s.max_time, stol, restart_solve, st, v, r,
                       &ran);
    if (ran) nlopt_set_maxtime(st->opt, st->s.max_time);
}

static hp_error nlopt_solve(void *state, const hp_problem *pb, const double *x0, double *x,
                            hp_backend_result *r, hp_diag *d)
{
    nlopt_state *st = state;
    if (!st || !pb || !x || !r) return hp_diag_set(d, HP_ERR_NULL, "nlopt: NULL argument");
    double xs[HP_PROBLEM_NX_MAX];
    int go;
    hp_error e = hpi_backend_begin("nlopt", pb, st->n, st->nx, x0, xs, r, &go, d);
    if (e != HP_OK || !go) return e;
    double t0 = st->s.restarts > 0 ? hpi_plan_now() : 0.0;

    {
        /* An uncommanded pose component (weight 0) is fixed at 0, as the core holds it:
         * left free, the solver uses it to meet the contacts. */
        double lb[HP_PROBLEM_NX_MAX], ub[HP_PROBLEM_NX_MAX];
        for (int i = 0; i < 6; i++) {
            double b = pb->w[i] > 0.0 ? HUGE_VAL : 0.0;
            lb[i] = -b, ub[i] = b;
            if (b == 0.0) xs[i] = 0.0;
        }
        for (int k = 0; !st->reduced && k < pb->n; k++)
            lb[6 + k] = pb->ri_lo[k], ub[6 + k] = pb->ri_hi[k];
        if ((e = nl(nlopt_set_lower_bounds(st->opt, lb), "set_lower_bounds", d)) ||
            (e = nl(nlopt_set_upper_bounds(st->opt, ub), "set_upper_bounds", d)) ||
            (st->reduced &&
             ((e = nl(nlopt_set_initial_step1(st->opt, cobyla_step(pb)), "set_initial_step", d)) ||
              (e = cobyla_scale(st, pb, d)))))
            return e;
    }
    double v[HP_PROBLEM_NX_MAX];
    one_solve(st, pb, xs, v, r);
    if (!st->reduced) restart(st, pb, xs, t0, v, r);
    memcpy(x, v, (size_t)st->nx * sizeof *x);
    return HP_OK;
}

/* The load level's HOLD with its tie-breaker on NLopt SLSQP (load_nlopt.c); the
 * derivative-free COBYLA has no load_hold. */
static hpi_load_solve_status slsqp_load_hold(const hp_load_model *M, const double xi[6],
                                             const double *lo, const double *hi,
                                             const double *target, const double *start,
                                             int max_iter, int stiffness, double *P, double *F,
                                             int *iterations, int *raw)
{
    (void)stiffness; /* not in caps: hp_planner_create refuses it */
    return hpi_load_hold_with(hpi_load_hold_nlopt, M, xi, lo, hi, target, start, max_iter, 0, P, F,
                              iterations, raw);
}

const hp_backend_ops hpi_backend_nlopt_slsqp_ops = {
    .name = "nlopt-slsqp",
    .caps = HP_BACKEND_THREAD_SAFE | HP_BACKEND_LOAD | HP_BACKEND_ONE_START | HP_BACKEND_RESTARTS,
    .load_hold = slsqp_load_hold,
    .create = slsqp_create,
    .solve = nlopt_solve,
    .destroy = nlopt_state_destroy,
};

const hp_backend_ops hpi_backend_nlopt_cobyla_ops = {
    .name = "nlopt-cobyla",
    .caps = HP_BACKEND_THREAD_SAFE | HP_BACKEND_ONE_START,
    .create = cobyla_create,
    .solve = nlopt_solve,
    .destroy = nlopt_state_destroy,
};
