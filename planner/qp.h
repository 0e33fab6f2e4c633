/* Internal: a small dense strictly convex QP,
 *     minimise ½ xᵀ G x + aᵀ x   subject to   C x >= b   (m rows),
 * by the Goldfarb–Idnani dual active-set method (Math. Programming 27, 1983). It starts from
 * the unconstrained minimum (or a warm start's dual-feasible rows) and adds violated constraints one at a time, keeping the dual
 * feasible; linearly dependent (degenerate) constraints are handled by its "drop" steps, and
 * an empty feasible set is detected, not looped on. Fixed-size workspace: no allocation. */
#ifndef HP_PLANNER_QP_H
#define HP_PLANNER_QP_H

#include "headplan/hp_common.h"

#define HP_QP_NMAX 6
#define HP_QP_MMAX (2 * HP_MAX_BLADDERS)

typedef enum hp_qp_status {
    HP_QP_OPTIMAL = 0,
    HP_QP_INFEASIBLE, /* no x satisfies C x >= b */
    HP_QP_ITERATION_LIMIT,
    HP_QP_BAD_INPUT, /* G not positive definite, NaN, sizes out of range */
    HP_QP_LAZY       /* hpi_qp_solve_lazy: a stand-in row's exact b is needed (*hit) */
} hp_qp_status;

/* What the warm start of hpi_qp_solve_warm did with its guessed active set. */
typedef enum hp_qp_warm {
    HP_QP_WARM_NONE = 0, /* no guess given (hpi_qp_solve, hpi_qp_solve_factored) */
    HP_QP_WARM_ACCEPTED, /* the guessed rows' equality-constrained QP is the answer */
    /* refused: the Goldfarb–Idnani loop ran, from the unconstrained minimum for the first
     * two, from the guessed rows kept (none kept: from the unconstrained minimum) for the
     * last two (hpi_qp_solve_warm) */
    HP_QP_WARM_SHAPE,     /* more rows than n or the budget, a twin pair, a zero row */
    HP_QP_WARM_CONDITION, /* the rows dependent or their Gram matrix too ill-conditioned */
    HP_QP_WARM_SIGN,      /* a guessed row's multiplier negative */
    HP_QP_WARM_VIOLATED   /* another row violated beyond feas_tol */
} hp_qp_warm;

/* The largest accepted bound on the 2-norm condition number of the guessed rows' scaled
 * Gram matrix (qp.c, warm_try). The equality solve goes through that matrix (normal
 * equations), so the multipliers carry a relative error of about κ·k·ε (k rows, ε the
 * unit roundoff): at 1e8 about 1e-7 in the worst case, and x, in which the error enters
 * only through √κ, about 1e4·ε relative — the accuracy of the Goldfarb–Idnani solve,
 * whose QR factor has the condition √κ. Beyond it the full solve runs. */
#define HP_QP_WARM_KAPPA 1e8

typedef struct hp_qp {
    int n, m;
    double G[HP_QP_NMAX * HP_QP_NMAX]; /* n×n row-major (leading dimension n), symmetric
                                         * positive definite */
    double a[HP_QP_NMAX];
    double C[HP_QP_MMAX * HP_QP_NMAX]; /* row j at C + j·HP_QP_NMAX: constraint normal;
                                         * columns >= n are never read */
    double b[HP_QP_MMAX];
    /* Declared twin pairs: for i < pairs, row 2i + 1 of C is exactly −row 2i (a lower and
     * an upper limit on one quantity, as the realtime backend builds them), so the solver
     * does not compare them, reads only row 2i's entries for the checks on C, and works
     * per pair. 0 (zero-initialise the struct): twins are found by comparing each row with
     * the one before, as they are for the rows from 2·pairs on. Outside 0..m/2:
     * HP_QP_BAD_INPUT. A wrong declaration gives wrong answers, not an error. */
    int pairs;
    /* outputs */
    double x[HP_QP_NMAX];   /* entries >= n are set to 0 */
    double u[HP_QP_MMAX];   /* multiplier of every constraint (0 when inactive) */
    int active[HP_QP_MMAX]; /* 1 when constraint j is in the final active set */
    int iterations;         /* add + drop steps; a warm start counts one add step per
                             * guessed row it keeps (iterations − gi_steps of them in a
                             * call that neither resumed a stopped solve, whose count it
                             * carries on, nor fell back to the full solve, which counts
                             * from 0 again while gi_steps counts both runs) */
    hp_qp_warm warm;        /* what the warm start did (HP_QP_WARM_NONE without a guess) */
    int warm_solved;        /* 1 when this call solved the guessed rows' equality system
                             * (the warm start's main cost), else 0 */
    int gi_steps;           /* the Goldfarb–Idnani loop's add and drop steps this call ran
                             * (the rows a warm start keeps count none; a loop from kept
                             * rows that found the QP empty and the full solve that
                             * checked it both count) */
    int scans;              /* the scans for the most violated row this call ran that formed
                             * the rows' products with x (a resume's first scan, at the
                             * stopped iterate, reuses the stop's products: none) */
    /* workspace: Jᵀ and C zero-padded to HP_QP_NMAX columns, R, the active set */
    double J_[HP_QP_NMAX * HP_QP_NMAX], R_[HP_QP_NMAX * HP_QP_NMAX];
    double C_[HP_QP_MMAX * HP_QP_NMAX];
    int A_[HP_QP_NMAX];
    double uA_[HP_QP_NMAX + 1];
    double L_[HP_QP_NMAX * HP_QP_NMAX]; /* the Cholesky factor of G when the caller gives none
                                         * (lower triangle, leading dimension HP_QP_NMAX) */
    /* the full solve's row state: squared norms, twin flags, rows skipped (active or of zero
     * norm), the active set's size: kept here so that a stopped solve can go on */
    double nrm2_[HP_QP_MMAX];
    int twin_[HP_QP_MMAX], skip_[HP_QP_MMAX], q_;
    /* the warm start's guessed rows, their scaled multipliers and column norms, kept from
     * its equality solve for its check of the other rows (which a stop can interrupt) */
    double wu_[HP_QP_NMAX], wd_[HP_QP_NMAX];
    int wa_[HP_QP_NMAX], wk_;
    /* When the last hpi_qp_solve_lazy or hpi_qp_resume_lazy stopped (HP_QP_LAZY) where
     * hpi_qp_resume_lazy can continue: 1 in the full solve's loop, 2 in the warm start's
     * check of the other rows (after its equality solve); 0 after any other return (a stop
     * on a guessed row, before the equality solve, starts again) */
    int resumable;
    /* 1 while the loop runs from a warm start's kept rows (qp.c, warm_gi): an empty verdict
     * reached from there is checked by the full solve from scratch */
    int kept_;
    /* the rows' products C_j x at a stop's iterate (cxk_ 1 until a scan reads them): a
     * resume's first scan is at that x and takes them instead of forming them again */
    double cx_[HP_QP_MMAX];
    int cxk_;
    /* What the last set-ups of Jᵀ and R were formed from, and gave (qp.c, setup_inverse and
     * warm_gi): the factor of G (lower triangle, leading dimension HP_QP_NMAX, order ckn_)
     * and its inverse Jᵀ = L⁻¹; then the rows a warm start kept, added in order (ckk_ rows:
     * their indices and zero-padded normals), and Jᵀ, R after those adds. ck_ 0: nothing
     * kept (a zeroed struct), 1: the inverse, 2: the inverse and the adds. A copy is read
     * only where every input is the same bits, so it is the bits forming it again gives:
     * at the linear level G and the rows are the same every solve, only b and a change. */
    int ck_, ckn_, ckk_, cka_[HP_QP_NMAX];
    double ckL_[HP_QP_NMAX * HP_QP_NMAX], ckJ0_[HP_QP_NMAX * HP_QP_NMAX];
    double ckC_[HP_QP_NMAX * HP_QP_NMAX], ckJ_[HP_QP_NMAX * HP_QP_NMAX];
    double ckR_[HP_QP_NMAX * HP_QP_NMAX];
} hp_qp;

/* Solves the QP held in q (n, m, G, a, C, b filled) with at most max_iter add/drop steps;
 * feas_tol is the violation (in units of b, per unit-norm row) accepted as satisfied.
 * Returns HP_QP_BAD_INPUT for a NaN or infinity anywhere in G, a, C or b (first n columns;
 * of a declared pair's rows the first), for a row of C whose squared norm overflows, for G
 * not positive definite and for q->pairs outside 0..m/2; then the outputs are not
 * meaningful (u and active may be partly zeroed). Allocation-free; a row that is the exact negation of the row before it (a lower
 * and an upper limit on one quantity) costs about half a row, a declared pair (q->pairs)
 * no comparison. */
hp_qp_status hpi_qp_solve(hp_qp *q, int max_iter, double feas_tol);

/* hpi_qp_solve with Lg the lower Cholesky factor of exactly this q->G from hpi_cholesky
 * (leading dimension n; entries above the diagonal not read), when the caller has factored
 * G already (the realtime backend does, to test its convexity): G is not factored again.
 * Lg NULL: hpi_qp_solve. The factor is the same bits either way. */
hp_qp_status hpi_qp_solve_factored(hp_qp *q, const double *Lg, int max_iter, double feas_tol);

/* hpi_qp_solve_factored started from a guessed active set: guess[j] != 0 for the rows
 * guessed active (m entries; it may be q->active, read before it is overwritten; NULL: no
 * guess, exactly hpi_qp_solve_factored). The guessed rows' equality-constrained QP is
 * solved directly and returned when it meets the full QP's optimality conditions — rows
 * independent and well conditioned (HP_QP_WARM_KAPPA), every guessed multiplier >= 0,
 * every other row satisfied to feas_tol as the full solve measures it — which make it the
 * unique minimum. Otherwise (q->warm says why): refused on a multiplier's sign, the
 * guessed rows with negative multipliers leave one at a time, the most negative (scaled
 * by its row's norm in the G⁻¹ metric) first, the smaller system solved again, until every
 * multiplier is >= 0; that point, or on a violated row the guessed rows' point itself, is
 * dual feasible (the minimum with the kept rows as equalities, multipliers >= 0), and the
 * Goldfarb–Idnani loop starts there, with J and R those of adding the kept rows in order.
 * From any dual-feasible start the loop reaches the same unique minimum as from the
 * unconstrained one, in fewer steps when the kept rows are rows of the answer (the loop
 * steps of the loop benchmark's step trace: tests/planner/test_rate_window.c,
 * test_binding_walk_warm); if it finds the QP empty, the full solve from scratch decides
 * (a degenerate vertex, a row violated only by rounding, can end the loop from kept rows
 * there). Refused for shape or conditioning, or with no row kept, the full solve runs from
 * scratch: the same bits as without a guess. A guess with both rows of a twin pair, more
 * rows than n or than max_iter, or a zero row is refused unsolved. Outputs, statuses and
 * the refusal of bad input are those of hpi_qp_solve; the active set and multipliers can
 * differ from the full solve's only where they are not unique (degenerate vertices); x
 * agrees to rounding (tests/planner/test_qp_warm.c, test_warm_vs_cold); a QP whose feasible
 * set is a single point to rounding may be found empty by one path and that point, within
 * feas_tol, by the other. q must have been zeroed when it was made (or its ck_ set to 0):
 * the set-up kept from its last solve (ck_) is read, and taken where its inputs are the same
 * bits; hpi_qp_solve and hpi_qp_solve_factored forget it. */
hp_qp_status hpi_qp_solve_warm(hp_qp *q, const double *Lg, const int *guess, int max_iter,
                               double feas_tol);

/* hpi_qp_solve_warm with some rows' b a stand-in (lazy[j] != 0; NULL: none): each such b
 * is at least the exact one (a tighter constraint, never looser), and the solve stops
 * with HP_QP_LAZY and *hit = that row (hit may be NULL) at the first decision the stand-in
 * could make differently: the row is the most violated one (the one picked, or the one
 * refusing the warm start), a guessed row (its b enters the warm start's equality solve)
 * or a row of zero norm (its b alone says whether the QP is empty). Under its exact b a
 * stand-in row is violated less or not at all, and every other row's violation is the
 * same, so while no stand-in row is picked the exact solve picks the same rows: a solve
 * that does not stop is, step for step and bit for bit, the solve with the exact b (the
 * rows' b enter nowhere else; tests/planner/test_qp_warm.c, test_lazy_rows_same_bits). On HP_QP_LAZY the outputs
 * are not meaningful except x, the iterate at the stop. */
hp_qp_status hpi_qp_solve_lazy(hp_qp *q, const double *Lg, const int *guess,
                               const unsigned char *lazy, int *hit, int max_iter, double feas_tol);

/* Continues a solve that stopped with HP_QP_LAZY where it can (q->resumable), after the
 * caller made the stopped row's b exact (and possibly other stand-in rows': lazy as it is
 * now). Nothing else of q may have changed: not G, a, C, the other rows' b, nor the
 * outputs; the factor of G need not be given again (a stop in the warm start's check keeps
 * a copy). A stop in the full loop: the stopped iterate is the exact solve's at the same
 * step (no stand-in row was picked before, and the rows' b enter only through the active
 * rows, none of them a stand-in). A stop in the warm start's check: its equality solve read
 * only the guessed rows' b, none of them a stand-in, so the check goes on from its x. Either
 * way going on is the exact solve, bit for bit, without the set-up, the factorisation, the
 * equality solve, the steps a new start repeats and the rows' products at the stopped
 * iterate, which its first scan for the most violated row takes from the stop's scan
 * (the same bits; hp_qp.scans; tests/planner/test_qp_warm.c, test_lazy_resume_same_bits).
 * The same outputs and statuses as hpi_qp_solve_lazy; HP_QP_BAD_INPUT when q is not
 * resumable. */
hp_qp_status hpi_qp_resume_lazy(hp_qp *q, const unsigned char *lazy, int *hit, int max_iter,
                                double feas_tol);

#endif
