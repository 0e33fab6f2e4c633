/* The planner: a desired 6-DOF correction -> every bladder's pressure, inside the safe
 * pressure, stretch and rate limits.
 *
 * Lifecycle: hp_settings_default -> (edit) -> hp_planner_create (the only call that
 * allocates) -> hp_plan, as often as needed -> hp_planner_destroy.
 *
 * Units: the API speaks SI (m, rad, Pa) like hp_pose.h; the tolerance and the weight
 * speak mm and degrees, the units the solvers work in.
 *
 * Thread-safety: one planner per thread. Distinct planners may run in different threads at
 * once EXCEPT with the Ipopt backend: Debian's Ipopt/MUMPS is not thread-safe, so the library
 * serialises Ipopt solves process-wide with a mutex (hp_plan with HP_BACKEND_IPOPT may wait
 * for another thread's Ipopt solve). The realtime and NLopt backends take no lock.
 *
 * Real time: with HP_BACKEND_REALTIME, hp_plan allocates nothing, prints nothing, takes no
 * lock and runs in bounded time (the direct chain, else at most max_iter active-set steps per
 * QP and, on the plane/surface levels, at most max_iter SQP steps). The Ipopt and NLopt
 * libraries allocate inside their own solve calls.
 *
 * Safety invariants (docs/safety.md; each is one test of the same name in
 * tests/reliability/test_invariants.c, run through every backend and every level, the load
 * level included where the backend plans it):
 *   pressure_within_limits: every returned pressure is finite and inside the bladder's
 *     [p_min, p_max], whatever the status.
 *   stretch_within_limits: every returned stretch (= ri / Ri) is inside
 *     [stretch_min, stretch_max], and ri is strictly below any inflation limit point's radius
 *     (at most (1 − 1e-3) of it), whatever the status.
 *   valid_fields_finite: for every status, status, raw_code, backend, level, n, commanded,
 *     uncommanded[6] (0 on the safe output), iterations (>= 0), solve_time (>= 0), achieved[6] and every bladder's ri, ro, pressure,
 *     stretch are finite; pose_error is finite when the result answers this request
 *     (REACHED, CLOSEST, and ITERATION_LIMIT / TIME_LIMIT carrying an iterate) and exactly
 *     +inf when it is the safe output; never NaN. desired[] is a copy of the input (may be
 *     NaN/Inf on INVALID_INPUT).
 *   plan_never_allocates: hp_plan's own code allocates nothing with any backend; with the
 *     realtime backend nothing at all is allocated. (Ipopt and NLopt allocate, and free,
 *     inside their own solve calls.)
 *   plan_never_prints: nothing is written to stdout or stderr, Ipopt and NLopt included.
 *   plan_never_blocks: the realtime and NLopt backends take no lock; the Ipopt backend waits
 *     only on its process-wide solver mutex. hp_plan never exits.
 *   failure_labelled_with_safe_output: a result that is not a new answer has a status other
 *     than REACHED/CLOSEST, the backend's raw_code, a text in hp_planner_error, and the SAFE
 *     OUTPUT: bit for bit the bladders and achieved pose of the last plan that returned an
 *     answer, or (after create, hp_planner_reset) the nominal answer, or (after
 *     hp_planner_set_previous) the pressures it was given, or (after
 *     hp_planner_set_previous_result) that result's bladders and pose. INVALID_INPUT, INFEASIBLE_START
 *     and SOLVER_ERROR always carry it; ITERATION_LIMIT / TIME_LIMIT carry it when the
 *     backend stopped without a usable iterate (pose_error +inf tells which).
 *   reached_means_reached: REACHED means the returned pressures, inverted by hp_iab_fk ->
 *     hp_iab_ro -> hp_contact_fk at the planner's level started from the NOMINAL pose (not
 *     from the answer), give the desired pose in every component within 1e-6 mm / degree
 *     (measured: below 1e-9); UNCOMMANDED means they give its commanded part
 *     (desired − uncommanded) back the same way. REACHED never has an uncommanded component
 *     beyond the tolerance. A correction outside the identifiable range (hp_contact.h,
 *     hp_identifiable: rotation angle >= 90 degrees for a head that is not a sphere,
 *     translation beyond the smallest semi-axis) is INVALID_INPUT, the limit named. No
 *     result carries an achieved pose outside that range either: a converged answer there is
 *     INVALID_INPUT, a budget's iterate there is replaced by the safe output.
 *   At the load level REACHED means held instead: achieved is the desired pose, the load
 *     model's generalized force there with the returned pressures vanishes (below 1e-9 N,
 *     hp_plan's load-level paragraph), and the forward model confirms the hold: its
 *     stiffness is positive definite and the forward statics started there rests within
 *     1e-6 mm / degree of it; its CLOSEST answers name their binding limits too.
 *   closest_names_binding: a CLOSEST answer has at least one bladder with binding flags
 *     (HP_BINDING_TOL_MM, the same for every backend) named in hp_planner_error; a claimed
 *     optimum with nothing binding is SOLVER_ERROR with the safe output. */
#ifndef HP_PLANNER_H
#define HP_PLANNER_H

#include "headplan/hp_common.h"
#include "headplan/hp_contact.h"
#include "headplan/hp_load.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum hp_backend {
    HP_BACKEND_REALTIME = 0, /* "realtime": direct chain, then a small bounded QP/SQP */
    HP_BACKEND_IPOPT,        /* "ipopt": reference, exact first and second derivatives */
    HP_BACKEND_NLOPT_SLSQP,  /* "nlopt-slsqp" */
    HP_BACKEND_NLOPT_COBYLA, /* "nlopt-cobyla": derivative-free */
    HP_BACKEND_COUNT_
} hp_backend;
/* "realtime", "ipopt", "nlopt-slsqp", "nlopt-cobyla"; "unknown" for other values. */
HP_API const char *hp_backend_name(hp_backend b);
/* Parses a backend name; HP_ERR_NULL for a NULL argument, HP_ERR_INVALID (out untouched)
 * for anything else. */
HP_API hp_error hp_backend_parse(const char *s, hp_backend *out);

/* Outcome of one plan. REACHED and CLOSEST carry a new answer; ITERATION_LIMIT and
 * TIME_LIMIT carry the last feasible iterate when the backend had one (inside every limit,
 * not proven closest), else the safe output; the other statuses carry the safe output (see
 * hp_plan). Whatever the status, every pressure is inside its limits. */
typedef enum hp_status {
    HP_STATUS_REACHED = 0,      /* the desired correction is met (to the tolerance) */
    HP_STATUS_CLOSEST,          /* unreachable: the closest reachable correction */
    HP_STATUS_ITERATION_LIMIT,  /* stopped by the iteration budget */
    HP_STATUS_TIME_LIMIT,       /* stopped by the time budget */
    HP_STATUS_INFEASIBLE_START, /* the limits cannot all hold (e.g. rate limits) */
    HP_STATUS_INVALID_INPUT,    /* NaN/Inf or out-of-range desired correction */
    HP_STATUS_SOLVER_ERROR,     /* the backend failed */
    HP_STATUS_UNCOMMANDED,      /* the commanded part is reached, but part of the desired
                                     correction (beyond the tolerance) lies in directions the
                                     layout cannot observe: result.uncommanded, named in
                                     hp_planner_error; never REACHED */
    HP_STATUS_COUNT_
} hp_status;
/* "reached", "closest", "iteration-limit", "time-limit", "infeasible-start",
 * "invalid-input", "solver-error", "uncommanded"; "unknown" for other values. */
HP_API const char *hp_status_name(hp_status s);

/* Why a bladder's answer sits on a limit (bit flags; several may be set). */
enum {
    HP_BIND_PRESSURE_MIN = 1u << 0,
    HP_BIND_PRESSURE_MAX = 1u << 1,
    HP_BIND_STRETCH_MIN = 1u << 2,
    HP_BIND_STRETCH_MAX = 1u << 3,
    HP_BIND_RATE_DOWN = 1u << 4,
    HP_BIND_RATE_UP = 1u << 5,
    HP_BIND_LIMIT_POINT = 1u << 6, /* the stable-branch cap below the inflation limit point */
    HP_BIND_STRESS_MAX = 1u << 7,  /* the bladder's inner hoop-stress limit (stress_max) */
    HP_BIND_INDENT_MAX = 1u << 8,  /* load level: the indentation range where the contact law
                                      is trusted (delta/ro <= HP_LOAD_INDENT_MAX, hp_load.h) */
    HP_BIND_CANNOT_PULL = 1u << 9, /* load level: the bladder carries no load (it cannot pull
                                      the head: zero force at zero gauge pressure or out of
                                      contact), and more would be needed the other way */
    HP_BIND_STABILITY = 1u << 10   /* load level: nearer poses are held inside the limits
                                      only at an unstable equilibrium (a saddle), so the
                                      answer is a stable hold found farther away. Set on the
                                      bladders that carry load in it: the holding stiffness
                                      that decides stability is the sum of their contacts'
                                      (a bladder carrying nothing adds none), so theirs are
                                      the pressures a nearer stable hold would need changed */
};
#define HP_BIND_COUNT 11
/* A bladder is reported as sitting on a limit when its outer radius is within this many mm
 * of the bound, the one threshold for every backend and level: above the solvers' stopping
 * slack at a bound (Ipopt's interior point keeps ~1e-8 of the bound, the realtime QP
 * 1e-11 mm), far below any clinical meaning. A CLOSEST answer names at least one. */
#define HP_BINDING_TOL_MM 1e-6
/* "pressure_min", "pressure_max", "stretch_min", "stretch_max", "rate_down", "rate_up",
 * "limit_point", "stress_max", "indent_max", "cannot_pull", "stability" for one flag bit;
 * "unknown" otherwise. */
HP_API const char *hp_binding_name(unsigned flag);

#define HP_DEFAULT_BACKEND HP_BACKEND_REALTIME
#define HP_DEFAULT_LEVEL HP_LEVEL_LINEAR
#define HP_DEFAULT_LEVEL_TOLERANCE 1e-5 /* [m] (0.01 mm) contact-model error auto may accept */
#define HP_DEFAULT_AUTO_TRANS 0.01      /* [m] translation auto must cover */
#define HP_DEFAULT_AUTO_ROT 0.0872664625997164788 /* [rad] (5 degrees) rotation auto covers */
#define HP_DEFAULT_TOLERANCE 1e-9                 /* pose tolerance, mm and degrees */
#define HP_DEFAULT_MAX_ITER 200
#define HP_DEFAULT_MAX_TIME 1.0 /* seconds of the plan's wall time (a monotonic clock) */
#define HP_DEFAULT_WEIGHT_MM_PER_DEG 1.0
#define HP_DEFAULT_MU 0.0
#define HP_DEFAULT_USE_RATE_LIMITS 1
#define HP_DEFAULT_WARM_START 1
#define HP_DEFAULT_LOAD_GEOMETRY HP_LEVEL_SURFACE
#define HP_DEFAULT_LOAD_TIEBREAK HP_TIE_LEAST_SQUEEZE
#define HP_DEFAULT_RESTARTS 7 /* Ipopt, NLopt SLSQP: 1/8, 2/8, ... 7/8 of the way to the target */
#define HP_DEFAULT_AUTO_POSE 0.0 /* [m, rad] every component: auto measures at the nominal pose */

/* The load level (HP_LEVEL_LOAD, docs/load.md): a desired pose -> the pressures that HOLD the
 * head there against its weight. At a pose the six equilibrium equations are linear in the
 * contact forces, and n pressures leave an (n − 6)-dimensional family that holds a
 * reachable pose, from which the tie-breaker picks one. */
typedef enum hp_load_tiebreak {
    HP_TIE_LEAST_SQUEEZE = 0, /* "least-squeeze": minimise sum_k P_k² among the stable
                                 holds (docs/load.md, "Stable holds") */
    HP_TIE_PREVIOUS,          /* "previous": minimise sum_k (P_k − P_prev,k)², likewise */
    HP_TIE_STIFFNESS,         /* "stiffness": maximise the holding stiffness's smallest
                                 eigenvalue (a smooth soft minimum of it; ipopt only) */
    HP_TIE_COUNT_
} hp_load_tiebreak;
HP_API const char *hp_load_tiebreak_name(hp_load_tiebreak t); /* "unknown" for other values */
HP_API hp_error hp_load_tiebreak_parse(const char *s, hp_load_tiebreak *out);

typedef struct hp_settings {
    hp_backend backend;       /* which solver runs when a limit binds */
    hp_level level;           /* contact fidelity (auto: resolved at create) */
    double level_tolerance;   /* [m] for HP_LEVEL_AUTO (> 0) */
    double auto_trans;        /* [m] largest translation auto must cover (>= 0) */
    double auto_rot;          /* [rad] largest rotation auto must cover (>= 0) */
    double tolerance;         /* pose tolerance in mm and degrees, in (0, 1] */
    int max_iter;             /* iteration budget per plan (> 0) */
    double max_time;          /* time budget per plan [s] (> 0) */
    double weight_mm_per_deg; /* W: 1 mm of error weighs as much as this many degrees (> 0) */
    double mu;                /* pressure regularisation (tie-breaker) [1/Pa²], >= 0;
                                 the realtime backend needs none and ignores it */
    int use_rate_limits;      /* 1: apply each bladder's rate_max from the previous plan */
    int warm_start;           /* 1: start each solve from the previous result */
    /* The load level. load.mass 0 (the default) states no load: HP_LEVEL_LOAD is refused
     * and auto chooses among the contact levels by their geometry's error bounds. With a
     * load (hp_load_spec_validate), auto compares every level's model error at auto_pose
     * (its plan's pressures rested under the load with the contact law fitted to the
     * finite-element reference; a contact level adds its geometry's bound) and takes the
     * cheapest within level_tolerance, else the smallest; once, in hp_planner_create
     * (docs/planner.md, "What create does"). */
    hp_load_spec load;              /* what the bladders carry (hp_load.h) */
    hp_level load_geometry;         /* the load level's contact geometry: linear, plane, surface */
    hp_load_tiebreak load_tiebreak; /* which holding pressures a reachable pose gets;
                                 HP_TIE_STIFFNESS needs a backend that solves it (ipopt) */
    /* A local method's closest pose depends on where it starts (docs/planner.md, Restarts).
     * Ipopt and NLopt SLSQP cannot tell a local minimum from the closest pose: after a
     * converged answer short of the target they solve again from this many deterministic
     * starts along the correction (within max_time) and keep the closest answer. 0..64; the
     * other backends ignore it. */
    int restarts;
    /* [m, rad] The correction at which auto, on settings that state a load, measures every
     * level's model error: the correction the planner will be asked for (hp_plan's desired
     * convention), since create decides before it sees one. Default: every component
     * HP_DEFAULT_AUTO_POSE, the nominal pose. Each component finite, |translation| <= 1 m
     * and |rotation| <= pi rad (as hp_plan checks a correction); where auto measures there,
     * hp_planner_create also refuses one outside the layout's identifiable range.
     * hp_scene_settings sets it to the scene's correction when the scene states a load. A
     * level that cannot reach it is measured at its closest answer (docs/planner.md). */
    double auto_pose[6];
} hp_settings;

/* Fills every field with its HP_DEFAULT_* value (load: all zero, no load). s may be NULL
 * (nothing happens). */
HP_API void hp_settings_default(hp_settings *s);
/* Checks every field (finite, in range); the first bad one is named in diag (may be NULL).
 * Returns HP_OK, HP_ERR_NULL or HP_ERR_INVALID. */
HP_API hp_error hp_settings_validate(const hp_settings *s, hp_diag *diag);

typedef struct hp_bladder_result {
    double ri, ro;    /* [m] */
    double pressure;  /* [Pa], always inside [p_min, p_max] */
    double stretch;   /* ri / Ri */
    unsigned binding; /* HP_BIND_* flags of the limits this bladder sits on */
} hp_bladder_result;

typedef struct hp_result {
    hp_status status;
    int raw_code;          /* the backend's own return code (0 for the direct chain) */
    hp_backend backend;    /* the backend that was configured */
    hp_level level;        /* the resolved contact level the answer was computed at */
    double desired[6];     /* SI, as passed */
    double achieved[6];    /* SI; pose of the returned radii at `level` (see below) */
    int commanded[6];      /* 1: the planner moves this pose component; 0: held at 0.
                                 The commanded part of desired (hp_pose_commanded_part: the
                                 pose in these components alone with the same contact
                                 distances) is what the planner aims at; achieved[] is 0 in
                                 the components not commanded */
    double uncommanded[6]; /* SI: desired − its commanded part, the part the layout cannot
                                 observe (all 0 for a rank-6 layout and on the safe output);
                                 beyond the tolerance it makes REACHED into UNCOMMANDED */
    double pose_error;     /* max over commanded i of |achieved − commanded part of
                                 desired|, mm or deg */
    int n;
    hp_bladder_result bladders[HP_MAX_BLADDERS];
    int iterations;    /* solver iterations (0: the direct chain answered) */
    double solve_time; /* [s], CLOCK_MONOTONIC, the whole hp_plan call */
} hp_result;

typedef struct hp_planner hp_planner;

/* Builds a planner for a layout (copied and validated here, hp_layout_prepare: the caller
 * may edit or free it afterwards; the planner derives its contact geometry once from its
 * own copy) and settings (NULL = defaults). Resolves HP_LEVEL_AUTO, finds what the
 * layout can tell apart and the commanded components (hp_layout_identify), maps every pressure and stretch limit to
 * bounds on the bladders' radii (clipped below any inflation limit point) and creates the
 * backend. The only call that allocates. On failure returns the error, sets *out = NULL,
 * frees everything, and puts the message in diag (may be NULL).
 * At the load level (settings level HP_LEVEL_LOAD, or auto choosing it) it builds the load
 * model once (settings load and load_geometry) and maps every pressure, stretch, stress and
 * limit-point limit to pressure bounds. It refuses (HP_ERR_INVALID, message in diag) a
 * backend that does not plan the load level ("backend: nlopt-cobyla is not available at the
 * load level ..."), the stiffness tie-breaker on a backend that does not solve it, a sphere
 * head (its contact forces all pass through its centre, so nothing holds its rotation), a
 * layout in which no bladder pushes against gravity ("no bladder pushes against gravity
 * (+z)"), and a weight larger than the bladders can carry along gravity at their largest
 * pressures. */
HP_API hp_error hp_planner_create(const hp_layout *layout, const hp_settings *settings,
                                  hp_planner **out, hp_diag *diag);

/* Plans one correction desired[6] (SI: m, rad). Always fills *result; returns HP_OK when a
 * result was produced (look at result->status), HP_ERR_NULL for NULL arguments and
 * HP_ERR_STATE for a planner that failed to build.
 *   - A correction outside the identifiable range (hp_layout_identify) is INVALID_INPUT
 *     with the limit named; otherwise the planner aims at its commanded part
 *     (hp_pose_commanded_part) and returns the rest in uncommanded[].
 *   - First the direct chain: pose -> contact distances -> radii -> pressures; when every
 *     limit holds that is the exact answer (REACHED, or UNCOMMANDED when part of the
 *     correction is not commanded; 0 iterations).
 *   - Otherwise the backend finds the closest reachable pose (CLOSEST, binding flags set).
 *   - achieved[] is the pose at the planner's level for which the returned outer radii are
 *     exactly the contact distances (the model-level round trip). Before REACHED,
 *     UNCOMMANDED or CLOSEST the planner runs the strict round trip itself (pressures ->
 *     radii -> hp_contact_fit from the nominal pose); a pose it does not recover is not
 *     identified by this layout: INVALID_INPUT (a CLOSEST answer of a warm solve is first
 *     solved once more from the nominal pose).
 *   - On INVALID_INPUT, INFEASIBLE_START or SOLVER_ERROR the result holds the SAFE OUTPUT:
 *     the previous valid answer's bladders and pose (after create or hp_planner_reset: the
 *     nominal pose's radii and pressures, clamped into the limits), so a controller that
 *     applies it holds the bladders where they are.
 * Every returned pressure is finite and inside [p_min, p_max] whatever the status.
 * Realtime backend: allocates nothing, prints nothing, takes no lock, bounded time. The text
 * of the last failure is kept (hp_planner_error). */
HP_API hp_error hp_plan(hp_planner *p, const double desired[6], hp_result *result);

/* hp_plan at the load level plans the pressures that hold the head at desired[6]. The
 * request is checked by the same code and with the same message as at the other levels.
 * REACHED: the equilibrium holds at the desired pose (the pose error is 0 by construction);
 * CLOSEST: no pressures inside the limits hold it there, and the answer is the nearest pose
 * (weighted as the settings say) at which some do that the closest-pose program finds (a
 * local method from several starts: docs/load.md), with the binding limits flagged, among
 * them indent_max (HP_LOAD_INDENT_MAX), cannot_pull (a bladder carrying nothing) and
 * stability (below).
 * "Limits" include the indentation range throughout. A REACHED or CLOSEST answer is an
 * equilibrium by two checks: Q below 1e-9 N (hp_load_eval, which also requires every
 * bladder centre outside the moved head) and, at the plane and surface geometries, the
 * Newton–Euler residual from the contact points below 1e-6 N and 1e-6 N·m; a pose found
 * that fails either is not returned (SOLVER_ERROR with the safe output: the previous
 * pressures at the previous pose). HOLD prefers a stable hold (docs/load.md, "Stable
 * holds"); every REACHED or CLOSEST answer is one (its stiffness positive definite, its
 * forward statics at rest within 1e-6 mm / degree of it). Where the hold found is only an
 * unstable equilibrium, a stable CLOSEST answer nearby is looked for (a rest of pressures on
 * the way from the previous answer, inside the rate windows, or a stable hold along
 * gravity); the nearest candidate found is the answer, its carrying bladders flagged
 * HP_BIND_STABILITY, and hp_planner_note says it is the nearest stable hold the search
 * found, not a proven nearest stable pose, and how far it is. Without one the plan is
 * SOLVER_ERROR with the safe output, the message saying so. result.level is HP_LEVEL_LOAD, commanded[] all 1,
 * uncommanded[] 0. With the realtime backend nothing is allocated. */

/* The message of the last failure: a plan whose status is not REACHED, CLOSEST or
 * UNCOMMANDED (ITERATION_LIMIT and TIME_LIMIT included: the budget ran out), or a refused
 * call. "" after an answer. Never NULL. */
HP_API const char *hp_planner_error(const hp_planner *p);

/* Why the last answer is CLOSEST or UNCOMMANDED (answers, not failures): the binding
 * limits (bladder and limit names) and the components the layout cannot command, with
 * their values; for a contact-level CLOSEST of a backend that solved from one start (NLopt
 * COBYLA, Ipopt and NLopt SLSQP with restarts 0), "; a local optimum: the BACKEND backend made
 * no restarts, and another start may end closer"; for a load-level CLOSEST answer limited
 * by stability (HP_BIND_STABILITY), "; the nearest stable hold the search found (...), not
 * a proven nearest stable pose: D mm/deg from the desired pose[, E mm/deg from the closest
 * held pose], which is held only at an unstable equilibrium". "" after REACHED and after a
 * failure. Never NULL. A CLOSEST answer's text is composed by the first call after the
 * plan (a control loop that never asks does not pay for it), so this call writes into the
 * planner: like hp_plan, not concurrently with another call on the same planner. */
HP_API const char *hp_planner_note(const hp_planner *p);

/* The message of the last plan whatever its status, for a caller that shows one text with
 * a result: the failure's (hp_planner_error) when the plan failed or was refused, else the
 * answer's (hp_planner_note: the binding limits of CLOSEST, the uncommanded components of
 * UNCOMMANDED); "" after REACHED. Never NULL. Writes into the planner as hp_planner_note
 * does: not concurrently with another call on the same planner. */
HP_API const char *hp_planner_message(const hp_planner *p);

/* Sets a backend-specific option by name, NLopt style, so that one backend's switch is not
 * a field every caller sees. Known: for Ipopt, "hessian_approximation" 0 (the exact
 * Hessian, default) or 1 (Ipopt's limited-memory quasi-Newton approximation, a benchmark
 * peer). Takes effect at the next plan. Returns HP_OK, HP_ERR_NULL, HP_ERR_STATE (planner
 * not built) or HP_ERR_INVALID (an option the configured backend does not know, or a bad
 * value; the message in hp_planner_error). Allocates nothing. */
HP_API hp_error hp_planner_set_option(hp_planner *p, const char *name, double value);

/* The resolved contact level and the planner's (validated) copy of the layout. */
HP_API hp_level hp_planner_level(const hp_planner *p);
HP_API const hp_layout *hp_planner_layout(const hp_planner *p);
/* What the planner's layout can tell apart (hp_layout_identify, computed at create): the
 * identifiable range hp_plan enforces and the commanded components. NULL for NULL. */
HP_API const hp_identifiable *hp_planner_identifiable(const hp_planner *p);

/* Why planner p plans at its level (hp_planner_level) when its settings asked for auto: the
 * error bounds auto compared against the tolerance, in one line ("auto chose surface: the
 * error bounds of linear (1.56 mm) and plane (0.969 mm) exceed model.tolerance_mm 0.01 for
 * corrections up to 5 mm, 3 deg"), into why (len bytes, truncated if short); "" when the
 * settings name a level. The text `headplan solve` prints as "level choice", batch writes
 * as the metadata record's level_choice and the Python Planner gives as level_choice.
 * Returns HP_OK; HP_ERR_NULL (p, why NULL or len 0; why gets "" when it can);
 * HP_ERR_STATE for a planner not built. Does not allocate; thread-safe on a const planner. */
HP_API hp_error hp_planner_level_choice(const hp_planner *p, char *why, size_t len);

/* The level a planner created from layout and settings (NULL: the defaults) plans at, into
 * *level, and why (the text hp_planner_level_choice gives, "" when the settings name a
 * level) into why (len bytes, may be NULL): hp_planner_create's own resolution of auto over
 * all four levels, run without building the rest of the planner, for a caller that needs
 * only the level (hp_scene_plan_level, so `headplan analyze` and `render` agree with solve).
 * Returns HP_OK, HP_ERR_NULL (layout or level NULL), or hp_planner_create's error for the
 * settings, the layout or auto's decision (diag says which). Allocates (a planner's
 * level-deciding part, freed before it returns). */
HP_API hp_error hp_planner_level_for(const hp_layout *layout, const hp_settings *settings,
                                     hp_level *level, char *why, size_t len, hp_diag *d);

/* The reach of planner p along each pose axis, as a single solve (from the nominal pose,
 * no rate limits) sees it: reach[i][1] >= 0 (reach[i][0] <= 0) is the largest correction
 * [mm or deg] along +e_i (−e_i) such that every correction up to it along that ray is
 * answered REACHED by the direct chain, under the planner's own limits (pressure, stretch,
 * hoop stress and the cap below an inflation limit point) at its level. So hp_plan of
 * 0.99·reach gives REACHED, and just beyond it a limit binds (CLOSEST), unless the reach
 * equals the search cap HP_REACH_CAP_MM / HP_REACH_CAP_DEG ("at least"). A component the planner does not command
 * (hp_identifiable.commanded) gets NAN in both entries. Returns HP_OK, HP_ERR_NULL,
 * HP_ERR_STATE (planner not built) or HP_ERR_INVALID (a planner at the load level, whose
 * reach is not defined this way). Allocates nothing; not real time (~10^4 contact
 * evaluations). */
HP_API hp_error hp_planner_reach(const hp_planner *p, double reach[6][2]);

/* Sets the pressures the bladders hold now [Pa] (n values): the rate limits of the next plan
 * start from them and they become the safe output, with the pose the forward contact
 * kinematics from the nominal pose fits to them. Each must be finite, inside its limits and
 * on the stable branch, and that fit must converge; otherwise HP_ERR_INVALID and nothing
 * changes. At the load level each must be inside its bounds (hp_planner_pressure_bounds);
 * the pose stays the previous one, and they are also the `previous` tie-breaker's target.
 * Before the first plan or this call the load level has no previous pressure and its first
 * plan is not rate-limited. */
HP_API hp_error hp_planner_set_previous(hp_planner *p, const double *pressures);

/* How far beyond the pressures its limits allow a measured pressure may lie and still be
 * taken (clamped onto the limit): this fraction of the bladder's p_max − p_min (15 Pa for
 * −5..+10 kPa), a pressure sensor's noise, far below any clinical effect. */
#define HP_MEASURED_TOL_REL 1e-3

/* The control loop's feedback: the pressures the bladders were measured to hold [Pa] (n
 * values), as hp_planner_set_previous takes them, for a reading with noise: one beyond the
 * pressures a bladder's limits allow (pressure and stretch limits) by at most
 * HP_MEASURED_TOL_REL·(p_max − p_min) is clamped onto that limit and reported in *clamped
 * (bit k for bladder k; clamped may be NULL), not refused. One farther beyond, or not
 * finite: HP_ERR_INVALID naming the bladder in hp_planner_error, and nothing changes. The
 * pressures become the next plan's rate windows' centres at once. The pose stated for them
 * is the forward contact kinematics' fit started from the previous answer's pose (a few
 * steps for a reading near the last plan; from the nominal pose when that start does not
 * converge), the radii solved from the previous answer's; both are derived when first
 * needed (a solve's start, a hold, the safe output, or the next reading when no plan used
 * this one), the same bits as at once; a plan the direct chain answers needs neither.
 * Should a reading have no stable radius or no pose there, it is dropped (the answer before
 * it stays the previous answer and the windows' centres) and the plan that needed it
 * returns INVALID_INPUT with that safe output, the reading named in hp_planner_error.
 * Allocates nothing. */
HP_API hp_error hp_planner_set_measured(hp_planner *p, const double *pressures, unsigned *clamped);

/* Makes a result the previous answer, as if hp_plan had just returned it, from its fields
 * alone: the rate limits of the next plan start from its pressures, the next solve starts
 * from its pose and inner radii (cold: the backend's own warm point, e.g. the realtime
 * multipliers, is dropped), and its bladders and pose become the safe output. So the state
 * is a function of these fields only, never of the calls before: equal results give equal
 * next plans (headplan batch relies on it; docs/batch.md). Read are n, achieved[6] and each
 * bladder's ri, ro and pressure; stretch is recomputed (ri / Ri) and nothing else is read.
 * Each must be finite and: n the layout's; achieved 0 in the components not commanded and
 * inside the identifiable range; pressure inside the bladder's limits, ri inside its
 * stretch limits (below any limit point's cap), pressure = IK(ri) to 1e-9 of the bladder's
 * pressure range (p_max − p_min) and ro = the volume law's ro of ri to 1e-9 m. Otherwise HP_ERR_INVALID, the field (and bladder)
 * named in hp_planner_error, and nothing changes. HP_ERR_NULL, HP_ERR_STATE (planner not
 * built). Allocates nothing and evaluates no contact model: 2n bladder-law evaluations,
 * none when the bladders are bit for bit those of this planner's last answer (which pass
 * the checks by construction: the same results are accepted either way). The pose is not
 * checked against ro: the caller vouches that it is the pose of those radii, as hp_plan's
 * achieved is. At the load level n, achieved (finite, inside the identifiable range) and
 * each pressure (inside its bounds, hp_planner_pressure_bounds) are read, and they become
 * the previous pressures and pose (the rate limits' origin, the `previous` tie-breaker's
 * target, the safe output). */
HP_API hp_error hp_planner_set_previous_result(hp_planner *p, const hp_result *result);

/* Replaces the per-plan rate limit [Pa] of every bladder (the layout's rate_max, one per
 * bladder: each > 0, +inf for none) for the next hp_plan calls: a caller planning rows of
 * varying intervals gives each row its own allowance (the horizon planners do). The
 * planner's own copy of the layout changes, not the caller's. HP_ERR_NULL, HP_ERR_INVALID
 * (a limit NaN, 0 or negative; nothing changes). When none is left finite the cycle bounds
 * return to the static ones at once; HP_ERR_STATE if they could not (not for a planner
 * hp_planner_create accepted). Allocates nothing. */
HP_API hp_error hp_planner_set_rate_max(hp_planner *p, const double *rate_max);

/* Forgets the previous plan: the nominal pose becomes the previous answer again. */
HP_API void hp_planner_reset(hp_planner *p);

/* The pressures [Pa] (n values) that hold the layout's nominal pose: each bladder's
 * closed-form IK at its nominal contact distance, unclamped. A trace run (headplan batch,
 * the Python module's run_trace) starts from them with hp_planner_set_previous. Returns
 * HP_OK, HP_ERR_NULL, or the bladder model's error (pressures then NaN). Allocates nothing. */
HP_API hp_error hp_planner_nominal_pressures(const hp_planner *p, double *pressures);

/* Each bladder's static pressure bounds [Pa] (n values each): the pressure, stretch, stress
 * and limit-point limits; a plan's rate limits cut them further (and at the load level the
 * indentation range, which depends on the pose). Returns HP_OK,
 * HP_ERR_NULL or HP_ERR_STATE (planner not built). Allocates nothing. */
HP_API hp_error hp_planner_pressure_bounds(const hp_planner *p, double *lo, double *hi);

/* What the load level reports beyond hp_result, for the last plan's returned pressures at
 * its returned pose (its answer, or the safe output). */
typedef struct hp_load_info {
    double force[HP_MAX_BLADDERS]; /* contact force of each bladder [N] */
    double residual_force;         /* |sum f + m g| at the answer [N] (Newton–Euler) */
    double residual_moment;        /* |net moment about the centre of mass| [N·m] */
    double rest[6];                /* the forward statics' rest of the returned pressures,
                                      started at the answer [m, rad] */
    double rest_error;             /* max |rest − achieved| in mm / degrees */
    double
        indent[HP_MAX_BLADDERS]; /* each bladder's delta/ro at the answer (hp_load_indentation) */
    hp_load_holding holding;     /* stiffness, stability and compliance of the answer: at
                                      the achieved pose with the returned pressures (not at
                                      the forward statics' rest) */
} hp_load_info;

/* The holding forces, residuals, forward-statics rest and holding stiffness of the last
 * plan's answer (before any plan: of the safe output, the planner's starting pressures at
 * the nominal pose). Returns HP_OK; HP_ERR_NULL; HP_ERR_STATE when the planner does not
 * plan at the load level or was not built; the load model's error when the answer cannot be
 * evaluated. Not real time (a forward-statics solve); allocates nothing. */
HP_API hp_error hp_planner_load_info(const hp_planner *p, hp_load_info *info);

/* The load model of a planner at the load level (its layout, carried load and contact
 * geometry), owned by the planner: valid until hp_planner_destroy, never to be passed to
 * hp_load_model_destroy. NULL for NULL p and for a planner at a contact level. */
HP_API const hp_load_model *hp_planner_load_model(const hp_planner *p);

/* Frees a planner; safe on NULL and on a half-built planner. */
HP_API void hp_planner_destroy(hp_planner *p);

#ifdef __cplusplus
}
#endif
#endif
