/* Internal: the deterministic restart points of the offline backends (multistart.c). A
 * local method's answer depends on its start; a backend that cannot tell a local minimum
 * from the closest pose solves again from these points and keeps the best answer. */
#ifndef HP_PLANNER_MULTISTART_H
#define HP_PLANNER_MULTISTART_H

#include "planner/problem.h"

/* Restart point j (1, 2, ...) for program pb whose first solve started at xs (nx values):
 * the pose a fraction f_j (the base-2 van der Corput sequence: 1/2, 1/4, 3/4, 1/8, ...) of
 * the way from the start's pose to the desired pose (components not commanded stay at the
 * start's), the radii the start's. Written to x. */
void hpi_multistart_point(const hp_problem *pb, const double *xs, int j, double *x);

#endif
