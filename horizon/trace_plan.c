/* A trace planned row after row through one planner (hp_trace_plan.h): the state carried
 * from the previous planned row, the per-row rate limits from the rows' intervals. */
#include "headplan/hp_trace_plan.h"
#include "horizon/horizon_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* What the planner holds before the next row, and whether it still has to be told. */
typedef enum { STATE_START, STATE_ROW } state_kind;

struct hp_trace_plan {
    hp_planner *p;
    int row_rates;                 /* per-row limits from the intervals */
    hp_horizon_settings hs;        /* with row_rates: rate_max_per_s, start_interval_s */
    double scene[HP_MAX_BLADDERS]; /* the bladders' rate_max before any row replaced it */
    int have_start;                /* the start is the pressures below, not the nominal */
    double start[HP_MAX_BLADDERS];
    state_kind kind;
    int pending;    /* the state is not yet the planner's */
    hp_result prev; /* with STATE_ROW: the previous planned row's result */
    long prev_line;
};

hp_error hp_trace_plan_create(hp_planner *p, const hp_horizon_settings *hs, hp_trace_plan **out,
                              hp_diag *d)
{
    if (out) *out = NULL;
    if (!p || !out) return hp_diag_set(d, HP_ERR_NULL, "trace plan: NULL argument");
    const hp_layout *L = hp_planner_layout(p);
    if (!L) return hp_diag_set(d, HP_ERR_STATE, "trace plan: the planner is not built");
    if (hs) {
        hp_error e = hp_horizon_settings_validate(hs, d);
        if (e != HP_OK) return e;
    }
    hp_trace_plan *tp = calloc(1, sizeof *tp);
    if (!tp) return hp_diag_set(d, HP_ERR_NOMEM, "trace plan: out of memory");
    tp->p = p;
    tp->row_rates = hs != NULL;
    if (hs) tp->hs = *hs;
    /* Copied before the first row's allowance replaces the planner's own copy. */
    hpi_horizon_scene_rates(L, tp->scene);
    tp->kind = STATE_START;
    tp->pending = 1;
    *out = tp;
    return HP_OK;
}

hp_error hp_trace_plan_set_start(hp_trace_plan *tp, const double *pressures, hp_diag *d)
{
    if (!tp) return hp_diag_set(d, HP_ERR_NULL, "trace plan: NULL argument");
    if (pressures) {
        hp_error e = hp_planner_set_previous(tp->p, pressures);
        if (e != HP_OK) return hp_diag_set(d, e, "start pressures: %s", hp_planner_error(tp->p));
        memcpy(tp->start, pressures, sizeof(double) * (size_t)hp_planner_layout(tp->p)->n);
    }
    tp->have_start = pressures != NULL;
    tp->kind = STATE_START;
    tp->pending = pressures == NULL; /* the planner holds the start pressures already */
    return HP_OK;
}

hp_error hp_trace_plan_set_state(hp_trace_plan *tp, const hp_result *prev)
{
    if (!tp) return HP_ERR_NULL;
    tp->kind = prev ? STATE_ROW : STATE_START;
    if (prev) tp->prev = *prev;
    tp->prev_line = 0;
    tp->pending = 1;
    return HP_OK;
}

/* Tells the planner the state before the next row, if it does not hold it yet. */
static hp_error apply_state(hp_trace_plan *tp, hp_diag *d)
{
    if (!tp->pending) return HP_OK;
    if (tp->kind == STATE_ROW) {
        const hp_error e = hp_planner_set_previous_result(tp->p, &tp->prev);
        if (e != HP_OK)
            return hp_diag_set(d, e, "line %ld: %s", tp->prev_line, hp_planner_error(tp->p));
    } else if (tp->have_start) {
        const hp_error e = hp_planner_set_previous(tp->p, tp->start);
        if (e != HP_OK) return hp_diag_set(d, e, "start pressures: %s", hp_planner_error(tp->p));
    } else {
        hp_planner_reset(tp->p);
    }
    tp->pending = 0;
    return HP_OK;
}

/* The per-row allowance of row t (rows[t - 1] the previous row given, t the index). */
static hp_error apply_rates(hp_trace_plan *tp, const hp_trace_row *rows, size_t t, hp_diag *d)
{
    if (!tp->row_rates) return HP_OK;
    double dt = NAN; /* hpi_horizon_row_dt writes it on HP_OK */
    hp_error e = hpi_horizon_row_dt(&tp->hs, rows, t, &dt, d);
    if (e != HP_OK) return e;
    const int n = hp_planner_layout(tp->p)->n;
    double delta[HP_MAX_BLADDERS];
    hpi_horizon_row_rates(tp->scene, n, &tp->hs, dt, delta);
    e = hp_planner_set_rate_max(tp->p, delta);
    if (e != HP_OK) return hp_diag_set(d, e, "line %ld: rate limit", rows[t].line);
    return HP_OK;
}

hp_error hp_trace_plan_run(hp_trace_plan *tp, const hp_trace_row *rows, const unsigned char *skip,
                           size_t T, hp_trace_plan_sink sink, void *ctx, hp_result *out, hp_diag *d)
{
    if (!tp || (T && !rows)) return hp_diag_set(d, HP_ERR_NULL, "trace plan: NULL argument");
    for (size_t t = 0; t < T; ++t) {
        if (skip && skip[t]) continue; /* the state passes through */
        hp_error e = apply_state(tp, d);
        if (e == HP_OK) e = apply_rates(tp, rows, t, d);
        if (e != HP_OK) return e;
        hp_result *r = out && !sink ? &out[t] : &tp->prev;
        e = hp_plan(tp->p, rows[t].correction, r);
        if (e != HP_OK)
            return hp_diag_set(d, e, "line %ld: %s", rows[t].line, hp_planner_error(tp->p));
        /* Every planned row, refused ones included (their safe output), is the next state. */
        if (r != &tp->prev) tp->prev = *r;
        tp->kind = STATE_ROW;
        tp->prev_line = rows[t].line;
        tp->pending = 1;
        if (sink && (e = sink(ctx, t, r)) != HP_OK) return e;
    }
    return HP_OK;
}

hp_planner *hp_trace_plan_planner(const hp_trace_plan *tp) { return tp ? tp->p : NULL; }

void hp_trace_plan_destroy(hp_trace_plan *tp) { free(tp); }
