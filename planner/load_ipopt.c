/* HOLD's tie-breaker on Ipopt (the reference backend at the load level): the NLP of
 * load_solve.h with exact first and second derivatives. Variables are the pressures in kPa
 * of the bladders that can carry (L_k < U_k); constraints the six equilibrium rows, which
 * are separable in the pressures, so the Lagrangian's Hessian is diagonal:
 *     d²L/dP_k² = obj_factor + sum_r lambda_r·A[r][k]·F_k''(P_k).
 * Every Ipopt call runs under the process-wide Ipopt lock that backend_ipopt.c owns (Debian's
 * Ipopt/MUMPS is not thread-safe); `sb yes`, print_level 0 and option_file_name "" keep
 * the library silent; bound_relax_factor 0 keeps every trial pressure inside its limits. */
#include "planner/ipopt_shared.h"
#include "planner/load_solve.h"

#include <IpStdCInterface.h>
#include <math.h>
#include <string.h>

typedef struct ud {
    const hp_load_hold_nlp *nlp;
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
    if (hp_load_bladder_force(q->M, k, x * 1e3, q->rho[k], &f, &d1, &d2) != HP_OK) {
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
    if (!values) {
        for (int j = 0; j < n; ++j) iRow[j] = jCol[j] = j;
        return TRUE;
    }
    for (int j = 0; j < n; ++j) {
        double F, F1, F2, s = 0.0;
        if (!force(u, j, x[j], &F, &F1, &F2)) return FALSE;
        for (int r = 0; r < m; ++r) s += lambda[r] * q->A[r * q->n + u->idx[j]];
        values[j] = obj_factor + s * F2;
    }
    return TRUE;
}

static int options(IpoptProblem a, int max_iter)
{
    return AddIpoptStrOption(a, "sb", "yes") && AddIpoptIntOption(a, "print_level", 0) &&
           AddIpoptStrOption(a, "option_file_name", "") &&
           AddIpoptNumOption(a, "tol", 1e-12) &&
           AddIpoptNumOption(a, "constr_viol_tol", 1e-12) &&
           AddIpoptNumOption(a, "bound_relax_factor", 0.0) &&
           AddIpoptStrOption(a, "honor_original_bounds", "yes") &&
           AddIpoptIntOption(a, "max_iter", max_iter);
}

hp_load_solve_status hp_load_hold_ipopt(const hp_load_hold_nlp *nlp, double *p, int max_iter,
                                        int *iterations, int *raw)
{
    ud u;
    memset(&u, 0, sizeof u);
    u.nlp = nlp;
    double xl[HP_MAX_BLADDERS], xu[HP_MAX_BLADDERS], x[HP_MAX_BLADDERS], gl[6], gu[6];
    for (int k = 0; k < nlp->n; ++k)
        if (nlp->L[k] < nlp->U[k]) {
            xl[u.nf] = nlp->L[k] * 1e-3;
            xu[u.nf] = nlp->U[k] * 1e-3;
            x[u.nf] = fmin(fmax(p[k] * 1e-3, xl[u.nf]), xu[u.nf]);
            u.idx[u.nf++] = k;
        }
    for (int r = 0; r < 6; ++r) gl[r] = gu[r] = nlp->b[r];
    if (iterations) *iterations = 0;
    if (u.nf == 0) return HP_LOAD_SOLVE_OK; /* nothing to choose */
    hp_ipopt_lock();
    IpoptProblem a = CreateIpoptProblem(u.nf, xl, xu, 6, gl, gu, 6 * u.nf, u.nf, 0, eval_f,
                                        eval_g, eval_grad_f, eval_jac_g, eval_h);
    hp_load_solve_status st = HP_LOAD_SOLVE_ERROR;
    if (a && options(a, max_iter)) {
        double g[6], obj, mg[6] = {0}, ml[HP_MAX_BLADDERS] = {0}, mu[HP_MAX_BLADDERS] = {0};
        enum ApplicationReturnStatus rs = IpoptSolve(a, x, g, &obj, mg, ml, mu, &u);
        if (raw) *raw = (int)rs;
        if (u.failed) st = HP_LOAD_SOLVE_ERROR;
        else if (rs == Solve_Succeeded || rs == Solved_To_Acceptable_Level) st = HP_LOAD_SOLVE_OK;
        else if (rs == Infeasible_Problem_Detected) st = HP_LOAD_SOLVE_UNREACHABLE;
        else if (rs == Maximum_Iterations_Exceeded) st = HP_LOAD_SOLVE_ITERATION_LIMIT;
    }
    if (a) FreeIpoptProblem(a);
    hp_ipopt_unlock();
    if (st == HP_LOAD_SOLVE_OK)
        for (int j = 0; j < u.nf; ++j) p[u.idx[j]] = fmin(fmax(x[j] * 1e3, nlp->L[u.idx[j]]),
                                                          nlp->U[u.idx[j]]);
    return st;
}
