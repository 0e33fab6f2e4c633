/* Internal: the contact geometry a layout implies at the nominal pose, and the kinematics
 * calls that take it ready-made. Not installed.
 *
 * The public hp_layout holds inputs only. Whatever is derived from it (each bladder's
 * nominal contact point, normal and distance) lives here, owned by whoever holds a private
 * copy of the layout (the planner, horizon planners, calibration) and derived once when
 * that copy is made, so a hot loop does not pay the derivation per call. The public
 * kinematics calls that take a layout derive an hp_geom on their own stack on every call
 * and then call the _g variant below: a layout edited by its caller can never be answered
 * with geometry from before the edit. */
#ifndef HP_KIN_GEOM_H
#define HP_KIN_GEOM_H

#include "headplan/hp_contact.h"
#include "kin_internal.h"

typedef struct hp_geom {
    hp_head head;                       /* the layout's head; a sphere's three semi-axes
                                            all equal to its radius semi_axes[0] */
    double contact[HP_MAX_BLADDERS][3]; /* nominal contact point on the head surface [m] */
    double normal[HP_MAX_BLADDERS][3];  /* outward unit head normal there */
    double rho0[HP_MAX_BLADDERS];       /* nominal contact distance |c − p| [m] */
    hp_kin_head_k headk;                /* the head's constants for the distance */
    double arm[HP_MAX_BLADDERS][3];     /* centre − pivot [m]: the pose-free part of the
                                            back transform's u = c − pivot − t */
    double row[HP_MAX_BLADDERS][6];     /* the linear level's Jacobian row ∂ρ_k/∂ξ at the
                                            nominal pose (−n, −(contact − pivot) × n):
                                            ρ_lin,k = rho0[k] + row[k]·ξ (hpi_geom_linear) */
} hp_geom;

/* Derives G from L. Checks only what the geometry needs: a valid head, a finite pivot,
 * n in 1..HP_MAX_BLADDERS, every centre finite and outside the head. HP_ERR_NULL or
 * HP_ERR_INVALID (message in diag, may be NULL) otherwise. Allocates nothing. */
hp_error hpi_geom_derive(const hp_layout *L, hp_geom *G, hp_diag *diag);

/* The linear level's distance of bladder k at pose xi (SI): rho0[k] + row[k]·xi, summed
 * left to right from rho0[k]. The one formula of the linear level's evaluation and of the
 * direct chain's prediction (hpi_kin_contact_inside), so both give the same bits. */
static inline double hpi_geom_linear(const hp_geom *G, int k, const double xi[6])
{
    double v = G->rho0[k];
    for (int i = 0; i < 6; ++i) v += G->row[k][i] * xi[i];
    return v;
}

/* The public calls of the same name without the _g, for a geometry G derived from L
 * (hpi_geom_derive or hp_layout_prepare's checks, then hpi_geom_derive) and not changed
 * since. Same contracts otherwise. */
hp_error hpi_contact_eval_g(const hp_layout *L, const hp_geom *G, hp_level level,
                            const double xi[6], double *rho, double *J, double *H);
/* hpi_contact_eval_g with one warm state per bladder for the surface level's distances
 * (warm[0..n-1], see hpi_kin_head_distance_warm; NULL: cold). Same answers to rounding. */
hp_error hpi_kin_contact_eval_warm(const hp_layout *L, const hp_geom *G, hp_level level,
                                   const double xi[6], hp_kin_dist_warm *warm, double *rho,
                                   double *J, double *H);
/* hpi_kin_contact_eval_warm computing the Hessian only of the bladders k with hmask[k] != 0
 * (NULL: all), the same bits as a full evaluation's; the other bladders' 36 entries of H
 * are not written (they keep what the caller left there, except after an error, which
 * writes NaN everywhere). A solver needs the Hessian of a distance only where its
 * multiplier is not zero, and reads no other. */
hp_error hpi_kin_contact_eval_mask(const hp_layout *L, const hp_geom *G, hp_level level,
                                   const double xi[6], hp_kin_dist_warm *warm,
                                   const unsigned char *hmask, double *rho, double *J, double *H);
/* Whether every contact distance at xi lies inside its limits: distance_k · scale in
 * [lo[k], hi[k]] (the caller's units, e.g. scale 1000 for mm). The distances are evaluated
 * bladder by bladder, each the same bits as hpi_contact_eval_g's, and the evaluation stops
 * at the first one outside (a NaN is outside): a target beyond reach usually costs a
 * fraction of a full evaluation. At the surface level the first bladder evaluated is the
 * one the linear level (hpi_geom_linear · scale) predicts furthest outside its bounds, the
 * largest max(lo[k] − v, v − hi[k]) (lowest index on a tie), then the others in index
 * order; at the linear and plane levels, index order (there a distance costs about what
 * the prediction does). The verdict does not depend on the order.
 * Returns HP_OK with *inside 1 and rho[0..n-1] written (m); or HP_OK with *inside 0 and
 * rho[k] written only for the bladders evaluated, in that order, up to and including the
 * first one outside (the others untouched: a caller must not read rho when not inside);
 * or the evaluation's error (*inside 0; rho all NaN for a non-finite xi or a distance not
 * defined at xi). Where a distance is not defined at xi, whether its bladder is reached
 * before one outside depends on the order: HP_OK with *inside 0, or the error. J (may be
 * NULL): the Jacobian rows (n×6, per m and per rad) of the bladders evaluated, the same bits
 * as hpi_contact_eval_g's (the fit's certificate needs them at a reached answer). */
hp_error hpi_kin_contact_inside(const hp_layout *L, const hp_geom *G, hp_level level,
                                const double xi[6], double scale, const double *lo,
                                const double *hi, double *rho, double *J, int *inside);
/* A bound (m) on the second-order remainder |rho_k(xi + dxi) − rho_k(xi) − J_k(xi)·dxi| of
 * each bladder k along the straight step from SI pose xi by dxi, at the given level: 0 at
 * the linear level; at the surface level it needs rho[k] = rho_k(xi) (m; may be NULL at
 * the others) and is infinity where the step could come within reach of the head.
 * Derivation in bound.c. HP_ERR_NULL, or HP_ERR_INVALID for a bad level or a non-finite
 * pose. Allocates nothing. */
hp_error hpi_kin_contact_step_bound(const hp_layout *L, const hp_geom *G, hp_level level,
                                    const double xi[6], const double dxi[6], const double *rho,
                                    double *bound);
/* A bound on the curvature of each bladder's contact distance over a ball of poses: for
 * every pose p with |p − xc| <= r in the solvers' scaled metric (the six components in mm
 * and degrees, Euclidean) and every direction v of unit scaled length,
 * |vᵀ∇²rho_k(p)v| <= h[k], rho in mm and the pose in mm and degrees (so h[k] bounds the
 * Hessian's spectral norm there). xc is an SI pose; at the surface level rho[k] is
 * rho_k(xc) (m) and h[k] is infinity where the ball may reach the head; 0 at the linear
 * level. Derivation in bound.c. HP_ERR_NULL, or HP_ERR_INVALID for a bad level, a
 * non-finite pose or r not in [0, inf). Allocates nothing. */
hp_error hpi_kin_contact_ball_curvature(const hp_layout *L, const hp_geom *G, hp_level level,
                                        const double xc[6], double r, const double *rho, double *h);
hp_error hpi_contact_error_bound_g(const hp_layout *L, const hp_geom *G, hp_level level,
                                   double trans, double rot, double *bound);
hp_error hpi_contact_auto_g(const hp_layout *L, const hp_geom *G, double tol, double trans,
                            double rot, hp_level *level);
hp_error hpi_contact_fit_g(const hp_layout *L, const hp_geom *G, hp_level level,
                           const double *target, const int free_[6], const double x0[6],
                           double xi[6], double *residual, int *iters);
hp_error hpi_contact_fk_g(const hp_layout *L, const hp_geom *G, hp_level level, const double *ro,
                          const double *xi0, double xi[6], double *residual, int *iters);
hp_error hpi_layout_identify_g(const hp_layout *L, const hp_geom *G, hp_identifiable *out);
hp_error hpi_pose_commanded_part_g(const hp_layout *L, const hp_geom *G, const hp_identifiable *id,
                                   hp_level level, const double xd[6], double xc[6]);

#endif
