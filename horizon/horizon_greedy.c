/* The greedy plan: each row planned alone through the library's trace call
 * (hp_trace_plan), from the previous row's answer, under that row's own rate allowance. */
#include "headplan/hp_trace_plan.h"
#include "horizon/horizon_internal.h"
#include "planner/nominal.h"

#include <string.h>

/* Greedy's sink: each planned row into the horizon's output, the first refusal noted. */
typedef struct greedy_ctx {
    const hp_trace_row *rows;
    hp_horizon_row *out;
    hp_planner *p;
    hp_diag *d;
    int refused;
} greedy_ctx;

static hp_error greedy_row(void *ctx, size_t t, const hp_result *r)
{
    greedy_ctx *g = ctx;
    const char *why = hp_planner_error(g->p);
    hpi_horizon_note_refusal(g->d, &g->refused, r, g->rows[t].line,
                             *why ? why : hp_planner_note(g->p));
    hpi_horizon_row_from_result(g->rows + t, r, r->n, g->out + t);
    return HP_OK;
}

hp_error hp_horizon_greedy(const hp_layout *L, const hp_settings *settings,
                           const hp_horizon_settings *hs, const hp_trace_row *rows, size_t T,
                           const double *p_start, hp_horizon_row *out, hp_diag *d)
{
    if (!L || !hs || (T && (!rows || !out)))
        return hp_diag_set(d, HP_ERR_NULL, "greedy: NULL argument");
    hp_error e = hp_horizon_settings_validate(hs, d);
    if (e == HP_OK) e = hpi_horizon_check_rows_at(L, rows, T, d);
    if (e != HP_OK) return e;
    hp_planner *p = NULL;
    hp_trace_plan *tp = NULL;
    if ((e = hp_planner_create(L, settings, &p, d)) != HP_OK) return e;
    if (d) d->text[0] = '\0';
    double start[HP_MAX_BLADDERS];
    const hp_layout *PL = hp_planner_layout(p);
    /* The load level without start pressures starts where its planner does after create
     * (no previous plan: headplan solve's and batch's first row). */
    const int own_start = !p_start && hp_planner_level(p) == HP_LEVEL_LOAD;
    if (p_start) memcpy(start, p_start, sizeof(double) * (size_t)PL->n);
    else if (!own_start) e = hp_horizon_nominal_pressures(PL, start, d);
    if (e == HP_OK) e = hp_trace_plan_create(p, hs, &tp, d);
    if (e == HP_OK && !own_start) e = hp_trace_plan_set_start(tp, start, d);
    greedy_ctx g = {rows, out, p, d, 0};
    if (e == HP_OK) e = hp_trace_plan_run(tp, rows, NULL, T, greedy_row, &g, NULL, d);
    hp_trace_plan_destroy(tp);
    hp_planner_destroy(p);
    return e;
}
