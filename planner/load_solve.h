/* Internal: the load planner's HOLD and POSE solves (see load_solve.c). No allocation. */
#ifndef HP_PLANNER_LOAD_SOLVE_H
#define HP_PLANNER_LOAD_SOLVE_H

#include "headplan/hp_load.h"

typedef enum hp_load_solve_status {
    HP_LOAD_SOLVE_OK = 0,
    HP_LOAD_SOLVE_UNREACHABLE,     /* no pressures inside the bounds hold this pose */
    HP_LOAD_SOLVE_ITERATION_LIMIT,
    HP_LOAD_SOLVE_ERROR            /* the model failed (geometry or bladder domain) */
} hp_load_solve_status;

/* HOLD: pressures P[n] inside [lo, hi] holding the head at xi, nearest (sum of squares) to
 * target[n] among all that do; F[n] their contact forces. start (may be NULL) seeds the
 * forces. */
hp_load_solve_status hp_load_hold(const hp_load_model *M, const double xi[6],
                                  const double *lo, const double *hi, const double *target,
                                  const double *start, int max_iter, double *P, double *F,
                                  int *iterations);

/* POSE: the pose nearest to desired (weights W per mm² and degree²) at which pressures in
 * [lo, hi] hold the head, from (xi0, P0); P gets those pressures (not tie-broken). */
hp_load_solve_status hp_load_pose(const hp_load_model *M, const double desired[6],
                                  const double W[6], const double *lo, const double *hi,
                                  const double xi0[6], const double *P0, int max_iter,
                                  double xi[6], double *P, int *iterations);

#endif
