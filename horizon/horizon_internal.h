/* Internal: what the horizon planners (horizon/horizon_*.c) share. Not installed. */
#ifndef HP_PLANNER_HORIZON_INTERNAL_H
#define HP_PLANNER_HORIZON_INTERNAL_H

#include "headplan/hp_horizon.h"

/* Sets the per-plan rate limit [Pa] of every bladder for the next hp_plan calls (planner.c;
 * each > 0, +inf for none). HP_ERR_NULL / HP_ERR_INVALID (nothing changes). When none is
 * left finite the cycle bounds return to the static ones at once (hp_plan then leaves them).
 * HP_ERR_STATE if they could not (not for a planner hp_planner_create accepted). */
hp_error hp_planner_set_rate_max(hp_planner *p, const double *rate_max);

/* Objective weight of pose component i (mm², deg² / weight_mm_per_deg²), 0 when the layout
 * does not command it. */
/* The planner's own words for its last hp_plan (its error, else its note), or "". */
const char *hp_horizon_rh_reason(const hp_horizon_rh *rh);

/* Puts "line N: reason" of the first row hp_plan refused (status INVALID_INPUT) into d, the
 * planner's own words as batch prints them: *noted says whether one already is. */
void hp_horizon_note_refusal(hp_diag *d, int *noted, const hp_result *r, long line,
                             const char *reason);

double hp_horizon_weight(const hp_settings *s, const int commanded[6], int i);

/* Δ [Pa] of every bladder for a row interval dt [s]. */
void hp_horizon_row_rates(const hp_layout *L, const hp_horizon_settings *hs, double dt,
                          double *delta);

/* The rate limits are met by at most this much less than Δ in the offline NLP [Pa], so the
 * returned pressures satisfy |ΔP| <= Δ exactly despite Ipopt's constraint tolerance. */
#define HP_HORIZON_RATE_MARGIN 1e-3

/* Test access to the offline NLP of T rows (horizon_offline.c): at x (T·(6+n), scaled) its
 * objective f, gradient grad (T·nx), constraints g (T·2n), dense Jacobian jac (T·2n × T·nx,
 * row-major) and the dense lower triangle of the Lagrangian's Hessian
 * obj_factor·∇²f + Σ lambda_i ∇²g_i (T·nx × T·nx), all from the callbacks Ipopt gets and
 * their sparsity patterns. Allocates. */
hp_error hp_horizon_nlp_dense(const hp_layout *L, const hp_settings *settings,
                              const hp_horizon_settings *hs, const hp_trace_row *rows, int T,
                              const double *p0, const double *x, double obj_factor,
                              const double *lambda, double *f, double *grad, double *g,
                              double *jac, double *hess);

#endif
