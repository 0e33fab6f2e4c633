/* The linear level's forward contact fit as the linear least-squares problem it is: the
 * normal matrix of ρ_lin = rho0 + row·ξ in the free components is a layout constant, so it
 * is scaled and factored once (hpi_kin_linear_fit_prepare) and each fit is two solves with
 * that factor (hpi_kin_linear_fit_solve). The same minimiser as hpi_kin_fit's Levenberg–
 * Marquardt iteration at this level (whose undamped first step solves the same equations),
 * to rounding. */
#include "kinematics/fit_internal.h"
#include "common/dense.h"

#include <math.h>
#include <string.h>

int hpi_kin_linear_fit_prepare(const hp_layout *L, const hp_geom *G, const int free_[6],
                               hp_kin_linear_fit *f)
{
    memset(f, 0, sizeof *f);
    for (int i = 0; i < 6; ++i)
        if ((f->free_[i] = free_[i] != 0)) f->col[f->nf++] = i;
    if (f->nf == 0) return -1;
    double A[36] = {0};
    for (int j = 0; j < f->nf; ++j)
        for (int k = 0; k < f->nf; ++k)
            for (int b = 0; b < L->n; ++b)
                A[j * 6 + k] += G->row[b][f->col[j]] * G->row[b][f->col[k]];
    /* Scaled to unit diagonal, the same condition bound as the fit's normal-equation steps
     * (HP_KIN_NORMAL_MAX_COND): beyond it the general fit (QR) decides. */
    for (int j = 0; j < f->nf; ++j) {
        if (!(A[j * 7] > 0) || !isfinite(A[j * 7])) return -1;
        f->d[j] = 1.0 / sqrt(A[j * 7]);
    }
    for (int j = 0; j < f->nf; ++j)
        for (int k = 0; k < f->nf; ++k) A[j * 6 + k] *= f->d[j] * f->d[k];
    if (!hpi_cholesky(A, 6, f->nf, 0.0, f->chol, 6)) return -1;
    if (!(f->nf * hpi_cholesky_inv_frob2(f->chol, 6, f->nf) <= HP_KIN_NORMAL_MAX_COND)) return -1;
    f->ready = 1;
    return 0;
}

/* One Gauss–Newton step from x: x −= (AᵀA)⁻¹·Aᵀr with r = ρ_lin(x) − target. */
static void step(const hp_kin_linear_fit *f, int n, const hp_geom *G, const double *target,
                 double x[6], double *cost)
{
    double g[6] = {0}, c = 0.0;
    for (int b = 0; b < n; ++b) {
        double r = hpi_geom_linear(G, b, x) - target[b];
        c += r * r;
        for (int j = 0; j < f->nf; ++j) g[j] -= G->row[b][f->col[j]] * r;
    }
    for (int j = 0; j < f->nf; ++j) g[j] *= f->d[j];
    hpi_cholesky_solve(f->chol, 6, f->nf, g);
    for (int j = 0; j < f->nf; ++j) x[f->col[j]] += g[j] * f->d[j];
    *cost = c;
}

hp_error hpi_kin_linear_fit_solve(const hp_kin_linear_fit *f, const hp_layout *L, const hp_geom *G,
                                  const double *target, double xi[6], double *residual_rms)
{
    if (!f->ready) return HP_ERR_INVALID;
    for (int k = 0; k < L->n; ++k)
        if (!isfinite(target[k])) return HP_ERR_INVALID;
    double x[6] = {0}, cost;
    /* The first step solves the problem to the normal equations' accuracy (about
     * nf·eps·cond of the scaled step); the second, from an exact residual, corrects it to
     * rounding, as the iterative fit's second step does. */
    step(f, L->n, G, target, x, &cost);
    step(f, L->n, G, target, x, &cost);
    cost = 0.0;
    for (int k = 0; k < L->n; ++k) {
        double r = hpi_geom_linear(G, k, x) - target[k];
        cost += r * r;
    }
    for (int i = 0; i < 6; ++i)
        if (!isfinite(x[i])) return HP_ERR_NO_CONVERGENCE;
    memcpy(xi, x, sizeof x);
    if (residual_rms) *residual_rms = sqrt(cost / L->n);
    return HP_OK;
}
