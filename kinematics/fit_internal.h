/* Internal: forward contact kinematics with what a caller already knows about the start
 * point. The planner checks every reached answer by a fit from the nominal pose, whose
 * distances and Jacobian are layout constants: computing them once at create removes one
 * of the fit's few contact evaluations. Not installed. */
#ifndef HP_FIT_INTERNAL_H
#define HP_FIT_INTERNAL_H

#include "headplan/hp_contact.h"
#include "kin_geom.h"

/* The contact model at a fit's start point x0, as hpi_kin_contact_eval_warm computes it
 * there from a cold start (so a fit given it takes the very same steps as one without). */
typedef struct hp_kin_fit_start {
    double rho[HP_MAX_BLADDERS];         /* contact distances at x0 [m] */
    double J[HP_MAX_BLADDERS * 6];       /* their Jacobian (n×6, row-major) */
    double A[6][6];                      /* JᵀJ of all six columns, each entry summed over the
                                        rows in order as the fit sums it: any free subset's
                                        normal matrix is a sub-block of it, bit for bit */
    hp_kin_dist_warm w[HP_MAX_BLADDERS]; /* the surface level's distances' warm states at x0 */
} hp_kin_fit_start;

/* Fills st at pose x0 (finite) for level. HP_OK or hp_contact_eval's error. */
hp_error hpi_kin_fit_start_at(const hp_layout *L, const hp_geom *G, hp_level level,
                              const double x0[6], hp_kin_fit_start *st);

/* The fit's damped least-squares step, min |J·dx + r|² + lambda·|diag(D)·dx|² (J n×nf
 * row-major, 1 <= nf <= 6, n <= HP_MAX_BLADDERS, lambda >= 0, D > 0 where lambda > 0).
 * lambda = 0 is the Gauss–Newton step, for a J of full column rank. Both return 0, or -1
 * when they cannot vouch for the result (then a more general solver decides). */

/* Householder QR of the stacked system [J; sqrt(lambda)·diag(D)], no pivoting. -1 for a
 * zero column or a result that is not finite. */
int hpi_kin_damped_qr(int n, int nf, const double *J, const double *r, const double *D,
                      double lambda, double *dx);

/* Largest condition number of the column-scaled normal matrix that hpi_kin_damped_normal
 * accepts. The normal equations' solution carries a relative error of about
 * nf·eps·(that condition number), at most 6·1.1e-16·1e6 ≈ 7e-10 of the scaled step here: a
 * Levenberg–Marquardt step that inexact still descends, each step is recomputed from an
 * exact residual, so the error never accumulates and the fit ends where QR steps end, to
 * rounding. Beyond it the error would grow as the square of the Jacobian's condition (a
 * pitch column with a small lever arm, a distant pivot): QR takes over. */
#define HP_KIN_NORMAL_MAX_COND 1e6

/* The same step from the normal equations (JᵀJ + lambda·diag(D)²)·dx = −Jᵀr, scaled
 * symmetrically to unit diagonal S and solved by Cholesky (hpi_cholesky): about 3 200
 * instructions for an 8×6 J against the QR's 4 800, and in the fit JᵀJ also yields the
 * column scales. -1 when S is not positive definite, when the rigorous bound
 * trace(S)·‖L⁻¹‖_F² >= λmax/λmin (hpi_cholesky_inv_frob2) exceeds HP_KIN_NORMAL_MAX_COND, or
 * when the result is not finite. Not bit-identical to the QR step (equal to ~1e-9 of it at
 * worst; 2e-14 measured on the default layout's, whose scaled condition is ~30). */
int hpi_kin_damped_normal(int n, int nf, const double *J, const double *r, const double *D,
                          double lambda, double *dx);

/* Iterations an early stop of hpi_kin_fit (its arrived test, its certificate) leaves in the
 * budget for the steps the full fit would still take at the rounding floor: there steps just
 * above the step tolerance alternate between acceptance and rejection, for up to 16
 * iterations measured (tests/kinematics/test_fit_attack.c) before the fit's own stop. Without
 * this margin a fit stopped early near the end of its budget could report an answer that the
 * full fit (the user's hp_contact_fk) reaches only after the budget, that is not at all. */
#define HP_KIN_FIT_STOP_MARGIN 32

/* A pose the caller expects the fit to arrive at, with a tolerance per component (SI), and
 * optionally an anchor: a pose (SI, in the fit's space: the components the fit does not
 * move equal its start's) whose contact distances at the fit's level are known (m), e.g.
 * the planner's answer and the distances it evaluated there. */
typedef struct hp_kin_fit_near {
    double pose[6];
    double tol[6];
    int has_anchor;
    double anchor[6];
    double anchor_rho[HP_MAX_BLADDERS];
    /* Optionally (NULL: none) the Jacobian at the anchor (n×6, per m and per rad, as
     * hpi_contact_eval_g gives it), read in place: then the certificate may hold before the
     * fit evaluates its first step (hpi_kin_fit_certified_trial). */
    const double *anchor_J;
    /* A bound on ‖J(anchor) − anchor_J‖₂ in the solvers' scaled units (mm per mm or
     * degree): 0 when anchor_J is the model's own Jacobian at the anchor, else e.g.
     * hpi_kin_jacobian_drift's for a Jacobian taken a short step away. */
    double anchor_J_err;
} hp_kin_fit_near;

/* A bound on ‖J(xb) − J̃‖₂ (scaled units, as hp_kin_fit_near's anchor_J_err) for J̃ (n×6,
 * SI) the model's Jacobian at xa (SI pose, distances rho_a [m] there) up to a few ulps
 * per entry, and xb the pose d scaled units (mm, degrees) from xa: each row moves by at
 * most its Hessian's bound times d on the ball of radius d around xa
 * (hpi_kin_contact_ball_curvature), and 4ε of J̃'s Frobenius norm covers the ulps. +inf
 * when a bound fails. */
double hpi_kin_jacobian_drift(const hp_layout *L, const hp_geom *G, hp_level level,
                              const double xa[6], const double *rho_a, const double *J, double d);

/* 1 when the rest of a fit (hpi_kin_fit) from its iterate x provably ends within near->tol/4
 * of near->pose, within iters_left more iterations: x (SI pose), the normal matrix A6 =
 * JᵀJ of its Jacobian's nf free columns col[] (6×6, leading dimension 6), its residual r =
 * rho(x) − target (m), the current damping lambda; it needs near's anchor. The proof
 * (fit_certify.c, docs/kinematics.md section 5): the distances' curvature is bounded on a
 * ball around x that the fit cannot leave and on which the distances determine the pose;
 * there the fit converges at a proven rate to within the noise of the anchor. 0 whenever a
 * condition fails (then the fit simply goes on). Allocates nothing. */
int hpi_kin_fit_certified(const hp_layout *L, const hp_geom *G, hp_level level, int nf,
                          const int *col, const double x[6], const double *A6, const double *r,
                          double lambda, const double *target, int iters_left,
                          const hp_kin_fit_near *near);

/* The same proof before the fit evaluates a trial point xt (a step from its current
 * iterate, whose computed squared residual is cost): on a ball around the anchor, with the anchor's
 * Jacobian (near->anchor_J) and its free columns' normal matrix A6 (6×6, leading dimension
 * 6). It proves that the trial is accepted (its residual, bounded through the anchor, is
 * below the start's), after which the damping is lambda_next, and that the rest of the fit
 * then ends within near->tol/4 of near->pose, within iters_left more iterations. 0 whenever
 * a condition fails. cache (may be NULL; ready = 0 before the first try): what depends only
 * on the anchor, the target and A6 (σ̂, the column norms, r0, the noise), kept between the
 * tries of one fit, whose trials share them. Allocates nothing. */
/* The model a certificate reasons with, at its ball's centre (fit_certify.c). */
typedef struct hp_kin_cert_model {
    double rho_c[HP_MAX_BLADDERS]; /* distances at the centre less their noise [m] */
    double Ah[36];                 /* scaled normal matrix of the Jacobian there */
    double cmin, cmax;             /* the range of its column norms */
    double r0, snu;                /* |ρ(a) − ρ*| plus noise, and the noise ν√n [mm] */
} hp_kin_cert_model;
typedef struct hp_kin_trial_cache {
    int ready; /* 0 before the first try; the rest is hpi_kin_fit_certified_trial's */
    hp_kin_cert_model m;
    double sig; /* σ̂, or −1 while not yet derived */
} hp_kin_trial_cache;
int hpi_kin_fit_certified_trial(const hp_layout *L, const hp_geom *G, hp_level level, int nf,
                                const int *col, const double xt[6], const double *A6, double cost,
                                double lambda_next, const double *target, int iters_left,
                                const hp_kin_fit_near *near, hp_kin_trial_cache *cache);

/* The linear level's fit in the free components free_ (the others 0), prepared once per
 * layout: the column-scaled normal matrix of the linear model's rows and its Cholesky factor.
 * prepare returns 0, or -1 (ready = 0) when no component is free or the scaled matrix is
 * not provably well conditioned (HP_KIN_NORMAL_MAX_COND): then hpi_kin_fit decides. */
typedef struct hp_kin_linear_fit {
    int ready, nf, col[6], free_[6];
    double d[6];     /* the columns' scales: 1/sqrt of the normal matrix's diagonal */
    double chol[36]; /* the scaled matrix's lower factor, leading dimension 6 */
} hp_kin_linear_fit;
int hpi_kin_linear_fit_prepare(const hp_layout *L, const hp_geom *G, const int free_[6],
                               hp_kin_linear_fit *f);
/* The least-squares pose of the outer radii target (n, [m]) at the linear level: two
 * Gauss–Newton steps from 0 with the prepared factor (the model is linear: the first solves
 * it, the second corrects its rounding). The same minimiser as hpi_kin_fit at this level to
 * rounding. HP_ERR_INVALID for an unprepared f or a non-finite target. Allocates nothing. */
hp_error hpi_kin_linear_fit_solve(const hp_kin_linear_fit *f, const hp_layout *L, const hp_geom *G,
                                  const double *target, double xi[6], double *residual_rms);

/* hp_contact_fit, started from st (computed at x0 for the same layout and level) when st
 * is not NULL. With near, the iteration may stop early at an iterate x (an accepted step,
 * never x0) within tol/4 of near->pose whose undamped Gauss–Newton step is below tol/4
 * in every free component: the Jacobian there has full column rank and the iteration
 * converges quadratically from x to a fit about one such step away, so the fit it would
 * end in lies within tol/2 (plus that step squared) of near->pose; xi is then x and
 * residual_rms the RMS at x. With near's anchor it may also stop at any iterate after the
 * first where hpi_kin_fit_certified proves the rest of the fit ends within tol/4 of
 * near->pose (both early stops only with at least HP_KIN_FIT_STOP_MARGIN iterations of the
 * budget left), or, with the anchor's Jacobian too, at any trial point before evaluating
 * it (hpi_kin_fit_certified_trial); xi is then the anchor and residual_rms the RMS of its
 * distances' residual.
 * Allocates nothing. */
hp_error hpi_kin_fit(const hp_layout *L, const hp_geom *G, hp_level level, const double *target,
                     const int free_[6], const double x0[6], const hp_kin_fit_start *st,
                     const hp_kin_fit_near *near, double xi[6], double *residual_rms, int *iters);

#endif
