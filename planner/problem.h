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
#include "kinematics/kin_geom.h"
#include "planner/load_solve.h"

typedef struct hp_problem {
    const hp_layout *layout;
    const hp_geom *geom;           /* layout's contact geometry, derived with it */
    hp_level level;                /* resolved: never HP_LEVEL_AUTO */
    int n;                         /* bladders */
    int nx;                        /* 6 + n */
    double w[6];                   /* objective weights per scaled unit² (0: not commanded) */
    double mu;                     /* [1/Pa²] */
    double d[6];                   /* desired correction, scaled (mm, deg) */
    double ri_lo[HP_MAX_BLADDERS]; /* [mm] bounds for this cycle */
    double ri_hi[HP_MAX_BLADDERS];
    double ro_lo[HP_MAX_BLADDERS]; /* the same bounds as outer radius [mm] */
    double ro_hi[HP_MAX_BLADDERS];
    double p_prev[HP_MAX_BLADDERS]; /* previous pressures [Pa] */
    /* Each bladder's rate window around p_prev ([-inf, inf] without a rate limit), worked
     * out once a plan (hpi_setup_rate_windows, in validate: valid from there to the plan's
     * end; the setters of p_prev leave them, the next plan works them out) and read by the
     * measured start check, the lazy set-up and its resolves, and the answer. Set only when
     * rate limits apply. The eager set-up (hpi_setup_cycle_bounds_memo, for backends that
     * do not resolve ends themselves) and hpi_setup_rate_surely_left work from p_prev. */
    double w_lo[HP_MAX_BLADDERS], w_hi[HP_MAX_BLADDERS];
    double ri_lo_si[HP_MAX_BLADDERS]; /* ri_lo, ri_hi in metres, exactly the radii whose
                                         stretch and pressure hold their limits in double
                                         precision (the mm copies may differ by an ulp) */
    double ri_hi_si[HP_MAX_BLADDERS];
    /* NULL: every bound above is exact. Else some rate window ends are stand-ins inside
     * their exact bounds (problem_setup.h, hp_rate_lazy), for a backend with
     * HP_BACKEND_LAZY_RATE: it resolves an end before any comparison a stand-in could decide
     * differently from the exact bound. */
    struct hp_rate_lazy *lazy;
} hp_problem;

/* The objective's weight of pose component i (0..5) in its scaled unit: 1 per mm², and
 * 1/weight² per degree² for weight_mm_per_deg (a degree counts as that many mm). */
static inline double hpi_pose_weight(double weight_mm_per_deg, int i)
{
    return i < 3 ? 1.0 : 1.0 / (weight_mm_per_deg * weight_mm_per_deg);
}

/* Objective f(x); grad (nx) and hess (nx×nx dense, row-major) may be NULL. */
hp_error hpi_problem_objective(const hp_problem *pb, const double *x, double *f, double *grad,
                               double *hess);

/* Equality constraints c_k(x) = ro(ri_k) − ρ_k(ξ) [mm], k < n; jac (n×nx row-major) may be
 * NULL; if lambda is not NULL, adds Σ_k lambda_k ∇²c_k into hess (nx×nx dense). */
hp_error hpi_problem_constraints(const hp_problem *pb, const double *x, double *c, double *jac,
                                 const double *lambda, double *hess);

/* Scratch an hp_plan call needs, sized for HP_MAX_BLADDERS, so no solve allocates. */
#define HP_PROBLEM_NX_MAX (6 + HP_MAX_BLADDERS)

/* A solver backend: one table of function pointers per backend file. The core sees only this.
 * create allocates everything the backend needs; solve allocates nothing it can avoid (Ipopt
 * and NLopt allocate internally: documented) and fills x (nx, scaled) and its own raw code. */
typedef struct hp_backend_result {
    hp_status status; /* REACHED/CLOSEST decided by the core; backends set the rest */
    int raw_code;
    int iterations;
    int converged; /* 1 when the backend reports a (locally) optimal point */
    /* 1 when rho holds the contact distances [mm] at the returned pose, evaluated by the
     * backend at exactly that pose: the core then need not evaluate them again, and derives
     * the inner radii from them (the backend may then leave x[6 + k] NAN). */
    int has_rho;
    double rho[HP_MAX_BLADDERS];
    /* 1 when the backend's answer is a step so short from its last linearisation point
     * lin_x (scaled pose) that rho was extrapolated from there: lin_rho [mm] and lin_J
     * (n×6, SI: per m and per rad, as hpi_contact_eval_g gives it) are the model at lin_x.
     * The round trip's certificate then may hold before the fit's second evaluation. */
    int has_lin;
    double lin_x[6], lin_rho[HP_MAX_BLADDERS], lin_J[HP_MAX_BLADDERS * 6];
} hp_backend_result;

/* What a backend is, so the core asks for a property instead of testing the enum. */
enum {
    /* A converged claim is a certified local optimum (Ipopt's KKT test, the realtime QP's
     * multiplier signs): the core need not re-check first-order conditions. */
    HP_BACKEND_CERTIFIES = 1u << 0,
    /* Solves from different threads need no process-wide lock (Ipopt's MUMPS does). */
    HP_BACKEND_THREAD_SAFE = 1u << 1,
    /* solve allocates nothing and is bounded by max_iter (the control loop's path). */
    HP_BACKEND_REAL_TIME = 1u << 2,
    /* Uses warm_point: warm-starts from its own last answer (points and multipliers). */
    HP_BACKEND_WARM_STARTS = 1u << 3,
    /* Plans the load level: load_hold is set (load_level.c). */
    HP_BACKEND_LOAD = 1u << 4,
    /* Its load_hold solves the stiffness tie-breaker (HP_TIE_STIFFNESS). */
    HP_BACKEND_LOAD_STIFFNESS = 1u << 5,
    /* A contact-level CLOSEST is the local optimum its one start leads to: nothing looks
     * for another, so the answer's note says so. The realtime backend has no such flag: its
     * closest answers are held to the best of the offline backends and a multi-start
     * reference in the clinically relevant range (tests/reliability/test_best_local.c). */
    HP_BACKEND_ONE_START = 1u << 6,
    /* With HP_BACKEND_ONE_START: solves again from settings.restarts further starts after a
     * CLOSEST answer (docs/planner.md, Restarts), so only restarts = 0 leaves it one start. */
    HP_BACKEND_RESTARTS = 1u << 7,
    /* Solves with rate window ends not yet solved (hp_problem.lazy), resolving those its
     * points come near; the other backends get every bound exact. */
    HP_BACKEND_LAZY_RATE = 1u << 8
};

typedef struct hp_backend_ops {
    const char *name; /* = hp_backend_name of its enum value */
    unsigned caps;    /* HP_BACKEND_* flags */
    hp_error (*create)(void **state, const hp_problem *pb, const hp_settings *s, hp_diag *d);
    hp_error (*solve)(void *state, const hp_problem *pb, const double *x0, double *x,
                      hp_backend_result *r, hp_diag *d);
    void (*destroy)(void *state);
    /* Optional (NULL: the backend keeps nothing between solves). The core says whether the
     * next solve starts from the answer this backend's last solve returned (accepted = 1:
     * the backend may reuse its multipliers) or from some other point (0). */
    void (*warm_point)(void *state, int accepted);
    /* Optional (NULL: ignored). Called after warm_point(state, 0) by
     * hp_planner_set_measured: the next solve's previous pressures are a reading, not this
     * backend's answer. When the answer before the reading was this backend's own (or a
     * reading of it), the reading is most likely of that answer's pressures, so the
     * backend may take the limits that answer bound as a guess (never as a start point). */
    void (*reading)(void *state);
    /* Optional (NULL: no options). A backend-specific option by name; HP_ERR_INVALID for a
     * name it does not know or a bad value (message in d). Takes effect at the next solve. */
    hp_error (*set_option)(void *state, const char *name, double value, hp_diag *d);
    /* Optional (NULL: the backend does not plan the load level). HOLD at the load level
     * (load_solve.h, hpi_load_hold): pressures P[n] inside [lo, hi] holding the head at xi,
     * the one nearest to target (stiffness = 1: the stiffest, with HP_BACKEND_LOAD_STIFFNESS)
     * among all that do, from start (may be NULL); F their forces. raw gets the solver's own
     * code when it has one (left alone otherwise). */
    hpi_load_solve_status (*load_hold)(const hp_load_model *M, const double xi[6], const double *lo,
                                       const double *hi, const double *target, const double *start,
                                       int max_iter, int stiffness, double *P, double *F,
                                       int *iterations, int *raw);
    /* Optional (NULL: HOLD's stable search forms the holding set and scans it itself).
     * load_hold with the distance tie-breaker that also hands back the holding set it formed
     * at xi and its scan's record (load_solve.h, hpi_load_hold_keep), so that the stable
     * search (load_stable.h) neither forms nor scans the same set again. */
    hpi_load_solve_status (*load_hold_keep)(const hp_load_model *M, const double xi[6],
                                            const double *lo, const double *hi,
                                            const double *target, const double *start, int max_iter,
                                            double *P, double *F, int *iterations,
                                            hp_load_hold_set *hs, hp_load_scan_rec *rec);
} hp_backend_ops;

extern const hp_backend_ops hpi_backend_realtime_ops;
extern const hp_backend_ops hpi_backend_ipopt_ops;
extern const hp_backend_ops hpi_backend_nlopt_slsqp_ops;
extern const hp_backend_ops hpi_backend_nlopt_cobyla_ops;

#endif
