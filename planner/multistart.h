/* Internal: the restarts of the offline backends (multistart.c). A local method's answer
 * depends on its start; a backend that cannot tell a local minimum from the closest pose
 * solves again from deterministic points and keeps the best answer. One loop for every
 * backend that restarts (NLopt SLSQP, Ipopt): each gives it its one solve. */
#ifndef HP_PLANNER_MULTISTART_H
#define HP_PLANNER_MULTISTART_H

#include "planner/problem.h"

/* Restart point j (1, 2, ...) for program pb whose first solve started at xs (nx values):
 * the pose a fraction f_j (the base-2 van der Corput sequence: 1/2, 1/4, 3/4, 1/8, ...) of
 * the way from the start's pose to the desired pose (components not commanded stay at the
 * start's), the radii the start's. Written to x. */
void hpi_multistart_point(const hp_problem *pb, const double *xs, int j, double *x);

/* A backend's one solve of pb from x0 (inside the radius bounds) into x (nx values, inside
 * them) with its result in r, cold (no warm start from an earlier solve); left is what is
 * left of the plan's time budget [s] (> 0). Returns 0 when the solve could not be set up
 * (the restarts stop there), else 1. */
typedef int (*hpi_multistart_solve)(void *ctx, const hp_problem *pb, const double *x0, double left,
                                    double *x, hp_backend_result *r);

/* The restarts after a backend's first solve from xs: when that answer v converged and binds
 * a limit (a radius within HP_BINDING_TOL_MM of a bound; with none bound the objective's one
 * minimum is the target), solves from restart points 1..restarts while the budget lasts
 * (max_time s from t0 on hpi_plan_now) and keeps in v and r (status, raw code) the answer of
 * least objective among those that converge and pass the core's first-order check
 * (hpi_backend_first_order_ok with tolerance tol), so a restart never turns an answer into
 * a refused one. r->iterations adds up every solve's. Returns the restart whose answer v
 * holds (0: the first solve's) and sets *ran to the number of restart solves run. */
int hpi_multistart_run(const hp_problem *pb, const double *xs, int restarts, double t0,
                       double max_time, double tol, hpi_multistart_solve solve, void *ctx,
                       double *v, hp_backend_result *r, int *ran);

#endif
