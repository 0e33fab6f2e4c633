/* Planning over a horizon: a trace of desired corrections planned as a whole (offline), row by
 * row (greedy) or N rows ahead at every row (receding horizon), under the same limits.
 *
 * The common problem (docs/horizon.md): rows t = 0..T−1 with time stamps t_t and desired
 * corrections d_t; at every row the per-row limits of hp_plan (pressure, stretch, the stable
 * branch, contact kept at the planner's contact level), and between consecutive rows a rate
 * limit per bladder
 *     |P_t,k − P_t−1,k| <= Δ_t,k = min(rate_max_k, rate_max_per_s · (t_t − t_t−1)),
 * rate_max_k the bladder's per-row limit (hp_bladder.rate_max) and rate_max_per_s the
 * per-second limit of hp_horizon_settings. Row 0 is planned from the start pressures, held
 * start_interval_s before it. Cost: Σ_t ‖ξ_t − d_t‖²_W (W of hp_settings: mm², and degrees²
 * divided by weight_mm_per_deg²) + smooth · Σ_t,k ((P_t,k − P_t−1,k) / 1 kPa)².
 *
 * Greedy: hp_plan per row with the rate limits carried. Offline: all rows in one sparse NLP
 * on Ipopt (the best tracking any planner can reach under the limits), in overlapping
 * windows for long traces. Receding horizon: at every row the next N rows, with a predicted
 * desired pose, by a primal-dual interior-point solver in a preallocated workspace; the first row
 * is then applied through hp_plan on the realtime backend, so every limit holds exactly.
 *
 * Units: SI (m, rad, Pa, s) like hp_planner.h; the smoothness weight is mm² per kPa². */
#ifndef HP_HORIZON_H
#define HP_HORIZON_H

#include "headplan/hp_common.h"
#include "headplan/hp_planner.h"
#include "headplan/hp_trace.h"

#include <math.h>
#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Largest receding horizon (rows). */
#define HP_HORIZON_MAX 64

typedef enum hp_prediction {
    HP_PREDICT_HOLD = 0, /* the future desired poses equal the latest one */
    HP_PREDICT_VELOCITY, /* extrapolated at the mean velocity of the recent rows */
    HP_PREDICT_PERIODIC  /* per component, a sinusoid on a linear trend fitted to the last two
                            periods of the recent rows (the period from the component's own
                            crossings of its trend line); velocity where no period shows */
} hp_prediction;
/* "hold", "velocity", "periodic"; "unknown" */
HP_API const char *hp_prediction_name(hp_prediction p);
HP_API hp_error hp_prediction_parse(const char *s, hp_prediction *out);

#define HP_DEFAULT_RATE_PER_S INFINITY /* [Pa/s]: no per-second limit */
#define HP_DEFAULT_SMOOTH 1e-6         /* [mm² per kPa²] */
#define HP_DEFAULT_START_INTERVAL 0.1  /* [s] */
#define HP_DEFAULT_HORIZON 10
#define HP_DEFAULT_VELOCITY_ROWS 3
#define HP_DEFAULT_RH_MAX_ITER 20
#define HP_DEFAULT_OFFLINE_TOL 1e-8
#define HP_DEFAULT_OFFLINE_MAX_ITER 3000
#define HP_DEFAULT_OFFLINE_MAX_TIME 600.0 /* [s] CPU time of one window */
/* window = 0 solves a trace of at most HP_HORIZON_WHOLE_MAX rows at once, a longer one in
 * windows of HP_HORIZON_AUTO_WINDOW rows overlapping by HP_HORIZON_AUTO_OVERLAP, so that the
 * NLP (about 27 kB of Ipopt's memory per row) stays the same size however long the trace:
 * 600/100 costs 1.3e-9 of the whole optimum on drift_long.csv (docs/horizon.md). A window of
 * at least T rows solves the whole trace at once. */
#define HP_HORIZON_WHOLE_MAX 1200
#define HP_HORIZON_AUTO_WINDOW 600
#define HP_HORIZON_AUTO_OVERLAP 100

typedef struct hp_horizon_settings {
    double rate_max_per_s;   /* [Pa/s] every bladder's pressure rate limit, > 0 (+inf: none) */
    double smooth;           /* [mm²/kPa²] weight of the pressure-change term, in [0, 1] */
    double start_interval_s; /* [s] the start pressures are held this long before row 0, > 0 */
    int horizon;             /* receding horizon N (rows), 1..HP_HORIZON_MAX */
    hp_prediction prediction;
    int velocity_rows;       /* rows the velocity is estimated from, 2..HP_HORIZON_MAX */
    int rh_max_iter;         /* interior-point iterations per receding-horizon call, 1..100 */
    int window;              /* offline: rows per window (0: HP_HORIZON_WHOLE_MAX above) */
    int overlap;             /* offline: rows shared by consecutive windows, < window */
    double offline_tol;      /* Ipopt tolerance of the offline NLP, in (0, 1e-2] */
    int offline_max_iter;    /* Ipopt iterations per window, > 0 */
    double offline_max_time; /* [s] Ipopt CPU time per window, > 0 */
} hp_horizon_settings;

/* Fills every field with its HP_DEFAULT_* value. s may be NULL (nothing happens). */
HP_API void hp_horizon_settings_default(hp_horizon_settings *s);
/* Checks every field (finite where it must be, in range); the first bad one is named in
 * diag. HP_OK, HP_ERR_NULL or HP_ERR_INVALID. */
HP_API hp_error hp_horizon_settings_validate(const hp_horizon_settings *s, hp_diag *diag);

/* One planned row. */
typedef struct hp_horizon_row {
    double t;                         /* [s] the row's time stamp */
    double desired[6];                /* SI, copied from the trace row */
    double achieved[6];               /* SI, the planned pose */
    double ri[HP_MAX_BLADDERS];       /* [m] inner radii */
    double pressure[HP_MAX_BLADDERS]; /* [Pa], IK of ri, inside every limit */
    hp_status status;                 /* REACHED / CLOSEST, or the per-row failure */
} hp_horizon_row;

/* The rate limits Δ_t,k [Pa] of every row (T×n, row-major) for a trace: see above. Checks
 * the time stamps (finite, strictly increasing: else HP_ERR_INVALID naming the trace line).
 * Allocates nothing. */
HP_API hp_error hp_horizon_rates(const hp_layout *L, const hp_horizon_settings *hs,
                                 const hp_trace_row *rows, size_t T, double *delta, hp_diag *diag);

/* How long the start pressures are taken to have been held before row 0 when a whole trace
 * is planned: the trace's first interval (rows[1].t − rows[0].t, when T >= 2 and it is finite
 * and > 0), else fallback. headplan horizon and Python's run_trace set start_interval_s from
 * it, so both plan row 0 under the same allowance. Allocates nothing. */
HP_API double hp_horizon_start_interval(const hp_trace_row *rows, size_t T, double fallback);

/* The request check hp_plan applies to a desired correction (finite, within its caps and
 * inside the layout's identifiable range: hp_planner.h), over every row: HP_OK, or
 * HP_ERR_INVALID with hp_plan's one-line reason in diag (without the line) and the first
 * refused row's index in *bad (may be NULL). Greedy, receding and offline plans refuse such a
 * trace before planning (diag "line N: reason"): a plan over a horizon has no row to leave
 * out. Allocates nothing. */
HP_API hp_error hp_horizon_check_rows(const hp_layout *L, const hp_trace_row *rows, size_t T,
                                      size_t *bad, hp_diag *diag);

/* The pressures of the nominal pose (every bladder at its reference contact), the default
 * start of every plan. */
HP_API hp_error hp_horizon_nominal_pressures(const hp_layout *L, double *p_start, hp_diag *diag);

/* Greedy plan of T rows: hp_plan with `settings` (NULL: defaults) row by row, each row's rate
 * limits Δ_t set before its plan, from p_start (NULL: the nominal pressures; at the load
 * level NULL starts from the planner's state after create, no previous pressures, so the
 * first row is planned as headplan solve and batch plan it). out has T rows.
 * A row hp_plan refuses is refused first (hp_horizon_check_rows); a row it cannot answer
 * keeps its safe output (status says so). On HP_OK, diag holds "line N: reason" for the first
 * row whose answer hp_plan refused (status INVALID_INPUT; the reason is the planner's, as
 * headplan batch prints it), else "". Allocates. */
HP_API hp_error hp_horizon_greedy(const hp_layout *L, const hp_settings *settings,
                                  const hp_horizon_settings *hs, const hp_trace_row *rows, size_t T,
                                  const double *p_start, hp_horizon_row *out, hp_diag *diag);

/* What an offline solve did. */
typedef struct hp_horizon_info {
    int windows;        /* Ipopt solves */
    int iterations;     /* summed over windows */
    int raw_code;       /* Ipopt's status of the last window that did not succeed, else 0 */
    int largest_window; /* rows of the largest NLP solved (its size, whatever T) */
    double cost;        /* the objective of the returned plan (pose + smoothness) */
} hp_horizon_info;

/* The window and overlap (rows) an offline plan of T rows uses with settings hs: hs's own,
 * or for window = 0 the defaults above. */
HP_API void hp_horizon_offline_windows(const hp_horizon_settings *hs, size_t T, int *window,
                                       int *overlap);

/* Offline plan of T rows: the sparse NLP above on Ipopt (exact first and second derivatives,
 * block-banded sparsity), started from the greedy plan, with hs->window rows per solve and
 * hs->overlap rows shared (hp_horizon_offline_windows). Every returned row is inside every limit (checked
 * after the solve; a window whose answer fails the check is an HP_ERR_SOLVER). Serialised
 * with every other Ipopt call of the process. info may be NULL. Allocates. */
HP_API hp_error hp_horizon_offline(const hp_layout *L, const hp_settings *settings,
                                   const hp_horizon_settings *hs, const hp_trace_row *rows,
                                   size_t T, const double *p_start, hp_horizon_row *out,
                                   hp_horizon_info *info, hp_diag *diag);

/* The receding-horizon planner: create once (allocates), then one hp_horizon_rh_step per
 * row. */
typedef struct hp_horizon_rh hp_horizon_rh;

/* Builds it for a layout, planner settings (NULL: defaults; the backend is forced to
 * realtime) and horizon settings (NULL: defaults). p_start: pressures held before the first
 * row (NULL: nominal). */
HP_API hp_error hp_horizon_rh_create(const hp_layout *L, const hp_settings *settings,
                                     const hp_horizon_settings *hs, const double *p_start,
                                     hp_horizon_rh **out, hp_diag *diag);

/* Plans the row at time t (s, later than the previous call's) with desired correction
 * desired[6] (SI): predicts the next N−1 desired poses, solves the N-row problem started from
 * the previous call's plan shifted by one row (at most rh_max_iter interior-point iterations)
 * and applies its first row through hp_plan (realtime) with this row's rate limits. result
 * is hp_plan's, its desired[], pose_error and status those of this row's own desired
 * correction (docs/horizon.md, Row statuses); HP_STATUS_TIME_LIMIT when the time budget
 * stopped the horizon solve early (the answer then depends on the machine's speed).
 * Allocates nothing, prints nothing, takes no lock; bounded: the horizon solve aims to end
 * within four fifths of the settings' max_time from the call's start (no iteration after the
 * first begins that the call's longest so far would carry past it; one iteration past it at
 * most, but for a stall of the host or an iteration longer than those before it), then
 * hp_plan runs under its own max_time.
 * HP_ERR_NULL / HP_ERR_INVALID (t not finite or not increasing: result holds nothing new). */
HP_API hp_error hp_horizon_rh_step(hp_horizon_rh *rh, double t, const double desired[6],
                                   hp_result *result);

/* Frees it; safe on NULL. */
HP_API void hp_horizon_rh_destroy(hp_horizon_rh *rh);

/* Receding-horizon plan of a whole trace (create, one step per row, destroy). diag on
 * HP_OK: as hp_horizon_greedy's. */
HP_API hp_error hp_horizon_receding(const hp_layout *L, const hp_settings *settings,
                                    const hp_horizon_settings *hs, const hp_trace_row *rows,
                                    size_t T, const double *p_start, hp_horizon_row *out,
                                    hp_diag *diag);

/* What a study compares. */
typedef struct hp_horizon_metrics {
    double rms[6];       /* RMS of achieved − desired per axis (mm, mm, mm, deg, deg, deg) */
    double max[6];       /* largest |achieved − desired| per axis */
    double time_outside; /* [s] summed row intervals with a translation error > tol_mm or a
                              rotation error > tol_deg (row t counts t_t − t_t−1; row 0 the
                              start interval) */
    double rows_outside; /* fraction of rows outside the tolerance */
    double travel;       /* [Pa] Σ_t,k |P_t,k − P_t−1,k| (from the start pressures) */
    double cost;         /* Σ_t ‖ξ_t − d_t‖²_W + smooth · Σ (ΔP / 1 kPa)² */
    double pose_cost;    /* the first sum alone */
} hp_horizon_metrics;

/* Metrics of a plan of n bladders (tolerances in mm and degrees, > 0). */
HP_API hp_error hp_horizon_measure(const hp_horizon_row *out, size_t T, int n,
                                   const double *p_start, const hp_settings *settings,
                                   const hp_horizon_settings *hs, double tol_mm, double tol_deg,
                                   hp_horizon_metrics *m);

#ifdef __cplusplus
}
#endif
#endif
