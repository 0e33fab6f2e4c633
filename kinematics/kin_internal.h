/* Internal helpers of the kinematics module: rotation derivatives, the point-to-head
 * distance with its derivatives, and small vector helpers. Not installed. */
#ifndef HP_KIN_INTERNAL_H
#define HP_KIN_INTERNAL_H

#include "headplan/hp_contact.h"
#include <math.h>

/* R = Rz(yaw)·Ry(roll)·Rx(pitch) for th = (pitch, roll, yaw), with its first derivatives
 * dR[j] = ∂R/∂th_j and second derivatives d2R[j][k] = ∂²R/∂th_j∂th_k (all row-major 3×3).
 * dR and d2R may be NULL. */
void hpi_kin_rotation_derivs(const double th[3], double R[9], double dR[3][9], double d2R[3][3][9]);

/* R with its first and second derivatives in roll alone, Dr = dR[1] and Drr = d2R[1][1] of
 * hpi_kin_rotation_derivs (the same bits; Dr and Drr may be NULL): every other derivative
 * is a signed copy of entries of these (pitch: R·[e_x]×, yaw: [e_z]×·R), which a caller
 * that contracts them can form where it needs them. */
void hpi_kin_rotation_roll(const double th[3], double R[9], double Dr[9], double Drr[9]);

/* Signed distance d from point q to the head surface at the nominal pose (> 0 outside),
 * its gradient (the outward unit normal at the closest surface point), its Hessian (3×3,
 * row-major) and the closest surface point foot. grad, hess and foot may be NULL.
 * HP_ERR_DOMAIN when q lies so deep inside the head that the closest point is not unique
 * or the distance is not smooth there (within 1e-3 of the centre-curvature set).
 * Allocates nothing. */
hp_error hpi_kin_head_distance(const hp_head *h, const double q[3], double *d, double grad[3],
                               double hess[9], double foot[3]);

/* What a warm start of the ellipsoid's root find keeps from one evaluation to the next of
 * the same bladder: the scaled Lagrange multiplier s at the point y (relative to the head
 * centre) and its gradient ds/dy there, so the next point y' starts from the first-order
 * prediction s + ds·(y' − y). s NAN: nothing kept (a cold start). evals: the Q evaluations
 * the last solve took (read by tests only). */
typedef struct hp_kin_dist_warm {
    double s, y[3], ds[3];
    int evals;
} hp_kin_dist_warm;

/* Marks w[0..n-1] cold. */
static inline void hpi_kin_dist_warm_cold(hp_kin_dist_warm *w, int n)
{
    for (int k = 0; k < n; ++k) {
        w[k].s = NAN;
        w[k].evals = 0;
    }
}

/* hpi_kin_head_distance with a warm start for the ellipsoid's multiplier: w (may be NULL)
 * supplies the start when its prediction lies inside the safeguarding bracket (else the
 * bracket's own start) and receives this point's state, for the next evaluation of a
 * nearby point. The answer is the same to rounding whatever w holds; a sphere leaves w
 * alone. */
hp_error hpi_kin_head_distance_warm(const hp_head *h, const double q[3], hp_kin_dist_warm *w,
                                    double *d, double grad[3], double hess[9], double foot[3]);

/* What the ellipsoid distance needs of a head beyond its inputs, derived once per head
 * (hpi_kin_head_consts) instead of on every call: the smallest semi-axis e, e², the ratios
 * r_i = (a_i/e)² >= 1 (each computed exactly as the distance used to compute
 * it per call, so the answers are the same bits). Unused for a sphere. */
typedef struct hp_kin_head_k {
    double e, e2;
    double r[3];
} hp_kin_head_k;

/* Fills k for head h (valid: hpi_kin_head_validate). */
void hpi_kin_head_consts(const hp_head *h, hp_kin_head_k *k);

/* hpi_kin_head_distance_warm for a head h whose constants k were derived from it by
 * hpi_kin_head_consts (and h not changed since). */
hp_error hpi_kin_head_distance_k(const hp_head *h, const hp_kin_head_k *k, const double q[3],
                                 hp_kin_dist_warm *w, double *d, double grad[3], double hess[9],
                                 double foot[3]);

/* hpi_kin_head_distance_k at the n points q (n <= HP_MAX_BLADDERS), each with its own warm
 * state w[j] (w may be NULL), distance d[j], gradient grad[j] and, when hess is not NULL
 * and want_h[j] (want_h NULL: every point), Hessian hess[j]: the same bits as n calls, faster for an ellipsoid (the
 * root finds run side by side). HP_OK, or the error of the first point (index order) that
 * fails, with its index in *bad; the points after it may have been evaluated (their
 * outputs and warm states written), its own outputs are not meaningful. */
hp_error hpi_kin_head_distances(const hp_head *h, const hp_kin_head_k *k, int n,
                                const double (*q)[3], hp_kin_dist_warm *w, double *d,
                                double (*grad)[3], double (*hess)[9], const unsigned char *want_h,
                                int *bad);

/* Smallest radius of curvature of the head surface [m] (a_min²/a_max for an ellipsoid). */
double hpi_kin_head_min_curvature_radius(const hp_head *h);

/* Checks the head: shape, finite centre, positive finite semi-axes, mass >= 0. */
hp_error hpi_kin_head_validate(const hp_head *h, hp_diag *diag);

/* 1 when all three components are finite. */
int hpi_kin_finite3(const double v[3]);

/* What the kinematic reach predicate of hp_layout_analyze needs. */
typedef struct hp_kin_reach_ctx {
    const hp_layout *L;
    hp_level level;
} hp_kin_reach_ctx;

/* Largest s in [0, cap] (HP_REACH_CAP_MM for axis < 3, else HP_REACH_CAP_DEG) such that
 * ok(ctx, xi) holds at every pose sign·s'·e_axis, s' <= s (xi SI): a scan in 1/scan of the
 * cap, so that a feasible set that is not an interval still yields its first boundary (any
 * gap narrower than a scan step can be missed), then bisection to ~1e-15 of the cap. 0 when
 * ok fails at the nominal pose; the cap when it never fails. Shared by hp_layout_analyze
 * (scan 100: the limits give intervals) and the planner's reach (hp_planner_reach, finer:
 * its round trip can fail in short gaps), so the two differ only in their predicate and
 * resolution. */
double hpi_kin_reach_axis(int (*ok)(void *ctx, const double xi[6]), void *ctx, int axis,
                          double sign, int scan);

#endif
