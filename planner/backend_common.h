/* Internal: helpers the general-purpose backends (Ipopt, NLopt) share. Not installed. */
#ifndef HP_PLANNER_BACKEND_COMMON_H
#define HP_PLANNER_BACKEND_COMMON_H

#include "planner/problem.h"

/* Checks pb's dimensions and bounds: HP_OK; HP_ERR_INVALID when n, nx, d, w, mu or a bound
 * is NaN/inf or out of range; HP_ERR_DOMAIN when some ri_lo_k > ri_hi_k (the limits cannot
 * all hold: the caller reports HP_STATUS_INFEASIBLE_START). */
hp_error hpi_backend_check_problem(const hp_problem *pb, hp_diag *d);

/* The direct-chain starting point: ξ = d, ri_k = inverse volume law of ρ_k(d), clipped to
 * [ri_lo_k, ri_hi_k] (ri_lo_k where ρ_k(d) would collapse the cavity). x has nx entries,
 * scaled units. Allocates nothing. */
hp_error hpi_backend_default_start(const hp_problem *pb, double *x);

/* Copies x0 (or the default start when x0 is NULL) into x, clipping ri into its bounds;
 * HP_ERR_INVALID when x0 holds a NaN or infinity. */
hp_error hpi_backend_start(const hp_problem *pb, const double *x0, double *x);

/* What every backend's solve does first: resets r, checks that the problem still has the
 * size the backend was created for (n, nx), checks the bounds, and builds the starting point
 * xs from x0. Returns HP_OK with *go = 1 to solve; HP_OK with *go = 0 when the bounds are
 * empty (r->status = INFEASIBLE_START, nothing to solve); an error (named after the backend
 * `name` in d) otherwise. */
hp_error hpi_backend_begin(const char *name, const hp_problem *pb, int n, int nx, const double *x0,
                           double *xs, hp_backend_result *r, int *go, hp_diag *d);

/* Moves every ri_k into [ri_lo_k, ri_hi_k] (solvers may leave them 1e-8 relative outside). */
void hpi_backend_clip(const hp_problem *pb, double *x);

/* First-order optimality measures of a point x (scaled units). */
typedef struct hp_kkt_measure {
    double feasibility;  /* max_k |c_k| [mm] */
    double stationarity; /* max over pose rows of |∇f + Jᵀλ| with least-squares λ */
    double wrong_sign;   /* largest wrong-signed bound multiplier (0 when all are right) */
    double grad_max;     /* |∇f|∞, the scale of the two above */
    int in_bounds;       /* 1 when every ri_k is inside [ri_lo_k, ri_hi_k] */
    /* Each radius's bound multiplier z_k = ∂L/∂ri_k (>= 0 right at a lower bound, <= 0 at
     * an upper one; 0 for a radius on neither bound). */
    double bound_mult[HP_MAX_BLADDERS];
} hp_kkt_measure;

/* Fills m for x (+inf stationarity when no multipliers can be computed). Allocates nothing. */
hp_error hpi_backend_kkt_measure(const hp_problem *pb, const double *x, hp_kkt_measure *m);

/* First-order optimality test of a point the solver could not certify (NLopt's
 * ROUNDOFF_LIMITED): 1 when every contact constraint holds to feas_tol [mm], every ri_k is
 * inside its bounds, and multipliers exist (least squares) making the Lagrangian's gradient
 * vanish to 1e-6·(1 + |∇f|∞) with bound multipliers of the right sign; else 0. */
int hpi_backend_kkt_ok(const hp_problem *pb, const double *x, double feas_tol);

/* The core's check of a claimed optimum that its backend does not certify (plan.c's
 * closest_verified; the NLopt restarts keep only answers it accepts): contacts to
 * max(10·tolerance, 1e-6) mm, radii in bounds, stationarity and multiplier signs to 1e-3 of
 * the gradient's scale. 1 when x passes. */
int hpi_backend_first_order_ok(const hp_problem *pb, const double *x, double tolerance);

#endif
