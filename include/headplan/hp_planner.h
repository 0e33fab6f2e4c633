/* The planner: a desired 6-DOF correction -> every bladder's pressure, inside the safe
 * pressure, stretch and rate limits.
 *
 * Lifecycle: hp_settings_default -> (edit) -> hp_planner_create (the only call that
 * allocates) -> hp_plan, as often as needed -> hp_planner_destroy.
 *
 * Thread-safety: one planner per thread. Distinct planners may run in different threads at
 * once EXCEPT with the Ipopt backend: Debian's Ipopt/MUMPS is not thread-safe, so the library
 * serialises Ipopt solves process-wide with a mutex (hp_plan with HP_BACKEND_IPOPT may wait
 * for another thread's Ipopt solve). The realtime and NLopt backends take no lock.
 *
 * DRAFT: the planner engineer owns and refines this header. */
#ifndef HP_PLANNER_H
#define HP_PLANNER_H

#include "headplan/hp_common.h"
#include "headplan/hp_kinematics.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum hp_backend {
    HP_BACKEND_REALTIME = 0, /* "realtime": direct chain, then a small bounded solver */
    HP_BACKEND_IPOPT,        /* "ipopt": reference, exact first and second derivatives */
    HP_BACKEND_NLOPT_SLSQP,  /* "nlopt-slsqp" */
    HP_BACKEND_NLOPT_COBYLA, /* "nlopt-cobyla": derivative-free */
    HP_BACKEND_COUNT_
} hp_backend;
const char *hp_backend_name(hp_backend b);
hp_error hp_backend_parse(const char *s, hp_backend *out);

/* Outcome of one plan. */
typedef enum hp_status {
    HP_STATUS_REACHED = 0,        /* the desired correction is met (to the tolerance) */
    HP_STATUS_CLOSEST,            /* unreachable: the closest reachable correction */
    HP_STATUS_ITERATION_LIMIT,    /* stopped by the iteration budget */
    HP_STATUS_TIME_LIMIT,         /* stopped by the time budget */
    HP_STATUS_INFEASIBLE_START,   /* the limits cannot all hold (e.g. rate limits) */
    HP_STATUS_INVALID_INPUT,      /* NaN/Inf or out-of-range desired correction */
    HP_STATUS_SOLVER_ERROR,       /* the backend failed */
    HP_STATUS_COUNT_
} hp_status;
const char *hp_status_name(hp_status s);

/* Why a bladder's answer sits on a limit (bit flags). */
enum {
    HP_BIND_PRESSURE_MIN = 1u << 0,
    HP_BIND_PRESSURE_MAX = 1u << 1,
    HP_BIND_STRETCH_MIN = 1u << 2,
    HP_BIND_STRETCH_MAX = 1u << 3,
    HP_BIND_RATE_DOWN = 1u << 4,
    HP_BIND_RATE_UP = 1u << 5
};
/* "pressure_min", ... for one flag bit; "unknown" otherwise. */
const char *hp_binding_name(unsigned flag);

#define HP_DEFAULT_BACKEND HP_BACKEND_REALTIME
#define HP_DEFAULT_LEVEL HP_LEVEL_LINEAR
#define HP_DEFAULT_TOLERANCE 1e-9      /* pose tolerance, mm and degrees */
#define HP_DEFAULT_MAX_ITER 200
#define HP_DEFAULT_MAX_TIME 1.0        /* seconds (Ipopt: CPU time) */
#define HP_DEFAULT_WEIGHT_MM_PER_DEG 1.0
#define HP_DEFAULT_MU 0.0

typedef struct hp_settings {
    hp_backend backend;       /* which solver runs when a limit binds */
    hp_level level;           /* contact fidelity (auto: resolved at create) */
    double level_tolerance;   /* [m] for HP_LEVEL_AUTO */
    double auto_trans;        /* [m] largest translation auto must cover */
    double auto_rot;          /* [rad] largest rotation auto must cover */
    double tolerance;         /* pose tolerance in mm and degrees (> 0) */
    int max_iter;             /* iteration budget per plan (> 0) */
    double max_time;          /* time budget per plan [s] (> 0) */
    double weight_mm_per_deg; /* W: 1 mm of error weighs as much as this many degrees */
    double mu;                /* pressure regularisation (tie-breaker) [1/Pa²], >= 0 */
    int use_rate_limits;      /* 1: apply each bladder's rate_max from the previous plan */
    int warm_start;           /* 1: start each solve from the previous result */
} hp_settings;

void hp_settings_default(hp_settings *s);
hp_error hp_settings_validate(const hp_settings *s, hp_diag *diag);

typedef struct hp_bladder_result {
    double ri, ro;       /* [m] */
    double pressure;     /* [Pa], always inside [p_min, p_max] */
    double stretch;      /* ri / Ri */
    unsigned binding;    /* HP_BIND_* flags */
} hp_bladder_result;

typedef struct hp_result {
    hp_status status;
    int raw_code;             /* the backend's own return code */
    double desired[6];        /* SI */
    double achieved[6];       /* SI; pose reached by the returned radii */
    int commanded[6];         /* 0 where the layout cannot command that direction */
    int n;
    hp_bladder_result bladders[HP_MAX_BLADDERS];
    int iterations;
    double solve_time;        /* [s] */
} hp_result;

typedef struct hp_planner hp_planner;

hp_error hp_planner_create(const hp_layout *layout, const hp_settings *settings,
                           hp_planner **out);
hp_error hp_plan(hp_planner *p, const double desired[6], hp_result *result);
const char *hp_planner_error(const hp_planner *p);
void hp_planner_destroy(hp_planner *p);

#ifdef __cplusplus
}
#endif
#endif
