/* Planner settings: defaults and the one validator. */
#include "headplan/hp_planner.h"

#include <math.h>

void hp_settings_default(hp_settings *s)
{
    if (!s) return;
    s->backend = HP_DEFAULT_BACKEND;
    s->level = HP_DEFAULT_LEVEL;
    s->level_tolerance = HP_DEFAULT_LEVEL_TOLERANCE;
    s->auto_trans = HP_DEFAULT_AUTO_TRANS;
    s->auto_rot = HP_DEFAULT_AUTO_ROT;
    s->tolerance = HP_DEFAULT_TOLERANCE;
    s->max_iter = HP_DEFAULT_MAX_ITER;
    s->max_time = HP_DEFAULT_MAX_TIME;
    s->weight_mm_per_deg = HP_DEFAULT_WEIGHT_MM_PER_DEG;
    s->mu = HP_DEFAULT_MU;
    s->use_rate_limits = HP_DEFAULT_USE_RATE_LIMITS;
    s->warm_start = HP_DEFAULT_WARM_START;
    s->ipopt_hessian_approx = HP_DEFAULT_IPOPT_HESSIAN_APPROX;
}

hp_error hp_settings_validate(const hp_settings *s, hp_diag *d)
{
    if (!s) return hp_diag_set(d, HP_ERR_NULL, "settings: NULL");
    if ((int)s->backend < 0 || s->backend >= HP_BACKEND_COUNT_)
        return hp_diag_set(d, HP_ERR_INVALID, "backend: unknown value %d", (int)s->backend);
    if ((int)s->level < 0 || s->level > HP_LEVEL_AUTO)
        return hp_diag_set(d, HP_ERR_INVALID, "level: unknown value %d", (int)s->level);
    if (!(s->level_tolerance > 0) || !isfinite(s->level_tolerance))
        return hp_diag_set(d, HP_ERR_INVALID, "level_tolerance: must be finite and > 0 m (got %g)",
                           s->level_tolerance);
    if (!(s->auto_trans >= 0) || !isfinite(s->auto_trans))
        return hp_diag_set(d, HP_ERR_INVALID, "auto_trans: must be finite and >= 0 m (got %g)",
                           s->auto_trans);
    if (!(s->auto_rot >= 0) || !isfinite(s->auto_rot))
        return hp_diag_set(d, HP_ERR_INVALID, "auto_rot: must be finite and >= 0 rad (got %g)",
                           s->auto_rot);
    if (!(s->tolerance > 0) || !isfinite(s->tolerance))
        return hp_diag_set(d, HP_ERR_INVALID, "tolerance: must be finite and > 0 (got %g)",
                           s->tolerance);
    if (!(s->max_iter > 0))
        return hp_diag_set(d, HP_ERR_INVALID, "max_iter: must be > 0 (got %d)", s->max_iter);
    if (!(s->max_time > 0) || !isfinite(s->max_time))
        return hp_diag_set(d, HP_ERR_INVALID, "max_time: must be finite and > 0 s (got %g)",
                           s->max_time);
    if (!(s->weight_mm_per_deg > 0) || !isfinite(s->weight_mm_per_deg))
        return hp_diag_set(d, HP_ERR_INVALID,
                           "weight_mm_per_deg: must be finite and > 0 (got %g)",
                           s->weight_mm_per_deg);
    if (!(s->mu >= 0) || !isfinite(s->mu))
        return hp_diag_set(d, HP_ERR_INVALID, "mu: must be finite and >= 0 (got %g)", s->mu);
    if (s->use_rate_limits != 0 && s->use_rate_limits != 1)
        return hp_diag_set(d, HP_ERR_INVALID, "use_rate_limits: must be 0 or 1 (got %d)",
                           s->use_rate_limits);
    if (s->warm_start != 0 && s->warm_start != 1)
        return hp_diag_set(d, HP_ERR_INVALID, "warm_start: must be 0 or 1 (got %d)",
                           s->warm_start);
    if (s->ipopt_hessian_approx != 0 && s->ipopt_hessian_approx != 1)
        return hp_diag_set(d, HP_ERR_INVALID, "ipopt_hessian_approx: must be 0 or 1 (got %d)",
                           s->ipopt_hessian_approx);
    return HP_OK;
}
