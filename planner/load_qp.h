/* Internal: the small separable QP of the load planner,
 *     minimise ½·sum_i h_i·(d_i − g_i)²   subject to   c + M·d = 0 (6 rows),  l <= d <= u,
 * with h_i > 0 and l <= 0 <= u, by the method of multipliers over a finite active-set
 * box QP (an nv×nv Cholesky per active-set change). No allocation. */
#ifndef HP_PLANNER_LOAD_QP_H
#define HP_PLANNER_LOAD_QP_H

#include "headplan/hp_common.h"

/* Up to one variable per bladder and six for the pose (the closest-pose program). */
#define HP_LOAD_QP_NMAX (HP_MAX_BLADDERS + 6)

typedef enum hp_load_qp_status {
    HP_LOAD_QP_OPTIMAL = 0,
    HP_LOAD_QP_INFEASIBLE, /* no d in the box satisfies the equations (dual unbounded) */
    HP_LOAD_QP_ITERATION_LIMIT
} hp_load_qp_status;

/* Solves the QP above with nv <= HP_LOAD_QP_NMAX variables; M is 6×nv row-major; lambda
 * (6) is the warm start in and the multipliers out (of λᵀ(c + M·d)); d receives the
 * solution. tol is the accepted |c + M·d|∞; max_iter bounds the multiplier updates. */
hp_load_qp_status hpi_load_qp_solve(int nv, const double *M, const double c[6], const double *h,
                                    const double *g, const double *l, const double *u, double tol,
                                    int max_iter, double lambda[6], double *d, int *iterations);

#endif

/* Box-constrained strictly convex QP: minimise ½dᵀHd + gᵀd subject to l <= d <= u
 * (l <= 0 <= u: d = 0 is feasible), nv <= HP_MAX_BLADDERS, H row-major positive
 * definite, by a primal active-set method from d = 0 (finite; at most max_iter changes of
 * the active set). Returns 0 on success, -1 when H is not positive definite or the
 * budget runs out (d then holds the last feasible point). No allocation. */
int hpi_load_box_qp(int nv, const double *H, const double *g, const double *l, const double *u,
                    int max_iter, double *d);
