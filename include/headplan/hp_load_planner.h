/* The load-level planner: a desired pose -> the bladder pressures that HOLD the head there
 * against its weight (hp_load.h), inside every pressure, stretch and limit-point bound.
 *
 * It is a planner object of its own, beside hp_planner (same settings, result and status
 * types), because the load level solves a different problem: at a pose the six
 * equilibrium equations are linear in the contact forces F_k, and n pressures leave an
 * (n − 6)-dimensional family that holds a reachable pose, from which a tie-breaker picks
 * one. See docs/load.md.
 *
 * Lifecycle: hp_load_planner_create (allocates) -> hp_load_plan (allocates nothing with the
 * realtime backend) -> hp_load_planner_destroy. One planner per thread. */
#ifndef HP_LOAD_PLANNER_H
#define HP_LOAD_PLANNER_H

#include "headplan/hp_load.h"
#include "headplan/hp_planner.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Which member of the family of holding pressures a reachable pose gets. */
typedef enum hp_load_tiebreak {
    HP_TIE_LEAST_SQUEEZE = 0, /* "least-squeeze": minimise sum_k P_k² */
    HP_TIE_PREVIOUS,          /* "previous": minimise sum_k (P_k − P_prev,k)² */
    HP_TIE_STIFFNESS,         /* "stiffness": maximise the holding stiffness's smallest
                                 eigenvalue (a smooth soft minimum of it; ipopt only) */
    HP_TIE_COUNT_
} hp_load_tiebreak;
HP_API const char *hp_load_tiebreak_name(hp_load_tiebreak t); /* "unknown" for other values */
HP_API hp_error hp_load_tiebreak_parse(const char *s, hp_load_tiebreak *out);

/* What the load planner reports beyond hp_result. */
typedef struct hp_load_info {
    double force[HP_MAX_BLADDERS]; /* contact force of each bladder [N] */
    double residual_force;         /* |sum f + m g| at the answer [N] (Newton–Euler) */
    double residual_moment;        /* |net moment about the centre of mass| [N·m] */
    double rest[6];                /* the forward statics' rest of the returned pressures,
                                      started at the answer [m, rad] */
    double rest_error;             /* max |rest − achieved| in mm / degrees */
    double indent[HP_MAX_BLADDERS];/* each bladder's delta/ro at the answer (hp_load_indentation) */
    hp_load_holding holding;       /* stiffness, stability and compliance of the answer: at
                                      the achieved pose with the returned pressures (not at
                                      the forward statics' rest) */
} hp_load_info;

typedef struct hp_load_planner hp_load_planner;

/* Builds a load planner for layout L carrying spec, with settings s (NULL = defaults;
 * s->level is the contact geometry: linear, plane or surface; auto means surface) and
 * tie-breaker tie (HP_TIE_STIFFNESS only with the ipopt backend). Refuses (HP_ERR_INVALID, message in diag) a sphere head (it cannot be
 * turned, and its contact forces pass through its centre), a layout in which no bladder
 * pushes against gravity ("no bladder pushes against gravity (+z)"), and a weight larger
 * than the bladders can carry along gravity at their largest pressures. */
HP_API hp_error hp_load_planner_create(const hp_layout *L, const hp_load_spec *spec,
                                const hp_settings *s, hp_load_tiebreak tie,
                                hp_load_planner **out, hp_diag *diag);

/* Plans the pressures that hold the head at desired[6] (SI). The request is checked as
 * hp_plan checks it, by the same code and with the same message (hp_load_planner_error):
 * a correction that is not finite, beyond hp_plan's caps or outside the layout's
 * identifiable range (hp_identifiable: a rotation angle of 90 degrees or more, a
 * translation beyond the head's smallest semi-axis) is INVALID_INPUT with the safe output
 * (the previous answer's pressures and pose, pose_error +inf). REACHED: the equilibrium
 * holds at the desired pose (the pose error is 0 by construction); CLOSEST: no pressures
 * inside the limits hold it there, and the answer is the nearest pose (weighted as the
 * settings say) at which some do that the closest-pose program finds (a local method from
 * several starts: docs/load.md), with the binding limits flagged, among them indent_max
 * (the indentation range, HP_LOAD_INDENT_MAX) and cannot_pull (a bladder carrying
 * nothing). "Limits" include the indentation range throughout. info (may be NULL)
 * gets the residuals, forces, the forward statics' rest of the answer and the holding. With
 * the realtime backend nothing is allocated. Every pressure is inside its limits, whatever
 * the status. A REACHED or CLOSEST answer is an equilibrium by two checks: Q below 1e-9 N
 * (hp_load_eval, which also requires every bladder centre outside the moved head) and, at
 * the plane and surface levels, the Newton–Euler residual from the contact points below
 * 1e-6 N and 1e-6 N·m; a pose found that fails either is not returned (SOLVER_ERROR with
 * the safe output and the reason in hp_load_planner_error). */
HP_API hp_error hp_load_plan(hp_load_planner *p, const double desired[6], hp_result *result,
                      hp_load_info *info);

/* Sets the pressures the bladders hold now [Pa] (n values): the `previous` tie-breaker and,
 * when the settings use rate limits, each bladder's rate_max of the next plan start from
 * them, and they are the safe output of a failed plan. Before the first plan or this call
 * there is no previous pressure and the first plan is not rate-limited. Each must be inside
 * the bladder's bounds (hp_load_planner_bounds); otherwise HP_ERR_INVALID (message in
 * hp_load_planner_error) and nothing changes. */
HP_API hp_error hp_load_planner_set_previous(hp_load_planner *p, const double *pressures);

/* The message of the last failure ("" when none). Never NULL. */
HP_API const char *hp_load_planner_error(const hp_load_planner *p);
/* The planner's model (layout, carried load, geometry), owned by the planner: valid until
 * hp_load_planner_destroy, never to be passed to hp_load_model_destroy. NULL for NULL p. */
HP_API const hp_load_model *hp_load_planner_model(const hp_load_planner *p);
/* Each bladder's pressure bounds [Pa] (from the pressure, stretch, stress and limit-point
 * limits; a plan's rate limits cut them further). */
HP_API hp_error hp_load_planner_bounds(const hp_load_planner *p, double *lo, double *hi);
HP_API void hp_load_planner_destroy(hp_load_planner *p);

#ifdef __cplusplus
}
#endif
#endif
