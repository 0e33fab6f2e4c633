/* The load level's entry criterion: the sag a kinematic plan would leave uncorrected. */
#include "headplan/hp_load.h"
#include "load_internal.h"

#include <math.h>
#include <stdio.h>

hp_error hp_load_predicted_sag(const hp_load_model *M, double *sag, double *k_gravity)
{
    if (!M || !sag) return HP_ERR_NULL;
    const hp_layout *L = &M->layout;
    double P[HP_MAX_BLADDERS], ro[HP_MAX_BLADDERS], xi[6] = {0}, Q[6], dQ[36];
    for (int k = 0; k < L->n; ++k) {
        double ri, rho0 = M->geom.rho0[k];
        hp_error err = hp_iab_ri(&L->bladders[k].iab, rho0, &ri);
        if (!err) err = hp_iab_ik(&L->bladders[k].iab, ri, &P[k]);
        if (err) return err;
        ro[k] = rho0; /* touching: the free radius is the contact distance */
    }
    /* right = 1: the stiffness of the contact branch at delta = 0. */
    hp_error err = hpi_load_eval_radii(M, xi, P, ro, NULL, 1, Q, dQ, NULL, NULL, NULL);
    if (err) return err;
    double g = 0.0, kg = 0.0;
    for (int a = 0; a < 3; ++a) g += M->spec.gravity[a] * M->spec.gravity[a];
    g = sqrt(g);
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b)
            kg -= M->spec.gravity[a] / g * dQ[a * 6 + b] * M->spec.gravity[b] / g;
    /* Below a millinewton per metre nothing holds the head: the nominal pressures are zero
     * up to rounding (~1e-12 Pa), and so is any "stiffness" they give. */
    *sag = kg > 1e-3 ? M->spec.mass * g / kg : INFINITY;
    if (k_gravity) *k_gravity = kg;
    return HP_OK;
}

hp_error hp_load_auto_choose(const hp_load_model *M, double tol, int *use_load, double *sag,
                             char *why, size_t len)
{
    if (!M || !use_load) return HP_ERR_NULL;
    if (!(tol > 0) || !isfinite(tol)) return HP_ERR_INVALID;
    double s, kg;
    hp_error err = hp_load_predicted_sag(M, &s, &kg);
    if (err) return err;
    *use_load = s > tol;
    if (sag) *sag = s;
    if (why && len) {
        if (isinf(s))
            snprintf(why, len,
                     "load: nothing is inflated at the nominal pose, so the head's "
                     "%.3g N weight is held by no stiffness (predicted sag unbounded)",
                     M->spec.mass * HP_GRAVITY);
        else
            snprintf(why, len,
                     "%s: predicted sag %.4g mm (weight %.4g N over %.4g N/mm "
                     "along gravity) %s tolerance %.4g mm",
                     *use_load ? "load" : "kinematic", s * 1e3, M->spec.mass * HP_GRAVITY,
                     kg * 1e-3, *use_load ? ">" : "<=", tol * 1e3);
    }
    return HP_OK;
}
