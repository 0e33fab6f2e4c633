/* HOLD's tie-breaker on Ipopt (the reference backend at the load level): the NLP of
 * load_solve.h with exact first and second derivatives. Variables are the pressures in kPa
 * of the bladders that can carry (L_k < U_k); constraints the six equilibrium rows, which
 * are separable in the pressures, so the Lagrangian's Hessian is diagonal:
 *     d²L/dP_k² = obj_factor + sum_r lambda_r·A[r][k]·F_k''(P_k).
 * The minimum-holding-stiffness objective (load_stiffness.c) couples the pressures through
 * the eigen-decomposition of K, so with it the Hessian is the dense lower triangle.
 * Every Ipopt call runs under the process-wide Ipopt lock and with the library's shared
 * option set (planner/ipopt_shared.h: silent, bounds never relaxed, so every trial pressure
 * stays inside its limits). */
#include "planner/ipopt_shared.h"
#include "planner/load_solve.h"

#include <IpStdCInterface.h>
#include <math.h>
#include <string.h>

typedef struct ud {
    const hp_load_hold_nlp *nlp;
    const hp_load_stiff *stiff;   /* the stiffness objective, NULL: the distance */
    int nf, idx[HP_MAX_BLADDERS]; /* variable j is bladder idx[j] */
    double fixedF[6];             /* the fixed bladders' share of each row (0: they carry 0) */
    int failed;
} ud;

/* F, F', F'' of variable j at x (kPa); per kPa and kPa². */
static int force(ud *u, int j, double x, double *F, double *F1, double *F2)
{
    const hp_load_hold_nlp *q = u->nlp;
    int k = u->idx[j];
    double f, d1, d2;
    if (hpi_load_bladder_force(q->M, k, x * 1e3, q->rho[k], &f, &d1, &d2) != HP_OK) {
        u->failed = 1;
        return 0;
    }
    *F = f;
    *F1 = d1 * 1e3;
    *F2 = d2 * 1e6;
    return 1;
}

static Bool eval_f(Index n, Number *x, Bool new_x, Number *obj, UserDataPtr p)
{
    (void)new_x;
    ud *u = p;
    if (u->stiff) {
        if (hpi_load_stiff_eval(u->stiff, n, u->idx, x, obj, NULL, NULL, NULL) != 0) {
            u->failed = 1;
            return FALSE;
        }
        return TRUE;
    }
    double v = 0.0;
    for (int j = 0; j < n; ++j) {
        double e = x[j] - u->nlp->target[u->idx[j]] * 1e-3;
        v += 0.5 * e * e;
    }
    *obj = v;
    return TRUE;
}

static Bool eval_grad_f(Index n, Number *x, Bool new_x, Number *g, UserDataPtr p)
{
    (void)new_x;
    ud *u = p;
    if (u->stiff) {
        if (hpi_load_stiff_eval(u->stiff, n, u->idx, x, NULL, g, NULL, NULL) != 0) {
            u->failed = 1;
            return FALSE;
        }
        return TRUE;
    }
    for (int j = 0; j < n; ++j) g[j] = x[j] - u->nlp->target[u->idx[j]] * 1e-3;
    return TRUE;
}

static Bool eval_g(Index n, Number *x, Bool new_x, Index m, Number *g, UserDataPtr p)
{
    (void)new_x;
    ud *u = p;
    const hp_load_hold_nlp *q = u->nlp;
    for (int r = 0; r < m; ++r) g[r] = u->fixedF[r];
    for (int j = 0; j < n; ++j) {
        double F, F1, F2;
        if (!force(u, j, x[j], &F, &F1, &F2)) return FALSE;
        for (int r = 0; r < m; ++r) g[r] += q->A[r * q->n + u->idx[j]] * F;
    }
    return TRUE;
}

static Bool eval_jac_g(Index n, Number *x, Bool new_x, Index m, Index nele, Index *iRow,
                       Index *jCol, Number *values, UserDataPtr p)
{
    (void)new_x;
    (void)nele;
    ud *u = p;
    const hp_load_hold_nlp *q = u->nlp;
    if (!values) {
        for (int r = 0; r < m; ++r)
            for (int j = 0; j < n; ++j) {
                iRow[r * n + j] = r;
                jCol[r * n + j] = j;
            }
        return TRUE;
    }
    for (int j = 0; j < n; ++j) {
        double F, F1, F2;
        if (!force(u, j, x[j], &F, &F1, &F2)) return FALSE;
        for (int r = 0; r < m; ++r) values[r * n + j] = q->A[r * q->n + u->idx[j]] * F1;
    }
    return TRUE;
}

static Bool eval_h(Index n, Number *x, Bool new_x, Number obj_factor, Index m, Number *lambda,
                   Bool new_lambda, Index nele, Index *iRow, Index *jCol, Number *values,
                   UserDataPtr p)
{
    (void)new_x;
    (void)new_lambda;
    (void)nele;
    ud *u = p;
    const hp_load_hold_nlp *q = u->nlp;
    /* Distance: the diagonal (entry j at j). Stiffness: the lower triangle row by row
     * (entry of (j, l), l <= j, at j(j+1)/2 + l). */
    if (!values) {
        for (int j = 0, e = 0; j < n; ++j)
            for (int l = u->stiff ? 0 : j; l <= j; ++l, ++e) {
                iRow[e] = j;
                jCol[e] = l;
            }
        return TRUE;
    }
    double Hs[HP_MAX_BLADDERS * HP_MAX_BLADDERS];
    if (u->stiff && hpi_load_stiff_eval(u->stiff, n, u->idx, x, NULL, NULL, Hs, NULL) != 0) {
        u->failed = 1;
        return FALSE;
    }
    for (int j = 0, e = 0; j < n; ++j) {
        double F, F1, F2, s = 0.0;
        if (!force(u, j, x[j], &F, &F1, &F2)) return FALSE;
        for (int r = 0; r < m; ++r) s += lambda[r] * q->A[r * q->n + u->idx[j]];
        if (u->stiff) {
            for (int l = 0; l < j; ++l) values[e++] = obj_factor * Hs[j * n + l];
            values[e++] = obj_factor * Hs[j * n + j] + s * F2;
        } else {
            values[e++] = obj_factor + s * F2;
        }
    }
    return TRUE;
}

/* Tolerances: 1e-12 on the equilibrium rows (N) always; on the optimality of the distance
 * tie-breaker 1e-12 (a convex problem: it gets there), of the stiffness one 1e-9 (a
 * soft minimum of eigenvalues, whose rounding is ~1e-12 of K's largest). The CPU-time
 * budget is Ipopt's own generous one: the iteration budget bounds the solve. */
static int options(IpoptProblem a, int max_iter, int stiff)
{
    return hpi_ipopt_base_options(a, stiff ? 1e-9 : 1e-12, max_iter, 1e6, NULL) == HP_OK &&
           AddIpoptNumOption(a, "constr_viol_tol", 1e-12);
}

hpi_load_solve_status hpi_load_hold_ipopt(const hp_load_hold_nlp *nlp, double *p, int max_iter,
                                          int *iterations, int *raw)
{
    ud u;
    memset(&u, 0, sizeof u);
    u.nlp = nlp;
    hp_load_stiff S;
    if (nlp->stiffness) {
        if (hpi_load_stiff_init(&S, nlp->M, nlp->xi, nlp->target) != HP_OK)
            return HP_LOAD_SOLVE_ERROR;
        u.stiff = &S;
    }
    double xl[HP_MAX_BLADDERS], xu[HP_MAX_BLADDERS], x[HP_MAX_BLADDERS], gl[6], gu[6];
    u.nf = hpi_load_hold_vars(nlp, p, u.idx, xl, xu, x);
    for (int r = 0; r < 6; ++r) gl[r] = gu[r] = nlp->b[r];
    if (iterations) *iterations = 0;
    if (u.nf == 0) return HP_LOAD_SOLVE_OK; /* nothing to choose */
    hpi_ipopt_lock();
    int nh = u.stiff ? u.nf * (u.nf + 1) / 2 : u.nf;
    IpoptProblem a = CreateIpoptProblem(u.nf, xl, xu, 6, gl, gu, 6 * u.nf, nh, 0, eval_f, eval_g,
                                        eval_grad_f, eval_jac_g, eval_h);
    hpi_load_solve_status st = HP_LOAD_SOLVE_ERROR;
    if (a && options(a, max_iter, u.stiff != NULL)) {
        double g[6], obj, mg[6] = {0}, ml[HP_MAX_BLADDERS] = {0}, mu[HP_MAX_BLADDERS] = {0};
        enum ApplicationReturnStatus rs = IpoptSolve(a, x, g, &obj, mg, ml, mu, &u);
        if (raw) *raw = (int)rs;
        if (u.failed) st = HP_LOAD_SOLVE_ERROR;
        else if (rs == Solve_Succeeded || rs == Solved_To_Acceptable_Level) st = HP_LOAD_SOLVE_OK;
        else if (rs == Infeasible_Problem_Detected) st = HP_LOAD_SOLVE_UNREACHABLE;
        /* The stiffness objective is not convex: a budget-limited iterate is still a
         * candidate, and the caller's equilibrium check decides whether it holds. */
        else if (rs == Maximum_Iterations_Exceeded)
            st = u.stiff ? HP_LOAD_SOLVE_OK : HP_LOAD_SOLVE_ITERATION_LIMIT;
    }
    if (a) FreeIpoptProblem(a);
    hpi_ipopt_unlock();
    if (st == HP_LOAD_SOLVE_OK) hpi_load_hold_answer(nlp, x, u.idx, u.nf, p);
    return st;
}
