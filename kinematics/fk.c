/* Forward contact kinematics: the pose whose contact distances best fit measured outer
 * radii, by Levenberg–Marquardt with Marquardt's column scaling. Each step is a damped
 * least-squares solve by QR (linalg_eigen.cpp), never the normal equations, so the pitch
 * column's small lever arm does not square the conditioning. */
#include "kin_internal.h"
#include "kin_geom.h"
#include "linalg.h"

#include <math.h>
#include <string.h>

#define FK_MAX_ITERS 200
/* A step whose effect on every radius is below this [m] ends the iteration: 1e-15 m is a
 * few ulps of a 30 mm radius, the resolution of the residual itself. */
#define FK_STEP_TOL 1e-15
#define FK_LAMBDA_MAX 1e12

static double sumsq(int n, const double *v)
{
    double s = 0.0;
    for (int i = 0; i < n; ++i) s += v[i] * v[i];
    return s;
}

/* Residual r = rho(xi) − ro and, if Jr is not NULL, its Jacobian in the nf free columns
 * listed in col[]. */
static hp_error residual(const hp_layout *L, const hp_geom *G, hp_level level, const double *ro,
                         const double xi[6], int nf, const int *col, double *r, double *Jr)
{
    double rho[HP_MAX_BLADDERS], J[HP_MAX_BLADDERS * 6];
    hp_error err = hp_contact_eval_g(L, G, level, xi, rho, Jr ? J : NULL, NULL);
    if (err) return err;
    for (int k = 0; k < L->n; ++k) {
        r[k] = rho[k] - ro[k];
        if (Jr)
            for (int j = 0; j < nf; ++j) Jr[k * nf + j] = J[k * 6 + col[j]];
    }
    return HP_OK;
}

hp_error hp_contact_fit_g(const hp_layout *L, const hp_geom *G, hp_level level,
                          const double *target, const int free_[6], const double x0[6],
                          double xi[6], double *residual_rms, int *iters)
{
    if (!L || !G || !target || !free_ || !x0 || !xi) return HP_ERR_NULL;
    if (level != HP_LEVEL_LINEAR && level != HP_LEVEL_PLANE && level != HP_LEVEL_SURFACE)
        return HP_ERR_INVALID;
    for (int k = 0; k < L->n; ++k)
        if (!isfinite(target[k])) return HP_ERR_INVALID;
    for (int i = 0; i < 6; ++i)
        if (free_[i] && !isfinite(x0[i])) return HP_ERR_INVALID;
    int n = L->n, col[6], nf = 0;
    for (int i = 0; i < 6; ++i)
        if (free_[i]) col[nf++] = i;
    double x[6];
    for (int i = 0; i < 6; ++i) x[i] = free_[i] ? x0[i] : 0.0;
    if (nf == 0) {
        memcpy(xi, x, sizeof x);
        return HP_OK;
    }
    double r[HP_MAX_BLADDERS], Jr[HP_MAX_BLADDERS * 6], rt[HP_MAX_BLADDERS];
    hp_error err = residual(L, G, level, target, x, nf, col, r, Jr);
    if (err) return err;
    double cost = sumsq(n, r), lambda = 1e-3;
    int it = 0, done = 0;
    while (!done && it < FK_MAX_ITERS) {
        ++it;
        double D[6], dx[6], xt[6];
        for (int j = 0; j < nf; ++j) {
            double s = 0.0;
            for (int k = 0; k < n; ++k) s += Jr[k * nf + j] * Jr[k * nf + j];
            D[j] = s > 0 ? sqrt(s) : 1.0;
        }
        if (cost == 0.0) break;
        if (hp_kin_damped_lstsq(n, nf, Jr, r, D, lambda, dx) != 0) return HP_ERR_NO_CONVERGENCE;
        double stepsize = 0.0;
        for (int j = 0; j < nf; ++j) stepsize = fmax(stepsize, fabs(D[j] * dx[j]));
        memcpy(xt, x, sizeof xt);
        for (int j = 0; j < nf; ++j) xt[col[j]] += dx[j];
        err = residual(L, G, level, target, xt, nf, col, rt, NULL);
        double ct = err == HP_OK ? sumsq(n, rt) : INFINITY;
        if (ct <= cost) {
            memcpy(x, xt, sizeof x);
            cost = ct;
            err = residual(L, G, level, target, x, nf, col, r, Jr);
            if (err) return err;
            lambda = fmax(lambda * 0.1, 1e-15);
            if (stepsize <= FK_STEP_TOL) done = 1;
        } else {
            lambda *= 10.0;
            /* No descent at any damping: the fit is at its minimum to rounding. */
            if (lambda > FK_LAMBDA_MAX || stepsize <= FK_STEP_TOL) done = 1;
        }
    }
    if (!done && cost != 0.0) return HP_ERR_NO_CONVERGENCE;
    memcpy(xi, x, sizeof x);
    if (residual_rms) *residual_rms = sqrt(cost / n);
    if (iters) *iters = it;
    return HP_OK;
}

hp_error hp_contact_fk_g(const hp_layout *L, const hp_geom *G, hp_level level, const double *ro,
                         const double *xi0, double xi[6], double *residual_rms, int *iters)
{
    if (!L || !G || !ro || !xi) return HP_ERR_NULL;
    if (level != HP_LEVEL_LINEAR && level != HP_LEVEL_PLANE && level != HP_LEVEL_SURFACE)
        return HP_ERR_INVALID;
    int n = L->n;
    int dof = L->head.shape == HP_HEAD_SPHERE ? 3 : 6;
    if (n < dof) return HP_ERR_INVALID;
    for (int k = 0; k < n; ++k)
        if (!(ro[k] > 0) || !isfinite(ro[k])) return HP_ERR_INVALID;
    double x[6] = {0};
    if (xi0) {
        for (int i = 0; i < 6; ++i) {
            if (!isfinite(xi0[i])) return HP_ERR_INVALID;
            x[i] = xi0[i];
        }
    }
    int free_[6];
    for (int i = 0; i < 6; ++i) free_[i] = i < dof;
    return hp_contact_fit_g(L, G, level, ro, free_, x, xi, residual_rms, iters);
}

hp_error hp_contact_fit(const hp_layout *L, hp_level level, const double *target,
                        const int free_[6], const double x0[6], double xi[6],
                        double *residual_rms, int *iters)
{
    if (!L || !target || !free_ || !x0 || !xi) return HP_ERR_NULL;
    hp_geom G;
    if (hp_geom_derive(L, &G, NULL) != HP_OK) return HP_ERR_INVALID;
    return hp_contact_fit_g(L, &G, level, target, free_, x0, xi, residual_rms, iters);
}

hp_error hp_contact_fk(const hp_layout *L, hp_level level, const double *ro,
                       const double *xi0, double xi[6], double *residual_rms, int *iters)
{
    if (!L || !ro || !xi) return HP_ERR_NULL;
    hp_geom G;
    if (hp_geom_derive(L, &G, NULL) != HP_OK) return HP_ERR_INVALID;
    return hp_contact_fk_g(L, &G, level, ro, xi0, xi, residual_rms, iters);
}
