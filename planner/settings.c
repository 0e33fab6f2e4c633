/* Planner settings: defaults and the one validator. */
#include "headplan/hp_planner.h"
#include "planner/settings_check.h"
#include "kinematics/names.h"
#include "planner/plan_range.h"

#include <math.h>
#include <string.h>

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
    memset(&s->load, 0, sizeof s->load); /* no load */
    s->load_geometry = HP_DEFAULT_LOAD_GEOMETRY;
    s->load_tiebreak = HP_DEFAULT_LOAD_TIEBREAK;
    s->restarts = HP_DEFAULT_RESTARTS;
    for (int i = 0; i < 6; ++i) s->auto_pose[i] = HP_DEFAULT_AUTO_POSE;
}

/* Each check accepts only finite values in range; written as !(v > x) so NaN fails. */
const char *hpi_check_level_tolerance(double v)
{
    return (v > 0 && isfinite(v)) ? NULL : "must be finite and > 0";
}

const char *hpi_check_auto_trans(double v)
{
    return (v >= 0 && isfinite(v)) ? NULL : "must be finite and >= 0";
}

const char *hpi_check_auto_rot(double v)
{
    return (v >= 0 && isfinite(v)) ? NULL : "must be finite and >= 0";
}

const char *hpi_check_tolerance(double v)
{
    return (v > 0 && v <= HP_TOLERANCE_MAX) ? NULL : "must be > 0 and at most 1 (mm and degrees)";
}

const char *hpi_check_max_iter(long v)
{
    return (v > 0 && v <= HP_MAX_ITER_MAX) ? NULL : "must be an integer in 1..1000000";
}

const char *hpi_check_max_time(double v)
{
    return (v > 0 && v <= HP_MAX_TIME_MAX) ? NULL : "must be > 0 and at most 3600 s";
}

const char *hpi_check_weight(double v)
{
    return (v >= HP_WEIGHT_MM_PER_DEG_MIN && v <= HP_WEIGHT_MM_PER_DEG_MAX)
               ? NULL
               : "must be in [1e-6, 1e6] (its square and inverse square enter the objective)";
}

const char *hpi_check_restarts(long v)
{
    return (v >= 0 && v <= HP_RESTARTS_MAX) ? NULL : "must be an integer in 0..64";
}

hp_error hp_settings_validate(const hp_settings *s, hp_diag *d)
{
    if (!s) return hp_diag_set(d, HP_ERR_NULL, "settings: NULL");
    if ((int)s->backend < 0 || s->backend >= HP_BACKEND_COUNT_)
        return hp_diag_set(d, HP_ERR_INVALID, "backend: unknown value %d", (int)s->backend);
    if ((int)s->level < 0 || s->level > HP_LEVEL_LOAD)
        return hp_diag_set(d, HP_ERR_INVALID, "level: unknown value %d", (int)s->level);
    const char *why;
    if ((why = hpi_check_level_tolerance(s->level_tolerance)))
        return hp_diag_set(d, HP_ERR_INVALID, "level_tolerance: %s m (got %g)", why,
                           s->level_tolerance);
    if ((why = hpi_check_auto_trans(s->auto_trans)))
        return hp_diag_set(d, HP_ERR_INVALID, "auto_trans: %s m (got %g)", why, s->auto_trans);
    if ((why = hpi_check_auto_rot(s->auto_rot)))
        return hp_diag_set(d, HP_ERR_INVALID, "auto_rot: %s rad (got %g)", why, s->auto_rot);
    if ((why = hpi_check_tolerance(s->tolerance)))
        return hp_diag_set(d, HP_ERR_INVALID, "tolerance: %s (got %g)", why, s->tolerance);
    if ((why = hpi_check_max_iter(s->max_iter)))
        return hp_diag_set(d, HP_ERR_INVALID, "max_iter: %s (got %d)", why, s->max_iter);
    if ((why = hpi_check_max_time(s->max_time)))
        return hp_diag_set(d, HP_ERR_INVALID, "max_time: %s (got %g)", why, s->max_time);
    if ((why = hpi_check_weight(s->weight_mm_per_deg)))
        return hp_diag_set(d, HP_ERR_INVALID, "weight_mm_per_deg: %s (got %g)", why,
                           s->weight_mm_per_deg);
    if (!(s->mu >= 0) || !isfinite(s->mu))
        return hp_diag_set(d, HP_ERR_INVALID, "mu: must be finite and >= 0 (got %g)", s->mu);
    if (s->use_rate_limits != 0 && s->use_rate_limits != 1)
        return hp_diag_set(d, HP_ERR_INVALID, "use_rate_limits: must be 0 or 1 (got %d)",
                           s->use_rate_limits);
    if (s->warm_start != 0 && s->warm_start != 1)
        return hp_diag_set(d, HP_ERR_INVALID, "warm_start: must be 0 or 1 (got %d)", s->warm_start);
    if ((why = hpi_check_restarts(s->restarts)))
        return hp_diag_set(d, HP_ERR_INVALID, "restarts: %s (got %d)", why, s->restarts);
    /* auto_pose as hp_plan checks a correction; its identifiable range needs the layout
     * (hp_planner_create, where auto measures there). */
    int i = hpi_plan_pose_out_of_range(s->auto_pose);
    if (i >= 0)
        return hp_diag_set(d, HP_ERR_INVALID, HPI_AUTO_POSE_NAME " %s: %s (got %g %s)",
                           hpi_pose_component_names[i],
                           isfinite(s->auto_pose[i]) ? HP_PLAN_RANGE_TEXT : "not finite",
                           s->auto_pose[i], i < 3 ? "m" : "rad");
    /* The load: none (mass exactly 0, the default) or one that hp_load_spec_validate
     * accepts; the load level needs one. */
    int has_load = !(s->load.mass == 0.0);
    if (has_load) {
        hp_error e = hp_load_spec_validate(&s->load, d);
        if (e != HP_OK) return e;
    } else if (s->level == HP_LEVEL_LOAD) {
        return hp_diag_set(d, HP_ERR_INVALID,
                           "level: load needs a load (settings load.mass > 0: what the "
                           "bladders carry)");
    }
    if (!hp_level_is_geometry(s->load_geometry)) {
        char names[64];
        return hp_diag_set(d, HP_ERR_INVALID, "load_geometry: must be %s (got %d)",
                           hpi_level_geometry_names(names, sizeof names), (int)s->load_geometry);
    }
    if ((int)s->load_tiebreak < 0 || s->load_tiebreak >= HP_TIE_COUNT_)
        return hp_diag_set(d, HP_ERR_INVALID, "load_tiebreak: unknown value %d",
                           (int)s->load_tiebreak);
    return HP_OK;
}
