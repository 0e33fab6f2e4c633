/* Wall stress as a safe limit: the hoop stress at the inner surface, and the largest inner
 * radius (on the stable branch) at which it stays below a bound.
 *
 * At the inner surface sigma_rr = −P and sigma_tt − sigma_rr = C1(l² − l⁻⁴) − C2(l⁻² − l⁴)
 * with l = ri/Ri, so sigma_tt(ri) = −P(ri) + C1(l² − l⁻⁴) − C2(l⁻² − l⁴) in closed form
 * (hp_iab_wall_stress at r = ri). For l >= 1 on the stable branch it rises with l: the
 * difference term rises (its derivative C1(2l + 4l⁻⁵) + C2(2l⁻³ + 4l³) > 0) faster than
 * the pressure does (tests/iab/test_iab_stress.c samples it for the catalogue's materials),
 * so a bound on it is a bound on the radius, found by bisection. */
#include "iab_internal.h"

#include <math.h>

hp_error hp_iab_hoop_stress_inner(const hp_iab *b, double ri, double *sigma)
{
    if (!sigma) return HP_ERR_NULL;
    double s_rr;
    return hp_iab_wall_stress(b, ri, ri, &s_rr, sigma);
}

hp_error hp_iab_stress_radius(const hp_iab *b, double sigma_max, double ri_cap, double *ri)
{
    if (!b || !ri) return HP_ERR_NULL;
    hp_error e = hp_iab_validate(b, NULL);
    if (e) return e;
    if (!(sigma_max > 0) || !isfinite(sigma_max) || !(ri_cap > b->Ri) || !isfinite(ri_cap))
        return HP_ERR_INVALID;
    double s;
    if ((e = hp_iab_hoop_stress_inner(b, ri_cap, &s))) return e;
    if (s <= sigma_max) {
        *ri = ri_cap;
        return HP_OK;
    }
    double lo = b->Ri, hi = ri_cap; /* stress 0 at Ri, above the bound at ri_cap */
    for (int it = 0; it < 200 && hi - lo > 4e-16 * hi; ++it) {
        double mid = 0.5 * (lo + hi);
        if ((e = hp_iab_hoop_stress_inner(b, mid, &s))) return e;
        if (s <= sigma_max) lo = mid;
        else hi = mid;
    }
    *ri = lo; /* the side that meets the bound */
    return HP_OK;
}
