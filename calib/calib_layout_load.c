/* The layout fit's forward model at the load level (see hp_calib.h, docs/calibration.md):
 * the pose of a row is where the head rests under its pressures (hp_load_rest), and the
 * Jacobian of that rest in the parameters comes from the implicit function theorem on the
 * equilibrium Q(ξ; θ) = 0: dξ/dθ = K⁻¹·∂Q/∂θ with K = −∂Q/∂ξ exact (hp_load_eval) and
 * ∂Q/∂θ by central differences of hp_load_eval at the fixed rest (no iteration inside, so
 * their noise is rounding only). Every rest is searched from the nominal pose, as the
 * statics themselves do: a start at the measured pose carries the measurement's noise into
 * directions the bladders hold weakly, where the search can lose its way. */
#include "calib/calib_internal.h"
#include "kinematics/linalg.h"
#include "kinematics/load_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define LOAD_FD_LENGTH 1e-6 /* [m] step for offsets and semi-axes: 1 µm */
#define LOAD_FD_MASS 1e-3   /* [kg] step for the mass: Q is linear in it, so exact */

/* The load model of layout L with the load's mass changed by theta's mass entry. */
static hp_error model_at(const lay_ctx *c, const hp_layout *L, const double *theta,
                         hp_load_model *M)
{
    hp_load_spec s = *c->load;
    if (c->mass_j >= 0) s.mass += theta[c->mass_j];
    if (!(s.mass > 0)) return HP_ERR_DOMAIN;
    return hpi_load_model_setup(M, L, &s, c->level, NULL);
}

hp_error calib_load_resid(const lay_ctx *c, const hp_layout *L, const double *theta, double *e,
                          const double (*start)[6], double (*poses)[6])
{
    hp_load_model *M = malloc(sizeof *M);
    if (!M) return HP_ERR_NOMEM;
    hp_error err = model_at(c, L, theta, M);
    for (int i = 0; !err && i < c->n; ++i) {
        double xi[6];
        err = hp_load_rest(M, c->rows[i].pressure, start ? start[i] : NULL, xi, NULL);
        if (err) break;
        if (poses) memcpy(poses[i], xi, sizeof xi);
        for (int j = 0; j < c->dofp; ++j)
            e[i * c->dofp + j] = (c->rows[i].pose[j] - xi[j]) * c->w[j];
    }
    free(M);
    return err;
}

hp_error calib_load_jacobian(const lay_ctx *c, const double *theta, double *J)
{
    int n = c->n, dp = c->dofp, np = c->np;
    hp_load_model *M = malloc(sizeof *M * 3); /* at theta, theta + h, theta − h */
    double(*xi)[6] = malloc(sizeof *xi * (size_t)n);
    double *dQ = malloc(sizeof(double) * (size_t)n * 6 * (size_t)np);
    hp_error err = (!M || !xi || !dQ) ? HP_ERR_NOMEM : HP_OK;
    hp_layout L;
    hp_geom G;
    if (!err) err = calib_layout_apply(c, theta, &L, &G, 0, NULL);
    if (!err) err = model_at(c, &L, theta, &M[0]);
    for (int i = 0; !err && i < n; ++i)
        err = hp_load_rest(&M[0], c->rows[i].pressure, NULL, xi[i], NULL);
    double th[HP_CALIB_MAX_PARAMS];
    for (int j = 0; !err && j < np; ++j) {
        double h = j == c->mass_j ? LOAD_FD_MASS : LOAD_FD_LENGTH;
        memcpy(th, theta, sizeof(double) * (size_t)np);
        for (int s = 0; !err && s < 2; ++s) {
            th[j] = theta[j] + (s ? -h : h);
            err = calib_layout_apply(c, th, &L, &G, 0, NULL);
            if (!err) err = model_at(c, &L, th, &M[1 + s]);
        }
        for (int i = 0; !err && i < n; ++i) {
            double Qp[6], Qm[6];
            err = hp_load_eval(&M[1], xi[i], c->rows[i].pressure, Qp, NULL, NULL, NULL, NULL);
            if (!err)
                err = hp_load_eval(&M[2], xi[i], c->rows[i].pressure, Qm, NULL, NULL, NULL, NULL);
            for (int a = 0; !err && a < 6; ++a)
                dQ[((size_t)i * (size_t)np + (size_t)j) * 6 + (size_t)a] = (Qp[a] - Qm[a]) /
                                                                           (2.0 * h);
        }
    }
    for (int i = 0; !err && i < n; ++i) {
        double Q[6], K[36], ones[6] = {1, 1, 1, 1, 1, 1};
        /* hp_load_eval gives ∂Q/∂ξ = −K. */
        err = hp_load_eval(&M[0], xi[i], c->rows[i].pressure, Q, K, NULL, NULL, NULL);
        for (int j = 0; !err && j < np; ++j) {
            double dx[6];
            /* (∂Q/∂ξ)·dx = −∂Q/∂θ, i.e. dx = dξ/dθ, by the kinematics' QR least squares. */
            if (hpi_kin_damped_lstsq(6, 6, K, &dQ[((size_t)i * (size_t)np + (size_t)j) * 6], ones,
                                     0.0, dx)) {
                err = HP_ERR_NO_CONVERGENCE;
                break;
            }
            for (int a = 0; a < dp; ++a) J[(i * dp + a) * np + j] = -c->w[a] * dx[a];
        }
    }
    free(M);
    free(xi);
    free(dQ);
    return err;
}
