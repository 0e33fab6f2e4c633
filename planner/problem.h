/* Internal: the planner's nonlinear program, shared by every backend.
 *
 * Variables x (scaled so the solvers see numbers near 1, docs/solver-facts.md "Scaling matters"):
 *   x[0..2] translation [mm], x[3..5] rotation [deg], x[6+k] inner radius ri_k [mm].
 * Problem:
 *   minimise   Σ_i w_i (x_i − d_i)²  +  mu · Σ_k (P_k(ri_k) − p_prev_k)²
 *   subject to ro(ri_k) − ρ_k(ξ) = 0                 (contact kept, mm)
 *              ri_lo_k <= ri_k <= ri_hi_k            (pressure, stretch and rate limits,
 *                                                     all mapped to ri through the monotone
 *                                                     stable branch of the bladder IK)
 * Equivalently, with ri eliminated: ro_lo_k <= ρ_k(ξ) <= ro_hi_k (the realtime path's form).
 *
 * Written by the planner engineers; this file fixes the contract between the core and the
 * backends. */
#ifndef HP_PLANNER_PROBLEM_H
#define HP_PLANNER_PROBLEM_H

#include "headplan/hp_planner.h"

typedef struct hp_problem {
    const hp_layout *layout;
    hp_level level;                  /* resolved: never HP_LEVEL_AUTO */
    int n;                           /* bladders */
    int nx;                          /* 6 + n */
    double w[6];                     /* objective weights per scaled unit² (0: not commanded) */
    double mu;                       /* [1/Pa²] */
    double d[6];                     /* desired correction, scaled (mm, deg) */
    double ri_lo[HP_MAX_BLADDERS];   /* [mm] bounds for this cycle */
    double ri_hi[HP_MAX_BLADDERS];
    double ro_lo[HP_MAX_BLADDERS];   /* the same bounds as outer radius [mm] */
    double ro_hi[HP_MAX_BLADDERS];
    double p_prev[HP_MAX_BLADDERS];  /* previous pressures [Pa] */
    double ri_lo_si[HP_MAX_BLADDERS]; /* ri_lo, ri_hi in metres, exactly the radii whose
                                         stretch and pressure hold their limits in double
                                         precision (the mm copies may differ by an ulp) */
    double ri_hi_si[HP_MAX_BLADDERS];
} hp_problem;

/* Objective f(x); grad (nx) and hess (nx×nx dense, row-major) may be NULL. */
hp_error hp_problem_objective(const hp_problem *pb, const double *x, double *f, double *grad,
                              double *hess);

/* Equality constraints c_k(x) = ro(ri_k) − ρ_k(ξ) [mm], k < n; jac (n×nx row-major) may be
 * NULL; if lambda is not NULL, adds Σ_k lambda_k ∇²c_k into hess (nx×nx dense). */
hp_error hp_problem_constraints(const hp_problem *pb, const double *x, double *c, double *jac,
                                const double *lambda, double *hess);

/* Scratch an hp_plan call needs, sized for HP_MAX_BLADDERS, so no solve allocates. */
#define HP_PROBLEM_NX_MAX (6 + HP_MAX_BLADDERS)

/* A solver backend: one table of function pointers per backend file. The core sees only this.
 * create allocates everything the backend needs; solve allocates nothing it can avoid (Ipopt
 * and NLopt allocate internally: documented) and fills x (nx, scaled) and its own raw code. */
typedef struct hp_backend_result {
    hp_status status;   /* REACHED/CLOSEST decided by the core; backends set the rest */
    int raw_code;
    int iterations;
    int converged;      /* 1 when the backend reports a (locally) optimal point */
} hp_backend_result;

typedef struct hp_backend_ops {
    const char *name;
    hp_error (*create)(void **state, const hp_problem *pb, const hp_settings *s, hp_diag *d);
    hp_error (*solve)(void *state, const hp_problem *pb, const double *x0, double *x,
                      hp_backend_result *r, hp_diag *d);
    void (*destroy)(void *state);
} hp_backend_ops;

extern const hp_backend_ops hp_backend_realtime_ops;
extern const hp_backend_ops hp_backend_ipopt_ops;
extern const hp_backend_ops hp_backend_nlopt_slsqp_ops;
extern const hp_backend_ops hp_backend_nlopt_cobyla_ops;

#endif
