/* Internal: forward contact kinematics with what a caller already knows about the start
 * point. The planner checks every reached answer by a fit from the nominal pose, whose
 * distances and Jacobian are layout constants: computing them once at create removes one
 * of the fit's few contact evaluations. Not installed. */
#ifndef HP_FIT_INTERNAL_H
#define HP_FIT_INTERNAL_H

#include "headplan/hp_kinematics.h"
#include "kin_geom.h"

/* The contact model at a fit's start point x0, as hp_kin_contact_eval_warm computes it
 * there from a cold start (so a fit given it takes the very same steps as one without). */
typedef struct hp_kin_fit_start {
    double rho[HP_MAX_BLADDERS];     /* contact distances at x0 [m] */
    double J[HP_MAX_BLADDERS * 6];   /* their Jacobian (n×6, row-major) */
    double s[HP_MAX_BLADDERS];       /* the surface level's multipliers at x0 (NAN: none) */
} hp_kin_fit_start;

/* Fills st at pose x0 (finite) for level. HP_OK or hp_contact_eval's error. */
hp_error hp_kin_fit_start_at(const hp_layout *L, const hp_geom *G, hp_level level,
                             const double x0[6], hp_kin_fit_start *st);

/* A pose the caller expects the fit to arrive at, with a tolerance per component (SI). */
typedef struct hp_kin_fit_near {
    double pose[6];
    double tol[6];
} hp_kin_fit_near;

/* hp_contact_fit, started from st (computed at x0 for the same layout and level) when st
 * is not NULL. With near, the iteration may stop early at an iterate x (an accepted step,
 * never x0) within tol/4 of near->pose whose undamped Gauss–Newton step is below tol/4
 * in every free component: the Jacobian there has full column rank and the iteration
 * converges quadratically from x to a fit about one such step away, so the fit it would
 * end in lies within tol/2 (plus that step squared) of near->pose; xi is then x and
 * residual_rms the RMS at x. Allocates nothing. */
hp_error hp_kin_fit(const hp_layout *L, const hp_geom *G, hp_level level, const double *target,
                    const int free_[6], const double x0[6], const hp_kin_fit_start *st,
                    const hp_kin_fit_near *near, double xi[6], double *residual_rms,
                    int *iters);

#endif
