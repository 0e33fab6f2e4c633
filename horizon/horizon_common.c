/* Horizon settings, per-row rate limits from time stamps, study metrics. */
#include "horizon/horizon_internal.h"
#include "planner/nominal.h"
#include "planner/plan_range.h"
#include "planner/problem_setup.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void hp_horizon_settings_default(hp_horizon_settings *s)
{
    if (!s) return;
    s->rate_max_per_s = HP_DEFAULT_RATE_PER_S;
    s->smooth = HP_DEFAULT_SMOOTH;
    s->start_interval_s = HP_DEFAULT_START_INTERVAL;
    s->horizon = HP_DEFAULT_HORIZON;
    s->prediction = HP_PREDICT_HOLD;
    s->velocity_rows = HP_DEFAULT_VELOCITY_ROWS;
    s->rh_max_iter = HP_DEFAULT_RH_MAX_ITER;
    s->window = 0;
    s->overlap = 0;
    s->offline_tol = HP_DEFAULT_OFFLINE_TOL;
    s->offline_max_iter = HP_DEFAULT_OFFLINE_MAX_ITER;
    s->offline_max_time = HP_DEFAULT_OFFLINE_MAX_TIME;
}

hp_error hp_horizon_settings_validate(const hp_horizon_settings *s, hp_diag *d)
{
    if (!s) return hp_diag_set(d, HP_ERR_NULL, "horizon settings: NULL");
    if (!(s->rate_max_per_s > 0)) /* +inf allowed: no limit */
        return hp_diag_set(d, HP_ERR_INVALID, "rate_max_per_s: must be > 0 Pa/s (got %g)",
                           s->rate_max_per_s);
    if (!(s->smooth >= 0 && s->smooth <= 1))
        return hp_diag_set(d, HP_ERR_INVALID, "smooth: must be in [0, 1] mm²/kPa² (got %g)",
                           s->smooth);
    if (!(s->start_interval_s > 0 && isfinite(s->start_interval_s)))
        return hp_diag_set(d, HP_ERR_INVALID, "start_interval_s: must be finite and > 0 (got %g)",
                           s->start_interval_s);
    if (s->horizon < 1 || s->horizon > HP_HORIZON_MAX)
        return hp_diag_set(d, HP_ERR_INVALID, "horizon: must be in 1..%d rows (got %d)",
                           HP_HORIZON_MAX, s->horizon);
    if (s->prediction != HP_PREDICT_HOLD && s->prediction != HP_PREDICT_VELOCITY &&
        s->prediction != HP_PREDICT_PERIODIC)
        return hp_diag_set(d, HP_ERR_INVALID, "prediction: unknown value %d", (int)s->prediction);
    if (s->velocity_rows < 2 || s->velocity_rows > HP_HORIZON_MAX)
        return hp_diag_set(d, HP_ERR_INVALID, "velocity_rows: must be in 2..%d (got %d)",
                           HP_HORIZON_MAX, s->velocity_rows);
    if (s->rh_max_iter < 1 || s->rh_max_iter > 100)
        return hp_diag_set(d, HP_ERR_INVALID, "rh_max_iter: must be in 1..100 (got %d)",
                           s->rh_max_iter);
    if (s->window < 0)
        return hp_diag_set(d, HP_ERR_INVALID, "window: must be >= 0 rows (got %d)", s->window);
    if (s->overlap < 0 || (s->window > 0 && s->overlap >= s->window) ||
        (s->window == 0 && s->overlap != 0))
        return hp_diag_set(d, HP_ERR_INVALID,
                           "overlap: must be >= 0 and < window (got %d, window %d)", s->overlap,
                           s->window);
    if (!(s->offline_tol > 0 && s->offline_tol <= 1e-2))
        return hp_diag_set(d, HP_ERR_INVALID, "offline_tol: must be in (0, 1e-2] (got %g)",
                           s->offline_tol);
    if (s->offline_max_iter < 1)
        return hp_diag_set(d, HP_ERR_INVALID, "offline_max_iter: must be > 0 (got %d)",
                           s->offline_max_iter);
    if (!(s->offline_max_time > 0 && isfinite(s->offline_max_time)))
        return hp_diag_set(d, HP_ERR_INVALID, "offline_max_time: must be finite and > 0 s (got %g)",
                           s->offline_max_time);
    return HP_OK;
}

double hpi_horizon_weight(const hp_settings *s, const int commanded[6], int i)
{
    if (commanded && !commanded[i]) return 0.0;
    return i < 3 ? 1.0 : 1.0 / (s->weight_mm_per_deg * s->weight_mm_per_deg);
}

hp_status hpi_horizon_label(const int commanded[6], const double desired[6], const double xc[6],
                            const double achieved[6], double tol, double *err)
{
    double e = 0;
    int unc = 0;
    for (int i = 0; i < 6; ++i) {
        double s = i < 3 ? HP_MM_PER_M : HP_DEG_PER_RAD;
        if (commanded[i]) e = fmax(e, fabs(achieved[i] - xc[i]) * s);
        unc |= fabs(desired[i] - xc[i]) * s > tol;
    }
    *err = e;
    return e <= tol ? (unc ? HP_STATUS_UNCOMMANDED : HP_STATUS_REACHED) : HP_STATUS_CLOSEST;
}

void hpi_horizon_scene_rates(const hp_layout *L, double *rate_max)
{
    for (int k = 0; k < L->n; ++k) rate_max[k] = L->bladders[k].rate_max;
}

void hpi_horizon_row_rates(const double *rate_max, int n, const hp_horizon_settings *hs, double dt,
                           double *delta)
{
    double per_s = isfinite(hs->rate_max_per_s) ? hs->rate_max_per_s * dt : INFINITY;
    for (int k = 0; k < n; ++k) delta[k] = fmin(rate_max[k], per_s);
}

double hp_horizon_start_interval(const hp_trace_row *rows, size_t T, double fallback)
{
    if (!rows || T < 2) return fallback;
    double dt = rows[1].t - rows[0].t;
    return dt > 0 && isfinite(dt) ? dt : fallback;
}

hp_error hpi_horizon_row_dt(const hp_horizon_settings *hs, const hp_trace_row *rows, size_t t,
                            double *dt, hp_diag *d)
{
    if (!isfinite(rows[t].t))
        return hp_diag_set(d, HP_ERR_INVALID, "line %ld: t_s: not finite", rows[t].line);
    *dt = hs->start_interval_s;
    if (t > 0) {
        *dt = rows[t].t - rows[t - 1].t;
        if (!(*dt > 0))
            return hp_diag_set(d, HP_ERR_INVALID,
                               "line %ld: t_s: %.17g s is not after the previous row's %.17g s",
                               rows[t].line, rows[t].t, rows[t - 1].t);
    }
    return HP_OK;
}

hp_error hp_horizon_rates(const hp_layout *L, const hp_horizon_settings *hs,
                          const hp_trace_row *rows, size_t T, double *delta, hp_diag *d)
{
    if (!L || !hs || (!rows && T) || (!delta && T))
        return hp_diag_set(d, HP_ERR_NULL, "horizon rates: NULL argument");
    double scene[HP_MAX_BLADDERS];
    hpi_horizon_scene_rates(L, scene);
    for (size_t t = 0; t < T; ++t) {
        double dt = NAN; /* hpi_horizon_row_dt writes it on HP_OK; set for -O3's flow analysis */
        hp_error e = hpi_horizon_row_dt(hs, rows, t, &dt, d);
        if (e != HP_OK) return e;
        hpi_horizon_row_rates(scene, L->n, hs, dt, delta + t * (size_t)L->n);
    }
    return HP_OK;
}

hp_error hp_horizon_nominal_pressures(const hp_layout *L, double *p_start, hp_diag *d)
{
    if (!L || !p_start) return hp_diag_set(d, HP_ERR_NULL, "nominal pressures: NULL argument");
    hp_geom G;
    hp_diag sub;
    sub.text[0] = '\0';
    hp_error e = hpi_geom_derive(L, &G, &sub);
    if (e != HP_OK) return hp_diag_set(d, e, "nominal pressures: %s", sub.text);
    int bad = 0;
    e = hpi_nominal_pressures_of(L, &G, p_start, &bad);
    if (e != HP_OK)
        return hp_diag_set(d, e, "bladder %s: nominal pressure: %s", L->bladders[bad].name,
                           hp_error_message(e));
    return HP_OK;
}

hp_error hp_horizon_check_rows(const hp_layout *L, const hp_trace_row *rows, size_t T, size_t *bad,
                               hp_diag *d)
{
    if (!L || (T && !rows)) return hp_diag_set(d, HP_ERR_NULL, "horizon rows: NULL argument");
    hp_identifiable id;
    hp_error e = hp_layout_identify(L, &id);
    if (e != HP_OK) return hp_diag_set(d, e, "layout: %s", hp_error_message(e));
    char why[HP_DIAG_MAX];
    for (size_t t = 0; t < T; ++t)
        if (!hpi_plan_desired_ok(&id, rows[t].correction, why)) {
            if (bad) *bad = t;
            return hp_diag_set(d, HP_ERR_INVALID, "%s", why);
        }
    return HP_OK;
}

hp_error hpi_horizon_check_rows_at(const hp_layout *L, const hp_trace_row *rows, size_t T,
                                   hp_diag *d)
{
    size_t bad = 0;
    hp_diag sub = {{0}};
    hp_error e = hp_horizon_check_rows(L, rows, T, &bad, &sub);
    if (e == HP_ERR_INVALID) return hp_diag_set(d, e, "line %ld: %s", rows[bad].line, sub.text);
    if (e != HP_OK) return hp_diag_set(d, e, "%s", sub.text);
    return HP_OK;
}

void hpi_horizon_row_from_result(const hp_trace_row *in, const hp_result *r, int n,
                                 hp_horizon_row *o)
{
    o->t = in->t;
    memcpy(o->desired, in->correction, sizeof o->desired);
    memcpy(o->achieved, r->achieved, sizeof o->achieved);
    for (int k = 0; k < n; ++k) {
        o->ri[k] = r->bladders[k].ri;
        o->pressure[k] = r->bladders[k].pressure;
    }
    o->status = r->status;
}

hp_error hpi_horizon_load_refused(const char *plan, hp_diag *d)
{
    return hp_diag_set(d, HP_ERR_INVALID,
                       "%s: the scene is planned at the load level, whose plans hold the head's "
                       "weight one row at a time: plan it with --mode greedy (or give "
                       "model.level surface, plane or linear to plan it without the weight)",
                       plan);
}

void hpi_horizon_note_refusal(hp_diag *d, int *noted, const hp_result *r, long line,
                              const char *reason)
{
    if (*noted || r->status != HP_STATUS_INVALID_INPUT) return;
    *noted = 1;
    hp_diag_set(d, HP_OK, "line %ld: %s", line, *reason ? reason : "invalid correction");
}

hp_error hp_horizon_measure(const hp_horizon_row *out, size_t T, int n, const double *p_start,
                            const hp_settings *settings, const hp_horizon_settings *hs,
                            double tol_mm, double tol_deg, hp_horizon_metrics *m)
{
    if (!out || !p_start || !settings || !hs || !m) return HP_ERR_NULL;
    if (!(tol_mm > 0 && tol_deg > 0) || n < 1 || n > HP_MAX_BLADDERS || T == 0)
        return HP_ERR_INVALID;
    memset(m, 0, sizeof *m);
    double sq[6] = {0}, outside_rows = 0;
    for (size_t t = 0; t < T; ++t) {
        const hp_horizon_row *o = &out[t];
        int outside = 0;
        for (int i = 0; i < 6; ++i) {
            double s = i < 3 ? HP_MM_PER_M : HP_DEG_PER_RAD;
            double e = (o->achieved[i] - o->desired[i]) * s;
            sq[i] += e * e;
            m->max[i] = fmax(m->max[i], fabs(e));
            m->pose_cost += hpi_horizon_weight(settings, NULL, i) * e * e;
            outside |= fabs(e) > (i < 3 ? tol_mm : tol_deg);
        }
        double dt = t ? o->t - out[t - 1].t : hs->start_interval_s;
        if (outside) {
            m->time_outside += dt;
            outside_rows += 1;
        }
        const double *prev = t ? out[t - 1].pressure : p_start;
        for (int k = 0; k < n; ++k) {
            double dp = o->pressure[k] - prev[k];
            m->travel += fabs(dp);
            m->cost += hs->smooth * (dp * 1e-3) * (dp * 1e-3);
        }
    }
    for (int i = 0; i < 6; ++i) m->rms[i] = sqrt(sq[i] / (double)T);
    m->cost += m->pose_cost;
    m->rows_outside = outside_rows / (double)T;
    return HP_OK;
}
