/* Internal: the planner object and the pieces its files share. planner.c holds the
 * lifecycle (create, reset, set_previous, destroy, accessors), level_choice.c the level's
 * resolution at create, plan.c the plan pipeline (validate -> direct chain -> solve ->
 * accept -> label) and its messages, plan_state.c the state between plans (scaling, the
 * answer of a pose, the previous answer), plan_text.c the round trip's message, text.c the
 * allocation-free message builders, backends.c the backend table, load_level.c the load
 * level (hp_plan hands a planner at HP_LEVEL_LOAD to it). */
#ifndef HP_PLANNER_INTERNAL_H
#define HP_PLANNER_INTERNAL_H

#include "planner/backend_common.h"
#include "planner/clock.h"
#include "planner/load_level.h"
#include "planner/text.h"
#include "planner/plan_range.h"
#include "planner/problem_setup.h"
#include "kinematics/fit_internal.h"

/* A reached pose counts as identified when forward contact kinematics started from the
 * nominal pose recovers it to HP_IDENT_FK_TOL (mm and degrees): far above the fit's own
 * precision on a well-posed layout (~1e-12), far below the distance of any second fit seen
 * (0.8 degrees on the near-degenerate layout at the plane level). A pivot far away makes
 * the pose coordinates themselves ill-conditioned (1 km: ~1e-6 mm/deg of rounding), so a
 * fit that meets the contact distances to HP_IDENT_FIT_MM and lies within HP_IDENT_SAME of
 * the pose is the same pose: another pose with the same distances would be a symmetric
 * copy (>= 90 degrees away) or a second fit (0.8 degrees). */
#define HP_IDENT_FK_TOL 1e-7
#define HP_IDENT_FIT_MM                                                                            \
    1e-8 /* 100x the rounding of distances computed with a 1 km lever;
                                 the second fit above misses them by 5.6e-5 mm */
#define HP_IDENT_SAME 1e-3
/* Largest RMS contact residual [mm] of clamped radii that still counts as holding a pose:
 * 100× above the solvers' own contact slop (1e-9 mm tolerance, bounds kept exactly), far
 * below anything physical. */
#define HP_CLAMP_RESID_MM 1e-6

/* One plan's bounds set with stand-ins (hp_rate_lazy) as the plan left them: the bounds of
 * hp_problem, their HP_BIND_* flags, and which ends are still stand-ins. */
typedef struct hp_rate_kept {
    double ri_lo[HP_MAX_BLADDERS], ri_hi[HP_MAX_BLADDERS], ro_lo[HP_MAX_BLADDERS],
        ro_hi[HP_MAX_BLADDERS], ri_lo_si[HP_MAX_BLADDERS], ri_hi_si[HP_MAX_BLADDERS];
    unsigned lo_flags[HP_MAX_BLADDERS], hi_flags[HP_MAX_BLADDERS];
    unsigned char lo[HP_MAX_BLADDERS], hi[HP_MAX_BLADDERS];
} hp_rate_kept;

/* The rows of the last direct answer a plan discarded, or kept at the end of a walk the rate
 * windows held back (hpi_plan_answer_from_pose, hpi_plan_answer_keep): each bladder's state from
 * its outer radius rho[k] [mm] with the inner radius moved into [ri_lo[k], ri_hi[k]] [m] (the key,
 * compared bit for bit), before a pressure window clamps the pressure. A function of the key and
 * of the bladders' models alone, both fixed for the planner's life: the same key gives the same
 * rows, so rows found here are the rows an evaluation would give. Such an answer comes again: a
 * rate-limited plan whose direct answer at the target comes near a rate window's end discards it
 * and solves, and the next plan toward the same target tests the same direct answer against its
 * windows. pending: the last direct answer's pressures before the window and clamp flags are in
 * res and clamped (ok 0) until kept. Zeroed: empty. */
typedef struct hp_answer_memo {
    int ok, pending;
    double rho[HP_MAX_BLADDERS], ri_lo[HP_MAX_BLADDERS], ri_hi[HP_MAX_BLADDERS];
    hp_bladder_result res[HP_MAX_BLADDERS]; /* pressure not clamped into a window; binding 0 */
    unsigned char clamped[HP_MAX_BLADDERS];
} hp_answer_memo;

struct hp_planner {
    hp_layout L; /* private, validated copy */
    hp_geom G;   /* its contact geometry, derived once at create */
    hp_settings s;
    hp_level level;
    hp_identifiable id; /* what the layout can tell apart (hp_layout_identify) */
    int commanded[6];   /* = id.commanded */
    hp_static_bounds sb;
    hp_rate_memo rate_memo;   /* the last rate bounds solved (plan.c), keyed by pressure */
    hp_rate_lazy rate_lazy;   /* this plan's window ends not yet solved (pb.lazy points here) */
    hp_rate_stand rate_stand; /* the stand-ins of the last set-ups (problem_setup.h) */
    hp_problem pb;
    unsigned lo_flags[HP_MAX_BLADDERS], hi_flags[HP_MAX_BLADDERS];
    const hp_backend_ops *ops;
    void *bstate;
    int built;
    hp_result nominal; /* safe output after create / reset */
    hp_result prev;    /* last valid answer: the safe output */
    double x_prev[HP_PROBLEM_NX_MAX];
    double x_work[HP_PROBLEM_NX_MAX];
    /* The direct chain's Jacobian at its answer (SI, n×6; curved levels): the strict round
     * trip's certificate starts from it. Scratch of one plan, not zeroed per plan. */
    double chain_J[HP_MAX_BLADDERS * 6];
    char err[HP_DIAG_MAX];  /* the last failure (hp_planner_error) */
    char note[HP_DIAG_MAX]; /* why the last answer is not REACHED (hp_planner_note) */
    /* A CLOSEST answer's note ("closest: binding ...") is written when it is first asked
     * for (hp_planner_note), from these flags: a control loop that never reads it does not
     * pay for the text (about 1 % of a plan). */
    int note_pending;
    /* The CLOSEST answer is a backend's one-start local optimum (HP_BACKEND_ONE_START and
     * no restarts): its note says so after the binding limits. */
    int note_local;
    /* No rate limit applies (use_rate_limits off, or no bladder has a finite rate_max): the
     * cycle's bounds do not depend on the previous answer and stay as create set them. */
    int rate_free;
    unsigned note_binding[HP_MAX_BLADDERS];
    hp_diag diag;
    int nom_ok;       /* nom is valid (else fits evaluate it themselves) */
    int fk_free[6];   /* hp_contact_fk's free components: 6, or 3 for a sphere */
    int prev_checked; /* prev's bladders pass hp_planner_set_previous_result's
                                    checks by construction (an answer of hp_plan, the
                                    nominal answer, or a result those checks passed) */
    /* The load level (level HP_LEVEL_LOAD; NULL at the contact levels): hp_plan and the
     * previous-answer calls are its. */
    hp_load_level *load;
    /* Why auto chose the level (hp_planner_level_choice), written once by create; "" when
     * the settings name the level. */
    char level_why[HP_DIAG_MAX];
    /* The linear level's fit of a measured reading's outer radii (set_measured), its normal
     * matrix factored at the first reading; lin_fit_tried: prepared (or refused) once. */
    int lin_fit_tried;
    hp_kin_linear_fit lin_fit;
    /* A reading of set_measured whose radii and pose are not derived yet (measured.c):
     * its pressures, already the rate windows' centres (pb.p_prev), while prev still holds
     * the answer they are derived from. */
    int meas_pending;
    double meas_P[HP_MAX_BLADDERS];
    /* The rate windows of the last plan that set rate bounds (rate_last_ok: one did), by
     * their centres and limits, so that a plan with the same windows takes that plan's
     * bounds as it left them (plan.c, rate_bounds). */
    int rate_last_ok;
    double rate_last_P[HP_MAX_BLADDERS];
    double rate_last_rate[HP_MAX_BLADDERS];
    /* rate_live: this plan set its bounds with stand-ins (p->rate_lazy); rate_kept_ok: the
     * bounds rate_kept holds are those the last such plan left, every end it resolved exact,
     * the others its stand-ins (plan.c, keep_rate_bounds). */
    int rate_live, rate_kept_ok;
    hp_rate_kept rate_kept;
    /* The static bounds as hpi_setup_cycle_bounds puts them without windows (static_kept_ok:
     * taken), for every rate-limited plan's start (plan.c, validate); the layout and its
     * static bounds do not change after create. */
    int static_kept_ok;
    hp_rate_kept static_kept;
    hp_answer_memo ans_memo; /* plan_state.c: rows of the last discarded direct answer */
    /* The contact model at the nominal pose (fit starts). Last, and its warm states last
     * in it: when they grew from 64 to 512 bytes in the middle, padding main's structs the
     * same way (a placebo, no code change) made plans 2.5 % slower at every level, a
     * placement effect; here the fields before it keep their offsets. */
    hp_kin_fit_start nom;
};

/* What a plan knows at its answer for the round trip's certificate: the scaled point x,
 * the distances there [mm], and (may be NULL) their Jacobian (SI) with a bound J_err on
 * its error (hp_kin_fit_near's anchor_J_err: 0 for the direct chain's own). */
typedef struct hp_plan_anchor {
    const double *x, *rho_mm, *J;
    double J_err;
} hp_plan_anchor;
/* Where a round trip's fit from the nominal pose ended, for its verdict and message. */
typedef struct hp_plan_trip {
    double worst;  /* mm/deg from the answer's pose to end (inf when the fit failed) */
    double end[6]; /* the fit's last pose (SI) */
    /* Only when the round trip fails: the largest difference [mm] between the contact
     * distances evaluated afresh at end and the answer's outer radii (inf when the fit or
     * the evaluation failed). At most HP_IDENT_NAME_MM: end is another pose that holds these
     * pressures; above: the fit stalled there. */
    double gap_mm;
} hp_plan_trip;
/* A pose whose contact distances match an answer's to this [mm] holds its pressures as far as
 * the planner can tell (its binding threshold HP_BINDING_TOL_MM and its clamp residual
 * HP_CLAMP_RESID_MM are the same 1e-6 mm); another pose with the same distances matches
 * them to rounding (~1e-12 mm), a stalled fit misses them by 1e-5..1 mm. */
#define HP_IDENT_NAME_MM 1e-6
/* The strict round trip of r's pressures (plan.c): 1 when the fit from the nominal pose ends
 * at achieved (SI); t says where it ended. Allocates nothing. */
int hpi_plan_round_trip(const hp_planner *p, const hp_result *r, const double achieved[6],
                        const hp_plan_anchor *anchor, hp_plan_trip *t);
/* The text of a failed round trip t into buf (hpi_text_add): "forward contact kinematics from
 * the nominal pose finds another pose, (x, y, z) mm (pitch, roll, yaw) deg, D mm/deg away,
 * whose contact distances match ..." when its end really holds the answer's distances
 * (HP_IDENT_NAME_MM), else that the fit stalled (or did not converge) and how far its
 * distances are from the answer's. */
void hpi_plan_trip_text(char *buf, const hp_plan_trip *t);
/* hp_contact_fit of the outer radii ro in the components free_ from the nominal pose,
 * taking its first model evaluation from p->nom: the same steps, one evaluation fewer.
 * near (may be NULL): hpi_kin_fit's early stop at an expected pose. */
hp_error hpi_plan_fit_from_nominal(const hp_planner *p, const double *ro, const int free_[6],
                                   const hp_kin_fit_near *near, double xi[6], double *residual_rms);

/* One plan of desired[6] (SI) at contact level `level`, as `headplan solve` makes it: a
 * planner of its own from layout and settings s with that level, from rest (no rate limits,
 * no warm start), into *r. HP_OK when hp_plan produced a result, else create's error.
 * planner.c hands it to hpi_planner_resolve_level, so that level_choice.c plans with it
 * without depending on the file that calls it. */
typedef hp_error (*hpi_plan_at_fn)(const hp_layout *layout, const hp_settings *s, hp_level level,
                                   const double desired[6], hp_result *r);

/* Resolves p->s.level into p->level once, over all four levels (level_choice.c), and writes
 * why into p->level_why. For the load level (asked for, or chosen by auto) p->load gets its
 * model, built from layout (the caller's) with p->s. Needs p->L, p->G. Auto away from the
 * nominal pose plans settings.auto_pose at each contact level with plan_at. */
hp_error hpi_planner_resolve_level(hp_planner *p, const hp_layout *layout, hpi_plan_at_fn plan_at,
                                   hp_diag *d);

/* The backend of an enum value (backends.c); NULL for a value with no backend. */
const hp_backend_ops *hpi_backend_table(hp_backend b);

/* Pose scaling of hp_problem: SI -> mm and degrees, and back. */
void hpi_plan_to_scaled(const double xi[6], double x[6]);
void hpi_plan_from_scaled(const double x[6], double xi[6]);

/* Fills res from a scaled pose x: contact distances at the planner's level (rho_known:
 * already evaluated at x [mm], else NULL), radii, pressures (clamped into this cycle's
 * limits), binding flags and achieved pose. Returns 0 when something was not finite.
 * clamp_mm receives the largest radius correction. direct: the direct chain's answer
 * under deferred rate bounds, which the plan may discard: its rows come from p->ans_memo
 * when it holds them (the same bits as evaluating them), else are evaluated and held
 * pending for hpi_plan_answer_keep. */
int hpi_plan_answer_from_pose(hp_planner *p, const double x[6], const double *rho_known, int direct,
                              hp_result *res, double *clamp_mm);
/* 1 when the direct answer at distances rho [mm] (deferred rate bounds: the static ones) is
 * one the plan discards for certain (hpi_setup_rate_clear would say 0 for it): a radius
 * beyond a rate window's end by the knots (hpi_setup_rate_surely_left), or the row of a
 * radius within a knot spacing of an end, evaluated alone, with its pressure not clear of
 * that end. 0 says nothing. Builds no answer and writes no memo. */
int hpi_plan_direct_left(hp_planner *p, const double *rho);
/* Keeps the rows of the direct answer res at distances rho [mm] that the plan discards, or keeps
 * where a walk the rate windows held back ends (the last hpi_plan_answer_from_pose with direct,
 * evaluated, not from the memo; else nothing), under the radius bounds it was answered with (call
 * it before they change). */
void hpi_plan_answer_keep(hp_planner *p, const double *rho, const hp_result *res);

/* TEST-ONLY count (inert): the answer rows (a bladder's inner radius and pressure from its
 * outer radius) hpi_plan_answer_from_pose evaluated in this process so far, rows it took
 * from the planner's memo of earlier answers not counted; and a hook that turns that memo
 * off (0) or on (1, the default), so a test can compare the two bit for bit. */
unsigned long hpi_test_answer_rows(void);
void hpi_test_answer_memo(int on);

/* TEST-ONLY hook (inert at 0, the default): whether a rate-limited plan looks for a direct
 * answer its windows discard for certain (hpi_plan_direct_left): 0 when the gate says so
 * (after an answer the windows held back or toward a far target), 1 always, -1 never. The
 * look saves work and changes no answer; a test compares the three bit for bit. */
void hpi_test_plan_look(int mode);

/* Makes r the previous answer: the safe output, the rate limits' origin and the next
 * solve's start point (a pending reading is forgotten). */
void hpi_plan_set_previous_answer(hp_planner *p, const hp_result *r);
/* The previous answer from pressures P inside [p_lo, p_hi] (measured.c): radii by the FK
 * (started at the previous answer's radii when warm), the pose by a fit from the nominal
 * pose (cold) or from the previous answer's pose (warm; the nominal one when that does not
 * converge). who starts the message of a refusal. HP_OK or HP_ERR_INVALID. */
hp_error hpi_plan_previous_from(hp_planner *p, const double *P, int warm, const char *who);
/* Derives a pending reading of set_measured (meas_pending) into the previous answer, as
 * hpi_plan_previous_from(p, meas_P, 1, "set_measured"); nothing when none is pending.
 * Called by whatever reads the previous answer's radii or pose. When the reading has no
 * stable radius or no pose, it is dropped (the previous answer and the rate windows'
 * centres are those before it) and p->err says why, after what it held ("; " between).
 * HP_OK or HP_ERR_INVALID. */
hp_error hpi_plan_measured_derive(hp_planner *p);
/* 1 when a solve may start from the previous answer (x_prev) without deriving a pending
 * reading: none is pending, or every bladder's previous pressure lies inside its limits and
 * inside the reading's rate window by the slack at which the window's radius bound does not
 * matter (hpi_setup_rate_clear): a feasible start, found in pressure space without an FK.
 * A start is only a start: the answer is verified as every answer is. */
int hpi_plan_measured_start_ok(const hp_planner *p);
/* TEST-ONLY count (inert): the closed-form pressure evaluations the bladder FK spent in
 * hpi_plan_previous_from in this process so far. */
unsigned long hpi_test_measured_fk_evals(void);
/* TEST-ONLY hook (inert unless a test sets it): while on, hpi_plan_measured_derive finds no
 * radius or pose for a pending reading (as a reading with none), so the drop is tested. */
void hpi_test_measured_refuse(int on);

/* Writes a pending CLOSEST note (note_pending) into p->note; nothing otherwise. */
void hpi_plan_note_flush(hp_planner *p);

#endif
