/* Internal: what the horizon planners (horizon/horizon_*.c) share. Not installed. */
#ifndef HP_PLANNER_HORIZON_INTERNAL_H
#define HP_PLANNER_HORIZON_INTERNAL_H

#include "headplan/hp_horizon.h"

/* The interval before row t [s] (hs->start_interval_s for row 0), checked: the row's time
 * stamp finite and after the previous row's. HP_ERR_INVALID with "line N: t_s: ..." in d. */
hp_error hpi_horizon_row_dt(const hp_horizon_settings *hs, const hp_trace_row *rows, size_t t,
                            double *dt, hp_diag *d);

/* Objective weight of pose component i (mm², deg² / weight_mm_per_deg²), 0 when the layout
 * does not command it. */
/* The planner's own words for its last hp_plan (its error, else its note), or "". */
const char *hpi_horizon_rh_reason(const hp_horizon_rh *rh);

/* Test access to the receding horizon's solve: the interior-point iterations of every call
 * so far, and a switch to the reference solve (every call from a cold start with fixed
 * centring, up to 100 iterations and a tolerance 100 times tighter than the default: the
 * converged answer a faster solve is held to). */
long hpi_horizon_rh_iterations(const hp_horizon_rh *rh);
/* The mean root-find steps per contact distance of every call so far: the ellipsoid head's
 * distances at the surface level (0 where none is solved: the plane and linear levels, a
 * sphere head); each row's distances start from where the row was last evaluated. */
double hpi_horizon_rh_dist_steps(const hp_horizon_rh *rh);
void hpi_horizon_rh_reference(hp_horizon_rh *rh);

/* A sinusoid on a linear trend, x(t) = a + e·τ + b·cos ωτ + c·sin ωτ with τ = t − t0: the
 * periodic prediction of one pose component (HP_PREDICT_PERIODIC). */
typedef struct hpi_periodic {
    double t0, omega, a, e, b, c;
} hpi_periodic;

/* Fits f to count rows (times t, increasing; values x[stride·k]), t0 the last row's time:
 * the period is twice the mean interval between the signal's crossings of its trend line
 * (with a hysteresis of a quarter of its largest deviation from the line), and a, e, b, c
 * are the least-squares fit over the rows of the last two periods. Returns 0, f untouched,
 * when no whole period shows (fewer than three crossings) or the fit is not finite. */
int hpi_horizon_periodic_fit(const double *t, const double *x, int stride, int count,
                             hpi_periodic *f);
double hpi_horizon_periodic_at(const hpi_periodic *f, double t);

/* hp_horizon_check_rows with the refused row's line in the message. */
hp_error hpi_horizon_check_rows_at(const hp_layout *L, const hp_trace_row *rows, size_t T,
                                   hp_diag *d);

/* The output row o of trace row in planned as r (n bladders). */
void hpi_horizon_row_from_result(const hp_trace_row *in, const hp_result *r, int n,
                                 hp_horizon_row *o);
/* The refusal of a receding or offline plan at the load level (HP_ERR_INVALID, the plan
 * named in d): those plans solve the contact levels' program over many rows; the load level
 * is planned greedy, one row at a time. */
hp_error hpi_horizon_load_refused(const char *plan, hp_diag *d);

/* Puts "line N: reason" of the first row hp_plan refused (status INVALID_INPUT) into d, the
 * planner's own words as batch prints them: *noted says whether one already is. */
void hpi_horizon_note_refusal(hp_diag *d, int *noted, const hp_result *r, long line,
                              const char *reason);

/* The status of a planned row as hp_plan labels an answer, from the row's own desired pose
 * (SI), its commanded part xc (hp_pose_commanded_part) and the achieved pose: REACHED when
 * every commanded component is within tol (mm or degrees) of xc, UNCOMMANDED when it is but
 * desired − xc (the part the layout cannot observe) exceeds tol somewhere, CLOSEST otherwise.
 * *err: the largest commanded error (mm or degrees). */
hp_status hpi_horizon_label(const int commanded[6], const double desired[6], const double xc[6],
                            const double achieved[6], double tol, double *err);

/* An iterate of the receding horizon's interior point this close (mm or degrees, every
 * commanded component) to the commanded part of the row's desired pose aims at the desired
 * pose itself: the difference is the solver's stopping accuracy (steps of 1e-9, a smoothness
 * weight of 1e-6 mm² per kPa²), not a choice of the plan, and hp_plan then meets the pose
 * to its own tolerance when no limit binds. */
#define HP_HORIZON_AIM_TOL 1e-6

double hpi_horizon_weight(const hp_settings *s, const int commanded[6], int i);

/* The scene's per-row rate limits rate_max[k] [Pa] of a layout, copied before a planner is
 * given any row's allowance: hp_planner_set_rate_max overwrites the planner's own copy, so
 * its layout no longer holds the scene's limits after the first row. */
void hpi_horizon_scene_rates(const hp_layout *L, double *rate_max);

/* Δ [Pa] of each of n bladders for a row interval dt [s]: min(rate_max[k], per-second limit
 * · dt), rate_max the scene's limits (hpi_horizon_scene_rates). */
void hpi_horizon_row_rates(const double *rate_max, int n, const hp_horizon_settings *hs, double dt,
                           double *delta);

/* The rate limits are met by at most this much less than Δ in the offline NLP [Pa], so the
 * returned pressures satisfy |ΔP| <= Δ exactly despite Ipopt's constraint tolerance. */
#define HP_HORIZON_RATE_MARGIN 1e-3

/* An allowance of at most this [Pa] holds the bladder's pressure in the offline plan: a rate
 * row that narrow (at most twice the margin) cannot be kept by an inequality Ipopt meets only
 * to its constraint tolerance, and a 1e-300 kPa/s limit made its bounds ±5e-302 kPa, which
 * Ipopt could not solve. The row is posed as an equality and the answer copies the previous
 * row's pressure and radius exactly (then checked like every row: contact, limits, pose). */
#define HP_HORIZON_HOLD_PA (2 * HP_HORIZON_RATE_MARGIN)

/* Test access to the offline NLP of T rows (horizon_offline.c): at x (T·(6+n), scaled) its
 * objective f, gradient grad (T·nx), constraints g (T·2n), dense Jacobian jac (T·2n × T·nx,
 * row-major) and the dense lower triangle of the Lagrangian's Hessian
 * obj_factor·∇²f + Σ lambda_i ∇²g_i (T·nx × T·nx), all from the callbacks Ipopt gets and
 * their sparsity patterns. Allocates. */
hp_error hpi_horizon_nlp_dense(const hp_layout *L, const hp_settings *settings,
                               const hp_horizon_settings *hs, const hp_trace_row *rows, int T,
                               const double *p0, const double *x, double obj_factor,
                               const double *lambda, double *f, double *grad, double *g,
                               double *jac, double *hess);

#endif
