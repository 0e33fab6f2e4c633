/* Planning a trace row after row through one hp_planner: the sequence `headplan batch`,
 * `headplan horizon --mode greedy` and the Python Planner.run_trace share.
 *
 * The state before every row is a function of the previous planned row alone: its result
 * becomes the planner's previous answer (hp_planner_set_previous_result: the rate limits of
 * the next plan start from its pressures, the solve starts cold from its pose and radii),
 * so two runs that reach an equal row continue identically (batch's shards rely on it).
 * Before the first planned row the state is the start of the trace: the nominal answer
 * (hp_planner_reset), or the start pressures given to hp_trace_plan_set_start.
 * A row the caller marks as skipped (a bad row of the file) is not planned and passes the
 * state through. With per-row rate limits (hp_trace_plan_create with hs), every row's
 * allowance is min(the bladder's rate_max, hs->rate_max_per_s · the row's interval), the
 * interval before row 0 being hs->start_interval_s; the time stamps must then be finite and
 * increasing. Without them the planner's own per-plan limits apply unchanged.
 *
 * The planner's level, backend and settings are used as they are: the trace is planned at
 * whatever level the planner plans. Units: SI (m, rad, Pa, s). */
#ifndef HP_TRACE_PLAN_H
#define HP_TRACE_PLAN_H

#include "headplan/hp_common.h"
#include "headplan/hp_horizon.h"
#include "headplan/hp_planner.h"
#include "headplan/hp_trace.h"

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct hp_trace_plan hp_trace_plan;

/* Receives every planned row i (0-based index into the rows given) with its result, in order,
 * before the next row is planned (hp_planner_error / hp_planner_message of the planner then
 * speak of this row). A return other than HP_OK stops the run with that error. */
typedef hp_error (*hp_trace_plan_sink)(void *ctx, size_t i, const hp_result *r);

/* Creates a trace plan over planner p, which it borrows (p must outlive it; a caller plans
 * with p through it only). hs NULL: the planner's own per-plan rate limits; else per-row
 * limits from the rows' intervals (hs checked by hp_horizon_settings_validate; only
 * rate_max_per_s and start_interval_s are read). Copies the bladders' rate_max of p's layout
 * now. The state is the start of the trace (the nominal answer). The only call that
 * allocates. HP_ERR_NULL, HP_ERR_INVALID (hs; diag names the field), HP_ERR_NOMEM. */
HP_API hp_error hp_trace_plan_create(hp_planner *p, const hp_horizon_settings *hs,
                                     hp_trace_plan **out, hp_diag *diag);

/* Makes the start of the trace the state: the pressures the bladders hold before row 0 [Pa]
 * (hp_planner_set_previous, applied now), or with pressures NULL the nominal answer. On a
 * refusal diag says "start pressures: REASON" and the state is unchanged. */
HP_API hp_error hp_trace_plan_set_start(hp_trace_plan *tp, const double *pressures, hp_diag *diag);

/* Makes prev the previous planned row (a result hp_plan returned; n, achieved and the
 * bladders' ri, ro and pressure are read), or with prev NULL the start of the trace as last
 * set, so that a run may continue from any row (batch's shards). Copies prev. */
HP_API hp_error hp_trace_plan_set_state(hp_trace_plan *tp, const hp_result *prev);

/* Plans rows[0..T) in order from the current state, handing each planned row to sink (may
 * be NULL; then out, if not NULL, receives the T results, a skipped row's left untouched).
 * skip (may be NULL) marks rows not to plan (skip[i] != 0). The state afterwards is the
 * last planned row. Allocates nothing. Returns HP_OK; HP_ERR_NULL; HP_ERR_INVALID for a
 * row's time stamp with per-row rates ("line N: t_s: ..." in diag, rows before it planned);
 * a planner's call error ("line N: REASON"); or the sink's error. A refused row
 * (status INVALID_INPUT) is a result, not an error. */
HP_API hp_error hp_trace_plan_run(hp_trace_plan *tp, const hp_trace_row *rows,
                                  const unsigned char *skip, size_t T, hp_trace_plan_sink sink,
                                  void *ctx, hp_result *out, hp_diag *diag);

/* The borrowed planner (for its messages). NULL for NULL. */
HP_API hp_planner *hp_trace_plan_planner(const hp_trace_plan *tp);

/* Frees the trace plan (not its planner); safe on NULL. */
HP_API void hp_trace_plan_destroy(hp_trace_plan *tp);

#ifdef __cplusplus
}
#endif
#endif
