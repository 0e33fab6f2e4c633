/* HOLD's tie-breaker on NLopt SLSQP: the NLP of load_solve.h (variables: the carrying
 * bladders' pressures in kPa; objective ½·sum (P − t)²; six equality rows, vector-valued
 * with their exact Jacobian; the pressure box as bounds). The NLopt object is created and
 * freed per solve (NLopt allocates inside). SLSQP is deterministic (no random start); the
 * equality tolerance is 1e-12 N per row. */
#include "planner/load_solve.h"

#include <math.h>
#include <nlopt.h>
#include <string.h>

typedef struct nl_ud {
    const hp_load_hold_nlp *nlp;
    int nf, idx[HP_MAX_BLADDERS];
    int failed;
} nl_ud;

static double objective(unsigned n, const double *x, double *grad, void *data)
{
    nl_ud *u = data;
    double v = 0.0;
    for (unsigned j = 0; j < n; ++j) {
        double e = x[j] - u->nlp->target[u->idx[j]] * 1e-3;
        v += 0.5 * e * e;
        if (grad) grad[j] = e;
    }
    return v;
}

static void rows(unsigned m, double *result, unsigned n, const double *x, double *grad, void *data)
{
    nl_ud *u = data;
    const hp_load_hold_nlp *q = u->nlp;
    for (unsigned r = 0; r < m; ++r) result[r] = -q->b[r];
    for (unsigned j = 0; j < n; ++j) {
        int k = u->idx[j];
        double F, d1, d2;
        if (hpi_load_bladder_force(q->M, k, x[j] * 1e3, q->rho[k], &F, &d1, &d2) != HP_OK) {
            u->failed = 1;
            F = d1 = 0.0;
        }
        for (unsigned r = 0; r < m; ++r) {
            double a = q->A[(size_t)r * (size_t)q->n + (size_t)k];
            result[r] += a * F;
            if (grad) grad[r * n + j] = a * d1 * 1e3;
        }
    }
}

hpi_load_solve_status hpi_load_hold_nlopt(const hp_load_hold_nlp *nlp, double *p, int max_iter,
                                          int *iterations, int *raw)
{
    nl_ud u;
    memset(&u, 0, sizeof u);
    u.nlp = nlp;
    double xl[HP_MAX_BLADDERS], xu[HP_MAX_BLADDERS], x[HP_MAX_BLADDERS], tol[6];
    u.nf = hpi_load_hold_vars(nlp, p, u.idx, xl, xu, x);
    if (iterations) *iterations = 0;
    if (u.nf == 0) return HP_LOAD_SOLVE_OK;
    for (int r = 0; r < 6; ++r) tol[r] = 1e-12;
    nlopt_opt o = nlopt_create(NLOPT_LD_SLSQP, (unsigned)u.nf);
    if (!o) return HP_LOAD_SOLVE_ERROR;
    hpi_load_solve_status st = HP_LOAD_SOLVE_ERROR;
    double fmin_ = 0.0;
    if (nlopt_set_lower_bounds(o, xl) > 0 && nlopt_set_upper_bounds(o, xu) > 0 &&
        nlopt_set_min_objective(o, objective, &u) > 0 &&
        nlopt_add_equality_mconstraint(o, 6, rows, &u, tol) > 0 &&
        nlopt_set_xtol_abs1(o, 1e-12) > 0 && nlopt_set_ftol_rel(o, 1e-15) > 0 &&
        nlopt_set_maxeval(o, 50 * max_iter) > 0) {
        nlopt_result rc = nlopt_optimize(o, x, &fmin_);
        if (raw) *raw = (int)rc;
        /* ROUNDOFF_LIMITED (−4) is ambiguous: the caller's equilibrium check decides. */
        if (u.failed) st = HP_LOAD_SOLVE_ERROR;
        else if (rc > 0 || rc == NLOPT_ROUNDOFF_LIMITED) st = HP_LOAD_SOLVE_OK;
        else st = HP_LOAD_SOLVE_ERROR;
    }
    nlopt_destroy(o);
    if (st == HP_LOAD_SOLVE_OK) hpi_load_hold_answer(nlp, x, u.idx, u.nf, p);
    return st;
}
