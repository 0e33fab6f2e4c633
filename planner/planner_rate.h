/* Internal: the per-plan rate limits a caller above the planner (the horizon planners) sets
 * between plans. Not installed. */
#ifndef HP_PLANNER_RATE_H
#define HP_PLANNER_RATE_H

#include "headplan/hp_planner.h"

/* Sets the per-plan rate limit [Pa] of every bladder for the next hp_plan calls (planner.c;
 * each > 0, +inf for none). HP_ERR_NULL / HP_ERR_INVALID (nothing changes). When none is
 * left finite the cycle bounds return to the static ones at once (hp_plan then leaves them).
 * HP_ERR_STATE if they could not (not for a planner hp_planner_create accepted). */
hp_error hp_planner_set_rate_max(hp_planner *p, const double *rate_max);

#endif
