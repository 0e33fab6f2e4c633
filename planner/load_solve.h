/* Internal: the load planner's HOLD and POSE solves (see load_solve.c). No allocation. */
#ifndef HP_PLANNER_LOAD_SOLVE_H
#define HP_PLANNER_LOAD_SOLVE_H

#include "headplan/hp_load.h"

typedef enum hpi_load_solve_status {
    HP_LOAD_SOLVE_OK = 0,
    HP_LOAD_SOLVE_UNREACHABLE, /* no pressures inside the bounds hold this pose */
    HP_LOAD_SOLVE_ITERATION_LIMIT,
    HP_LOAD_SOLVE_ERROR /* the model failed (geometry or bladder domain) */
} hpi_load_solve_status;

/* HOLD: pressures P[n] inside [lo, hi] holding the head at xi, nearest (sum of squares) to
 * target[n] among all that do; F[n] their contact forces. start (may be NULL) seeds the
 * forces. */
hpi_load_solve_status hpi_load_hold(const hp_load_model *M, const double xi[6], const double *lo,
                                    const double *hi, const double *target, const double *start,
                                    int max_iter, double *P, double *F, int *iterations);

/* The minimum-holding-stiffness objective at a fixed pose (load_stiffness.c): the soft
 * minimum of the eigenvalues of the holding stiffness K(P) in N/mm (mm/degree units),
 * negated, plus squeeze·½·sum (P − t)² (kPa) to break its own ties. */
#define HP_LOAD_STIFF_BETA 20.0    /* [mm/N] soft-min sharpness: within log(6)/20 = 0.09 N/mm */
#define HP_LOAD_STIFF_SQUEEZE 1e-6 /* [N/mm per kPa²] */
typedef struct hp_load_stiff {
    const hp_load_model *M;
    int n;
    double K0[36];                  /* gravity's stiffness, scaled */
    double JJ[HP_MAX_BLADDERS][36]; /* J_k J_kᵀ, scaled (times the law's normal stiffness) */
    double H[HP_MAX_BLADDERS][36];  /* the contact distance's Hessian, scaled */
    double rho[HP_MAX_BLADDERS];
    const double *target; /* [Pa] */
    double beta, squeeze;
} hp_load_stiff;

/* Prepares the objective at pose xi (target [Pa], kept by pointer). HP_ERR_* of the model. */
hp_error hpi_load_stiff_init(hp_load_stiff *S, const hp_load_model *M, const double xi[6],
                             const double *target);

/* The objective at x[nv] (kPa; variable j is bladder idx[j]): f, its gradient (nv) and its
 * Hessian (nv×nv, row-major, both triangles), each may be NULL; lam_min (may be NULL) the
 * smallest eigenvalue of K [N/mm]. 0 on success, -1 when the model fails. */
int hpi_load_stiff_eval(const hp_load_stiff *S, int nv, const int *idx, const double *x, double *f,
                        double *grad, double *hess, double *lam_min);

/* The holding set at a pose: {A·F = b, Flo <= F <= Fhi} (A 6×n, weighted rows) in the
 * forces, with each bladder's carrying pressures [L, U] (L: where it starts to carry, U: the
 * top of its bounds and of the indentation range) and touching pressure Pt. HOLD's scan
 * and the stable search (load_stable.c) work on it. */
typedef struct hp_load_hold_set {
    const hp_load_model *M;
    int n;
    const double *lo, *target;
    double rho[HP_MAX_BLADDERS], A[6 * HP_MAX_BLADDERS], b[6];
    double L[HP_MAX_BLADDERS], U[HP_MAX_BLADDERS], Flo[HP_MAX_BLADDERS], Fhi[HP_MAX_BLADDERS];
    double Pt[HP_MAX_BLADDERS];
    double fscale, tol; /* the largest |b_r| and the rows' tolerance */
    /* The m bladders that can carry (L < U), col[], and the inner radii at the ends of their
     * carrying pressures (ra at L, rc at U; 0 for the others). */
    int col[HP_MAX_BLADDERS], m;
    double ra[HP_MAX_BLADDERS], rc[HP_MAX_BLADDERS];
} hp_load_hold_set;

/* The holding set at pose xi inside [lo, hi] for the tie-breaker target (both kept by
 * pointer): OK, UNREACHABLE when a bladder centre is inside the head or a row no force box
 * can meet, ERROR when the model fails. */
hpi_load_solve_status hpi_load_hold_set_at(const hp_load_model *M, const double xi[6],
                                           const double *lo, const double *hi, const double *target,
                                           hp_load_hold_set *h);

/* A point x (forces) of the set: P gets its pressures, R (may be NULL) the carrying
 * bladders' inner radii, *e the tie-breaker sum (P − t)², which stops early once it reaches
 * stop. 0, or -1 when the model fails. */
int hpi_load_hold_set_point(const hp_load_hold_set *h, const double *x, double stop, double *e,
                            double *P, double *R);

/* The point of the set at pressures P[n] (a HOLD answer: inside [L, U] where a bladder
 * carries): x gets its forces (each clamped into its range; at or below L its least force
 * Flo, positive where its pressure floor lies above touching), Pp the pressures
 * hpi_load_hold_set_point gives a point of those forces (L at or below L, U at the top,
 * else P itself: the solve from the force would return it to rounding), and R
 * the carrying bladders' inner radii at them (0 for the others). One forward-kinematics
 * solve a carrying bladder strictly inside its carrying range (none at its ends: the set's
 * ra, rc), no pressure solve. 0, or -1 when the model fails. */
int hpi_load_hold_set_at_pressures(const hp_load_hold_set *h, const double *P, double *x,
                                   double *Pp, double *R);

/* Two points a, b of the set (forces xa, xb) whose pressures were solved, with their inner
 * radii Ra, Rb (hpi_load_hold_set_point's R): a point between them (forces x between xa and
 * xb bladder by bladder, as on the segment from a to b) has each carrying bladder's inner
 * radius between theirs, so its pressure solve starts from that bracket. */
typedef struct hp_load_near {
    const double *xa, *Ra, *xb, *Rb;
} hp_load_near;

/* hpi_load_hold_set_point(h, h's carrying bladders, x, no stop, ...) with each bladder whose
 * force lies strictly between nr's two (both carrying, below the top of the range) solved
 * from their radii, stopping after a Newton step of at most 1e-8 of the radius (the root to
 * rounding: quadratic convergence), about two steps. 0, or -1 when the model fails. */
int hpi_load_hold_set_point_near(const hp_load_hold_set *h, const hp_load_near *nr, const double *x,
                                 double *e, double *P, double *R);

/* A test of a point of the set (forces x, pressures P, inner radii R): 1 accept, 0 reject,
 * -1 failure. */
typedef int (*hp_load_point_test)(void *ctx, const double *x, const double *P, const double *R);

/* The tie-breaker's grid points per free coordinate of the set, and the most a scan takes
 * (the stable search's finer scan: 7). */
#define HP_LOAD_SCAN_GRID_N 3
#define HP_LOAD_SCAN_GRID_MAX 7
_Static_assert(HP_LOAD_SCAN_GRID_N <= HP_LOAD_SCAN_GRID_MAX, "the scan keeps its grid forces");

/* HOLD's scan of the set (load_solve.c): a grid_n × grid_n grid of its (at most two) free
 * pressures and its vertices; f gets the point with the least tie-breaker sum among those
 * test (may be NULL) accepts. 0, or -1 when none qualifies (and for grid_n above
 * HP_LOAD_SCAN_GRID_MAX, which every caller's constant is asserted not to be). */
int hpi_load_hold_set_scan(const hp_load_hold_set *h, int grid_n, hp_load_point_test test,
                           void *ctx, double *f);

/* The scan can carry at most eight bladders (six rows, at most two free forces), so it has at
 * most HP_LOAD_SCAN_GRID_N² grid points and 4·C(8, 2) vertices. */
#define HP_LOAD_SCAN_CARRY 8
#define HP_LOAD_SCAN_POINTS (HP_LOAD_SCAN_GRID_N * HP_LOAD_SCAN_GRID_N + 4 * 28)

/* HOLD's scan (the tie-breaker's, without a test) as it went, point by point in its order,
 * for the stable search to replay instead of scanning the same set again: each point's
 * carrying forces, and its tie-breaker sum as far as the scan summed it (done of the m
 * carrying bladders, in col order: the scan stops a sum once it cannot win) with those
 * bladders' pressures and inner radii. Indexed like the set's col[]. valid = 0: no record
 * (the scan did not run to its end, or the set was not scanned). */
typedef struct hp_load_scan_rec {
    int valid, count;
    int done[HP_LOAD_SCAN_POINTS];
    double e[HP_LOAD_SCAN_POINTS];
    double x[HP_LOAD_SCAN_POINTS][HP_LOAD_SCAN_CARRY];
    double P[HP_LOAD_SCAN_POINTS][HP_LOAD_SCAN_CARRY];
    double R[HP_LOAD_SCAN_POINTS][HP_LOAD_SCAN_CARRY];
} hp_load_scan_rec;

/* The same answer as hpi_load_hold_set_scan(h, HP_LOAD_SCAN_GRID_N, test, ctx, f), bit for
 * bit, from rec (HOLD's scan of h): the points in the scan's order, each sum carried on from
 * where HOLD's stopped only as far as the test's scan would carry it. Sums it carries on
 * are written back to rec. *e, P and R get the answer's tie-breaker sum, pressures and
 * inner radii, the bits hpi_load_hold_set_point gives for f. 0, or -1 when none qualifies or
 * the model or the test fails. */
int hpi_load_scan_replay(const hp_load_hold_set *h, hp_load_scan_rec *rec, hp_load_point_test test,
                         void *ctx, double *f, double *e, double *P, double *R);

/* hpi_load_hold (the realtime tie-breaker) that also hands back the holding set it formed
 * at xi (*hs, when the status is not ERROR) and its scan's record (*rec), for HOLD's stable
 * search (load_stable.h, hpi_load_stable_hold_set). */
hpi_load_solve_status hpi_load_hold_keep(const hp_load_model *M, const double xi[6],
                                         const double *lo, const double *hi, const double *target,
                                         const double *start, int max_iter, double *P, double *F,
                                         int *iterations, hp_load_hold_set *hs,
                                         hp_load_scan_rec *rec);
/* TEST-ONLY counts (summed over the process): the scans of holding sets (HOLD's and the
 * stable search's) and the vertices they solved for (at most 4·C(8, 2) a scan). */
void hpi_test_scan_counts(unsigned long *scans, unsigned long *vertices);
/* TEST-ONLY counts (summed over the process): the pressure-of-force solves that iterated
 * (a force strictly inside a bladder's range), their Newton-or-bisection steps (one law
 * evaluation each), and those that took more than HP_LOAD_PRESSURE_STEPS_LONG steps. */
#define HP_LOAD_PRESSURE_STEPS_LONG 16
void hpi_test_pressure_counts(unsigned long *solves, unsigned long *steps, unsigned long *longer);
/* TEST-ONLY count (summed over the process): the passes through the bladder model (its
 * validation, the pressure at an inner radius and the outer radius) those solves made. */
void hpi_test_pressure_model_counts(unsigned long *passes);
/* TEST-ONLY counts (summed over the process): the holding sets formed (hpi_load_hold_set_at),
 * and the bladder states evaluated with their pressure derivatives (the tie-breaker's SQP
 * steps need them; a force alone needs neither the law's derivatives nor the IK's). */
void hpi_test_hold_counts(unsigned long *sets, unsigned long *derived);
/* TEST-ONLY count (summed over the process): the bladder forward-kinematics solves (inner
 * radius of a pressure, hp_iab_fk_limit) of HOLD, its holding sets and the stable search. */
void hpi_test_fk_counts(unsigned long *fk);
/* TEST-ONLY count (summed over the process): the 6×6 holding-stiffness eigenproblems the
 * load planner solved (hpi_load_stiff_lambda_at, hpi_load_stiff_lambda_min). */
void hpi_test_eigen_counts(unsigned long *eigen);

/* The smallest eigenvalue [N/mm] of the holding stiffness of S's pose when the nv bladders
 * idx[] carry forces F [N] with normal stiffnesses a [N/m] (a = −dF/drho) and the others
 * nothing. 0, or -1 when the decomposition fails. */
int hpi_load_stiff_lambda_at(const hp_load_stiff *S, int nv, const int *idx, const double *F,
                             const double *a, double *lam);

/* Whether that stiffness's smallest eigenvalue is above margin [N/mm]: exactly when
 * K − margin·I is positive definite, so one 6×6 Cholesky factorisation answers it (about a
 * twentieth of the eigenproblem's work). 1 above, 0 not (at margin itself too), -1 when K is
 * not finite. */
int hpi_load_stiff_above(const hp_load_stiff *S, int nv, const int *idx, const double *F,
                         const double *a, double margin);

/* The smallest eigenvalue [N/mm, mm/degree units, the scale of the stable margin] of a
 * holding stiffness K (hp_load_holding.K, SI). 0, or -1 when the decomposition fails. */
int hpi_load_stiff_lambda_min(const double K[36], double *lam);

/* The tie-breaker NLP of HOLD at a fixed pose, for a general-purpose solver: variables the
 * pressures (kPa) of the bladders with L_k < U_k (the others fixed at L_k), objective
 * ½·sum (P − t)² (or, with stiffness, the stiffness objective above), constraints
 * sum_k A[r][k]·F_k(P_k) = b[r] (six). */
typedef struct hp_load_hold_nlp {
    const hp_load_model *M;
    int n;
    const double *rho, *A, *b, *L, *U, *target; /* A 6×n row-major; L, U, target in Pa */
    const double *xi;                           /* the pose [m, rad] */
    int stiffness;                              /* 1: the stiffness objective at xi
                                                     (load_stiffness.c), 0: the distance */
} hp_load_hold_nlp;

/* A general-purpose solver of that NLP from p (Pa, feasible); p gets the answer, raw the
 * solver's own code. */
typedef hpi_load_solve_status (*hp_load_nlp_solver)(const hp_load_hold_nlp *nlp, double *p,
                                                    int max_iter, int *iterations, int *raw);

/* HOLD (hpi_load_hold) with its second phase, the tie-breaker, solved by nlp_solve (a
 * backend's: hpi_load_hold_ipopt, hpi_load_hold_nlopt); the first phase (reachability) is the
 * same exact one. stiffness = 1 replaces the distance to target by the minimum-holding-
 * stiffness objective (target then only breaks its ties; Ipopt only). Allocates (inside the
 * solver); Ipopt takes the process-wide Ipopt lock. */
hpi_load_solve_status hpi_load_hold_with(hp_load_nlp_solver nlp_solve, const hp_load_model *M,
                                         const double xi[6], const double *lo, const double *hi,
                                         const double *target, const double *start, int max_iter,
                                         int stiffness, double *P, double *F, int *iterations,
                                         int *raw);

/* The NLP's variables for a solver: the bladders whose bounds leave room (L < U), in kPa
 * (the solvers' scale), started from p clamped into the bounds. Fills idx (variable j is
 * bladder idx[j]), xl, xu, x; returns how many. Shared by the Ipopt and NLopt hold. */
int hpi_load_hold_vars(const hp_load_hold_nlp *nlp, const double *p, int *idx, double *xl,
                       double *xu, double *x);

/* Writes the nf variables x (kPa) back into p (Pa) for bladders idx[], clamped into [L, U]
 * so rounding of the scale cannot leave a bound. */
void hpi_load_hold_answer(const hp_load_hold_nlp *nlp, const double *x, const int *idx, int nf,
                          double *p);

/* Solves that NLP from p (Pa, feasible) with Ipopt (load_ipopt.c); p gets the answer. */
hpi_load_solve_status hpi_load_hold_ipopt(const hp_load_hold_nlp *nlp, double *p, int max_iter,
                                          int *iterations, int *raw);

/* The same NLP on NLopt SLSQP (load_nlopt.c); raw gets NLopt's result code. */
hpi_load_solve_status hpi_load_hold_nlopt(const hp_load_hold_nlp *nlp, double *p, int max_iter,
                                          int *iterations, int *raw);

/* Bladder k's contact force at pressure P against contact distance rho (the contact branch's
 * formula, not clipped at 0) with dF/dP and d²F/dP² (both NULL: the force alone, without the
 * law's derivatives or the IK's; the same bits). */
hp_error hpi_load_bladder_force(const hp_load_model *M, int k, double P, double rho, double *F,
                                double *dF, double *d2F);

/* Bladder k's contact stiffness along its normal at pressure P against rho, a = −dF/drho
 * (the contact branch's formula), with da/dP and d²a/dP² (through ro(P)): a[0..2]. */
hp_error hpi_load_bladder_stiff(const hp_load_model *M, int k, double P, double rho, double a[3]);

/* Row weights of the equilibrium equations: N for the force rows, and N·m/rad times
 * (1°/1 mm) for the moment rows, so both read as "force per unit of pose". */
double hpi_load_row_weight(int r);

/* The touching pressure of bladder k at contact distance rho: the one whose free radius is
 * rho (−inf when rho is below the smallest radius the cavity allows, +inf past the limit
 * point). */
double hpi_load_touch_pressure(const hp_load_model *M, int k, double rho);

/* The pressure at which bladder k, at contact distance rho, reaches the edge of the
 * indentation range (delta/ro = HP_LOAD_INDENT_MAX): the largest a carrying bladder may
 * hold there. +inf past the limit point, −inf below the smallest radius. */
double hpi_load_indent_pressure(const hp_load_model *M, int k, double rho);

/* POSE: the pose nearest to desired (weights W per mm² and degree²) at which pressures in
 * [lo, hi] hold the head, from (xi0, P0); P gets those pressures (not tie-broken). */
hpi_load_solve_status hpi_load_pose(const hp_load_model *M, const double desired[6],
                                    const double W[6], const double *lo, const double *hi,
                                    const double xi0[6], const double *P0, int max_iter,
                                    double xi[6], double *P, int *iterations);

/* CLOSEST: the held pose nearest to desired (weights W per mm² and degree²) as one program
 * in the pose and the contact forces,
 *     minimise ½·sum_i W_i·(xi_i − desired_i)²  subject to
 *     sum_k F_k·J_k(xi) + Q_grav(xi) = 0,   Flo_k(xi) <= F_k <= Fhi_k(xi),
 * where [Flo_k, Fhi_k] are the forces bladder k can carry at pose xi inside [lo_k, hi_k]
 * and the indentation range (load_closest.c). Started from pose xi0 with forces F0 (a held
 * pose and its forces; F0 NULL: every bladder at the middle of its force range, a start
 * that need not hold the head); xi gets the pose where it stops (feasible to the
 * equilibrium's rounding, not yet verified: the caller holds it with HOLD). */
hpi_load_solve_status hpi_load_closest(const hp_load_model *M, const double desired[6],
                                       const double W[6], const double *lo, const double *hi,
                                       const double xi0[6], const double *F0, int max_iter,
                                       double xi[6], int *iterations);
/* TEST-ONLY counts (summed over the process): CLOSEST's solves, their evaluations of the rows
 * and the free outer radii (hp_load_radius: a forward-kinematics solve each) they asked for. */
void hpi_test_closest_counts(unsigned long *solves, unsigned long *evals, unsigned long *radii);

#endif
