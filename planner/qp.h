/* Internal: a small dense strictly convex QP,
 *     minimise ½ xᵀ G x + aᵀ x   subject to   C x >= b   (m rows),
 * by the Goldfarb–Idnani dual active-set method (Math. Programming 27, 1983). It starts from
 * the unconstrained minimum and adds violated constraints one at a time, keeping the dual
 * feasible; linearly dependent (degenerate) constraints are handled by its "drop" steps, and
 * an empty feasible set is detected, not looped on. Fixed-size workspace: no allocation. */
#ifndef HP_PLANNER_QP_H
#define HP_PLANNER_QP_H

#include "headplan/hp_common.h"

#define HP_QP_NMAX 6
#define HP_QP_MMAX (2 * HP_MAX_BLADDERS)

typedef enum hp_qp_status {
    HP_QP_OPTIMAL = 0,
    HP_QP_INFEASIBLE,     /* no x satisfies C x >= b */
    HP_QP_ITERATION_LIMIT,
    HP_QP_BAD_INPUT       /* G not positive definite, NaN, sizes out of range */
} hp_qp_status;

typedef struct hp_qp {
    int n, m;
    double G[HP_QP_NMAX * HP_QP_NMAX]; /* n×n row-major (leading dimension n), symmetric
                                         * positive definite */
    double a[HP_QP_NMAX];
    double C[HP_QP_MMAX * HP_QP_NMAX]; /* row j at C + j·HP_QP_NMAX: constraint normal;
                                         * columns >= n are never read */
    double b[HP_QP_MMAX];
    /* outputs */
    double x[HP_QP_NMAX];   /* entries >= n are set to 0 */
    double u[HP_QP_MMAX];   /* multiplier of every constraint (0 when inactive) */
    int active[HP_QP_MMAX]; /* 1 when constraint j is in the final active set */
    int iterations;         /* add + drop steps */
    /* workspace: Jᵀ and C zero-padded to HP_QP_NMAX columns, R, the active set */
    double J_[HP_QP_NMAX * HP_QP_NMAX], R_[HP_QP_NMAX * HP_QP_NMAX];
    double C_[HP_QP_MMAX * HP_QP_NMAX];
    int A_[HP_QP_NMAX];
    double uA_[HP_QP_NMAX + 1];
} hp_qp;

/* Solves the QP held in q (n, m, G, a, C, b filled) with at most max_iter add/drop steps;
 * feas_tol is the violation (in units of b, per unit-norm row) accepted as satisfied.
 * Returns HP_QP_BAD_INPUT for a NaN or infinity anywhere in G, a, C or b (first n columns),
 * for a row of C whose squared norm overflows, and for G not positive definite; then the
 * outputs are not meaningful. Allocation-free; a row that is the exact negation of the row
 * before it (a lower and an upper limit on one quantity) costs about half a row. */
hp_qp_status hp_qp_solve(hp_qp *q, int max_iter, double feas_tol);

/* hp_qp_solve with Lg the lower Cholesky factor of exactly this q->G from hp_cholesky
 * (leading dimension n; entries above the diagonal not read), when the caller has factored
 * G already (the realtime backend does, to test its convexity): G is not factored again.
 * Lg NULL: hp_qp_solve. The factor is the same bits either way. */
hp_qp_status hp_qp_solve_factored(hp_qp *q, const double *Lg, int max_iter, double feas_tol);

#endif
