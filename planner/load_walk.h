/* Internal: the load level's stable walk (load_walk.c, docs/load.md "Stable holds"): when a
 * plan's hold is only an unstable equilibrium, pressures on the segment from the previous
 * answer toward a stable hold whose forward-statics rest, started at the previous answer's
 * pose, is stable: a pose its pressures really hold, by construction. No allocation. */
#ifndef HP_PLANNER_LOAD_WALK_H
#define HP_PLANNER_LOAD_WALK_H

#include "kinematics/load_internal.h"

/* The walk's candidates: t = 1, 7/8, ..., 1/8, 0 of the way from the previous answer's
 * pressures toward the goal's (HP_LOAD_WALK_STEPS + 1 of them). */
#define HP_LOAD_WALK_STEPS 8

/* The closest-pose program's distance of xi from desired: sum W[i]·(difference in mm or
 * degrees)², W per mm² and per degree². */
double hpi_load_pose_err(const double xi[6], const double desired[6], const double W[6]);

/* The caller's checks of a candidate answer: 1 when pressures P holding the head at xi may
 * be returned (an equilibrium, stable, inside the contact law's range, a limit named), else
 * 0. */
typedef int (*hpi_load_walk_check)(const void *ctx, const double xi[6], const double *P);

/* The best candidate so far: its pose, pressures and weighted squared distance from the
 * desired pose (INFINITY: none yet). */
typedef struct hpi_load_pick {
    double xi[6];
    double P[HP_MAX_BLADDERS];
    double err;
} hpi_load_pick;

/* What every candidate is measured against: the desired pose, the weights of the distance
 * (W, per mm² and per degree², the closest-pose program's), the caller's checks. */
typedef struct hpi_load_walk_goal {
    const double *desired;
    const double *W;
    hpi_load_walk_check check;
    const void *ctx;
} hpi_load_walk_goal;

/* The stable walk: for each candidate P(t) = clip(prev_P + t·(goal_P − prev_P), lo, hi)
 * (per bladder, so every pressure lies in [lo, hi] to the last bit), the forward statics'
 * rest of P(t) started at prev_xi (where the head, at the previous answer's pose, goes when
 * the bladders take P(t)); a rest the checks accept replaces *best when nearer the desired
 * pose (the larger t on a tie). Returns 1 when one did. Deterministic, bounded
 * (HP_LOAD_WALK_STEPS + 1 forward-statics solves and checks). */
int hpi_load_walk(const hp_load_model *M, const double *prev_P, const double prev_xi[6],
                  const double *goal_P, const double *lo, const double *hi,
                  const hpi_load_walk_goal *g, hpi_load_pick *best);

#endif
