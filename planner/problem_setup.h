/* Internal: what hp_planner_create and hp_plan derive from a layout before any solver runs —
 * every limit as a bound on the bladders' radii, the commanded directions, unit scaling. */
#ifndef HP_PLANNER_PROBLEM_SETUP_H
#define HP_PLANNER_PROBLEM_SETUP_H

#include "planner/problem.h"

#include "common/next_double.h"
/* Scaled units of hp_problem: x[0..2] mm, x[3..5] degrees, radii mm (common/units.h). */
#include "common/units.h"
#include "iab/iab_internal.h"
/* Relative distance below an inflation limit point's inner radius that the planner keeps
 * every bladder: 1e-3 of ri leaves the pressure ~1e-6 below the peak, so hp_iab_fk can still
 * recover the radius from the pressure (dP/dri vanishes at the peak). */
#define HP_STABLE_MARGIN 1e-3

/* Knots per bladder for the rate window ends' stand-ins and root-find starts
 * (hp_static_bounds.knot_*), evenly spaced in pressure: a stand-in from a knot lies at most
 * one knot spacing inside its exact bound (the static pressure interval / 32: 338 Pa on the
 * default scene), so a window wider than two spacings (the loop benchmark's 1 kPa) always
 * has stand-ins at both ends. 33, not more: with 129 (evenly in radius) the tables cost a
 * rate-limited plan 0.1 to 0.3 us more on the loop benchmark than they saved. */
#define HP_RATE_KNOTS 33

/* Limits of one layout that do not change from plan to plan, in SI. */
typedef struct hp_static_bounds {
    double ri_lo[HP_MAX_BLADDERS], ri_hi[HP_MAX_BLADDERS];         /* [m] */
    unsigned lo_flags[HP_MAX_BLADDERS], hi_flags[HP_MAX_BLADDERS]; /* HP_BIND_* at each */
    double p_lo[HP_MAX_BLADDERS], p_hi[HP_MAX_BLADDERS];           /* IK at ri_lo, ri_hi [Pa] */
    /* The volume law at ri_lo, ri_hi [m] (NaN if it failed): a plan without rate limits
     * uses these bounds as they are, and need not evaluate it 2n times a plan. */
    double ro_lo[HP_MAX_BLADDERS], ro_hi[HP_MAX_BLADDERS];
    hp_iab_limit limit[HP_MAX_BLADDERS]; /* inflation limit points, for hp_iab_fk_limit:
                                            pressure -> radius every cycle without a scan */
    /* Each bladder validated and scaled once (hpi_iab_scaled_init), for the per-plan model
     * evaluations (hpi_setup_bladder_from_ro_s, hpi_iab_s_fk_limit_warm_ro). */
    hp_iab_s iab_s[HP_MAX_BLADDERS];
    /* hpi_setup_rate_slack of the bladder: how far inside a rate window [Pa] a pressure
     * must lie for the window's radius bound not to matter (hpi_setup_rate_clear). */
    double rate_slack[HP_MAX_BLADDERS];
    /* HP_RATE_KNOTS points over the static interval, evenly in pressure: their outer
     * radii [m] and closed-form pressures [Pa] (rising; knots_ok 0 when they could not be
     * made): where a window end's stand-in (hp_rate_lazy) comes from. */
    double knot_ro[HP_MAX_BLADDERS][HP_RATE_KNOTS], knot_p[HP_MAX_BLADDERS][HP_RATE_KNOTS];
    /* and their inner radii [m], slopes dP/dri and curvatures d²P/dri² (per scaled length):
     * the root finds' starts (a quintic Hermite interpolant of ri(P) between two knots) */
    double knot_ri[HP_MAX_BLADDERS][HP_RATE_KNOTS], knot_d[HP_MAX_BLADDERS][HP_RATE_KNOTS];
    double knot_d2[HP_MAX_BLADDERS][HP_RATE_KNOTS];
    double knot_dp[HP_MAX_BLADDERS]; /* their mean spacing [Pa] */
    int knots_ok[HP_MAX_BLADDERS];
    /* The closed form's pressure at twice Ri (0 when it failed or is not positive): the
     * window ends' root finds take it as their first probe for an upper end
     * (hpi_iab_fk_start.p_2ri) instead of evaluating it each time. */
    double p_2ri[HP_MAX_BLADDERS];
} hp_static_bounds;

/* The rate slack of a bladder whose dP/dro is at most slope [Pa/m] on its static bounds:
 * a pressure that far inside a rate window lies on a radius more than 2·HP_BINDING_TOL_MM
 * inside that window's radius bound (an outer radius more than the binding tolerance
 * inside, with room for the bound's own few ulps and the pressure's rounding, ~1e-11 Pa).
 * A non-finite slope gives +inf: never clear, the bounds are always solved. */
static inline double hpi_setup_rate_slack(double slope)
{
    return isfinite(slope) ? slope * 2e-3 * HP_BINDING_TOL_MM + 1e-6 : INFINITY;
}

/* The one home of a rate window: the pressures a plan may reach from prev [Pa] under a rate
 * limit rate [Pa], [prev − rate, prev + rate] with each end rounded inward: lo the least
 * double with fl(prev − lo) <= rate, hi the greatest with fl(hi − prev) <= rate. fl(P − prev)
 * is monotone in P, so every P in [lo, hi] keeps fabs(P − prev) <= rate as a caller computes
 * it; a plainly rounded end can lie half an ulp of prev ± rate beyond (fl(fl(prev + rate) −
 * prev) > rate), so a plan ending on it would break the limit it was given by ~1e-14 Pa.
 * prev itself is always inside. One or two ulps move each end; rate may be +inf. */
static inline void hpi_rate_window(double prev, double rate, double *lo, double *hi)
{
    double l = prev - rate, h = prev + rate;
    while (prev - l > rate) l = hpi_next_up(l);
    while (h - prev > rate) h = hpi_next_down(h);
    *lo = l;
    *hi = h;
}

/* 1 when every bladder's pressure br[k].pressure lies more than its rate slack inside its
 * rate window (pb->w_lo[k], pb->w_hi[k]: hpi_setup_rate_windows) on each side where that
 * window is tighter than the static pressure bounds: then the answer those pressures came
 * from (a direct chain inside the static bounds) is, bit for bit, the one the exact rate
 * bounds would give (no radius clamped by them, no rate limit binding within the
 * tolerance), and hp_plan need not solve them. */
int hpi_setup_rate_clear(const hp_layout *L, const hp_static_bounds *b, const hp_problem *pb,
                         const hp_bladder_result *br);

/* Every bladder's rate window around pb->p_prev (hpi_rate_window, with L's rate limits) into
 * pb->w_lo and pb->w_hi: [-inf, inf] where the rate is infinite. */
void hpi_setup_rate_windows(const hp_layout *L, hp_problem *pb);
/* hpi_setup_rate_clear's test of bladder k's pressure P against its rate window [pl, ph]
 * (hpi_rate_window's): 1 when clear. Inline: the measured start check runs it beside its
 * own test of each bladder. */
static inline int hpi_setup_rate_clear_row(const hp_static_bounds *b, int k, double pl, double ph,
                                           double P)
{
    double m = b->rate_slack[k];
    /* The same tests as hpi_setup_cycle_bounds for whether a window end is a bound. */
    return !(pl > b->p_lo[k] && !(P >= pl + m)) && !(ph < b->p_hi[k] && !(P <= ph - m));
}

/* One bladder's safe envelope: the one home of its pressure, stretch, hoop-stress and
 * limit-point limits as bounds on its inner radius, so that IK(ri_lo) >= p_min and
 * IK(ri_hi) <= p_max hold in floating point (FK roots moved inward ulp by ulp), ri_lo >=
 * stretch_min·Ri and ri_hi <= stretch_max·Ri in exact arithmetic (common/exact_prod.h), ri_hi
 * at most HP_STABLE_MARGIN below any inflation limit point and within the hoop-stress
 * limit; with the pressures there (cut to [p_min, p_max]) and the HP_BIND_* flags of what
 * set each bound (equal bounds keep both). Every planner (the kinematic levels, the load
 * level) and the benchmark lab take a bladder's limits from here. */
typedef struct hp_envelope {
    double ri_lo, ri_hi; /* [m] */
    double p_lo, p_hi;   /* [Pa] IK at ri_lo, ri_hi, inside [p_min, p_max] */
    double ro_lo, ro_hi; /* [m] the volume law there (NaN if it failed) */
    unsigned lo_flags, hi_flags;
    hp_iab_limit limit; /* the inflation limit point */
} hp_envelope;

/* Fills e for bladder B. HP_ERR_INVALID (the bladder named in d) when the limits leave no
 * stable radius. */
hp_error hpi_bladder_envelope(const hp_bladder *B, hp_envelope *e, hp_diag *d);

/* Every bladder's envelope (hpi_bladder_envelope) into b, with what the per-plan evaluations
 * keep (the validated model, the rate slack). Errors name the bladder. */
hp_error hpi_setup_static_bounds(const hp_layout *L, hp_static_bounds *b, hp_diag *d);

/* One plan's bounds: the static ones intersected with the rate limits around p_prev (when
 * use_rate), written into pb (mm) with the HP_BIND_* flags of each bound. Allocates nothing.
 * HP_ERR_INVALID with the bladder named when a bladder's interval is empty. */
hp_error hpi_setup_cycle_bounds(const hp_layout *L, const hp_static_bounds *b, const double *p_prev,
                                int use_rate, hp_problem *pb, unsigned *lo_flags,
                                unsigned *hi_flags, hp_diag *d);

/* The last radius bound solved for each end of each bladder's rate window, keyed by the
 * window end's pressure p: the same pressure, bit for bit, gives the same bound r and outer
 * radius ro without a solve (a plan holding a closest answer under rate limits sets the
 * same windows cycle after cycle). Another pressure's root find starts at the knots'
 * interpolant (hpi_setup_knot_guess), or, where the knots give none, at r with the pressure
 * there (p_at, the closed form's bits) and the slope d (per scaled length) of the last
 * Newton step, no evaluation. p_at also places the end's stand-in. Zeroed: empty. */
typedef struct hp_rate_end {
    double p, r, ro, p_at, d;
    int ok;
} hp_rate_end;

/* A start for the root find of pressure pw [Pa] on bladder k of b: the inner radius [m] of
 * the quintic Hermite interpolant of ri(P) through the two knots around pw (their radii,
 * slopes and curvatures). NAN when pw lies outside the knots or they failed. Only a start:
 * the root is the FK's whatever it is (tests/planner/test_rate_knots.c measures how near). */
double hpi_setup_knot_guess(const hp_static_bounds *b, int k, double pw);

typedef struct hp_rate_memo {
    hp_rate_end down[HP_MAX_BLADDERS], up[HP_MAX_BLADDERS];
} hp_rate_memo;

/* hpi_setup_cycle_bounds with a memo (may be NULL) read and filled: the same bounds, bits
 * and errors. */
hp_error hpi_setup_cycle_bounds_memo(const hp_layout *L, const hp_static_bounds *b,
                                     const double *p_prev, int use_rate, hp_rate_memo *memo,
                                     hp_problem *pb, unsigned *lo_flags, unsigned *hi_flags,
                                     hp_diag *d);

/* The stand-ins (hp_rate_lazy) the set-up's short ways (both ends of a bladder stand-ins, or one
 * with the other end beyond a static limit) made, each with the closed-form pressure at its point:
 * a later set-up takes one again, without a knot looked up, for a window end it still serves (its
 * pressure beyond the new end by the rate slack and within a knot spacing of that, as a new
 * stand-in would lie). A reading fed back every cycle moves each window by the sensor's noise, a
 * few Pa. Where a memo bound would also serve, the kept stand-in is taken, up to a knot spacing
 * farther inside: the same answers, perhaps an end resolved more. The planner owns it; zeroed:
 * empty. */
typedef struct hp_rate_stand {
    /* [0] the lower end's, [1] the upper end's: a point's pressure [Pa], its outer radius [m] */
    double p[2][HP_MAX_BLADDERS], ro[2][HP_MAX_BLADDERS];
    unsigned char ok[2][HP_MAX_BLADDERS]; /* 1: kept */
} hp_rate_stand;

/* One plan's bounds with the rate windows' ends not yet solved (lazy): each such end's
 * outer-radius bound in pb (ro_lo, ro_hi) is a stand-in strictly inside the exact bound, by
 * at least the radius of the rate slack (a knot of hp_static_bounds or the last bound solved
 * for that end, whose pressure lies beyond the window end, or such a point kept from an
 * earlier set-up, hp_rate_stand), and its inner-radius
 * bounds (ri_lo, ri_hi) are the static ones, outside the exact bound. So a comparison of a
 * radius that lies strictly inside the stand-in decides as the exact bound would, and one
 * that does not is made only after hpi_setup_rate_resolve has put the exact bound (the bits
 * of hpi_setup_cycle_bounds_memo) in its place. The plan owns it (hp_planner); a backend
 * that resolves ends itself (HP_BACKEND_LAZY_RATE) finds it in hp_problem.lazy. */
typedef struct hp_rate_lazy {
    const hp_layout *L;
    const hp_static_bounds *b;
    hp_rate_memo *memo;
    hp_rate_stand *stand; /* may be NULL */
    hp_problem *pb;
    unsigned *lo_flags, *hi_flags;
    /* 1: a stand-in, not solved. The windows are pb's (w_lo, w_hi: hpi_setup_rate_windows). */
    unsigned char lo[HP_MAX_BLADDERS], hi[HP_MAX_BLADDERS];
    int failed; /* a resolved end had no stable radius: the plan fails as the eager one */
} hp_rate_lazy;

/* Sets z's bounds into z->pb for its rate windows (pb->w_lo, pb->w_hi, which the caller has
 * worked out: hpi_setup_rate_windows) with every rate window end a stand-in (a
 * bladder whose stand-ins leave a window of outer radii narrower than 2·HP_BINDING_TOL_MM,
 * or for which no stand-in can be made, gets its exact bounds at once). z's pointers must be set.
 * Errors as hpi_setup_cycle_bounds_memo. */
hp_error hpi_setup_cycle_bounds_lazy(hp_rate_lazy *z, hp_diag *d);

/* Puts the exact bound of bladder k's window ends in ends (1: the lower, 2: the upper, 3:
 * both) in place of their stand-ins (the memo's bits when it holds the end; both ends
 * when the other's stand-in would leave too narrow a window). 0 (and z->failed set) when
 * a window end has no stable radius. */
int hpi_setup_rate_resolve(hp_rate_lazy *z, int k, unsigned ends);

/* Resolves every stand-in end of the bladders k (n of them) that the radius rho_mm[k] does
 * not lie more than margin_mm inside; a non-finite rho resolves nothing (every comparison
 * of it fails whatever the bound). 0 when a resolve failed. z may be NULL (no-op). */
int hpi_setup_rate_touch(hp_rate_lazy *z, const double *rho_mm, int n, double margin_mm);

/* 1 when some bladder's outer radius rho_mm[k] [mm] lies outside its exact window for
 * certain, by more than margin_mm beyond an end still a stand-in: beyond the knot whose
 * pressure brackets that end's from outside (the pressure rises with the radius, so the
 * exact bound lies inside that knot). Then "is every radius inside its bounds" is answered
 * no with the exact bounds as with the stand-ins, whatever ends are left unsolved. 0 when
 * z is NULL, for a NaN radius, and where the knots bracket nothing. No model evaluation. */
int hpi_setup_rate_surely_out(const hp_rate_lazy *z, const double *rho_mm, int n, double margin_mm);

/* 1 when some bladder's outer radius rho_mm[k] [mm] (L->n of them) lies beyond an end of
 * its rate window around p_prev[k] for certain, by more than margin_mm beyond the knot that
 * brackets that end from outside, where the end is tighter than the static pressure bound:
 * before any bound of the plan is set, from the knots alone (no model evaluation, no window
 * worked out). Then that radius's pressure lies beyond the window's end, so the answer's,
 * clamped into the window, lies on it (not its rate slack inside), and hpi_setup_rate_clear
 * says 0 for that answer. 0 for a NaN radius and where the knots bracket nothing; then bit
 * k of *near is set for each bladder whose radius lies beyond the knot inside an end (its
 * pressure within a knot spacing of the end, or beyond it). It reads p_prev and the rate
 * as given and does not look at use_rate_limits: the caller asks only when the plan's rate
 * windows apply (planner/plan_state.c: under rate_deferred). */
int hpi_setup_rate_surely_left(const hp_layout *L, const hp_static_bounds *b, const double *p_prev,
                               const double *rho_mm, double margin_mm, unsigned *near);

/* Whether any end of z is still a stand-in. */
int hpi_setup_rate_pending(const hp_rate_lazy *z);

/* TEST-ONLY hooks (not installed, no public header; inert until a test sets them):
 * the number of rate-limit window ends solved into radius bounds in this process so far
 * (an atomic count), and whether hp_plan defers the rate bounds until a plan needs them
 * (1, the default) or solves them first (0). */
unsigned long hpi_test_rate_bound_solves(void);
/* The closed-form pressure evaluations those solves spent (root find and nudge). */
unsigned long hpi_test_rate_bound_evals(void);
/* The plans whose bounds were set up with stand-ins (hpi_setup_cycle_bounds_lazy). */
unsigned long hpi_test_rate_lazy_setups(void);
/* The resolves (hpi_setup_rate_resolve calls that made an end exact) and the window ends
 * they derived again (solved, taken from the memo or a stand-in made), ends solved included. */
unsigned long hpi_test_rate_resolves(void);
unsigned long hpi_test_rate_rederived(void);
/* The rate windows worked out by hpi_setup_rate_windows (one a bladder; every rate-limited
 * plan, eager or lazy, and a reading dropped in a plan), which a plan's start check, its lazy
 * set-up, resolves, hpi_setup_rate_surely_out and its answer use. */
unsigned long hpi_test_rate_windows(void);
/* The stand-ins made anew by the set-up's short ways (both ends stand-ins, or one beside a
 * static limit), not taken from hp_rate_lazy.stand. */
unsigned long hpi_test_rate_stands_new(void);
void hpi_test_rate_lazy(int on);
int hpi_setup_rate_lazy(void);

/* The planner's contact geometry (of hp_planner_layout(p)), derived once at create: for
 * the horizon planners that run on its layout. */
const hp_geom *hpi_planner_geom(const hp_planner *p);

/* Scaled pose (mm, deg) -> SI (m, rad), by division (the bits every evaluation of the
 * planner's pose has always had). */
void hpi_setup_pose_from_scaled(const double x[6], double xi[6]);

/* Contact distances and Jacobian in scaled units: rho_mm[n], J_s[n×6] (mm per mm, mm per
 * degree); J_s may be NULL. x is scaled (mm, deg). Allocates nothing. */
hp_error hpi_setup_contact_scaled(const hp_layout *L, const hp_geom *G, hp_level level,
                                  const double x[6], double *rho_mm, double *J_s);
/* hpi_setup_contact_scaled with one warm state per bladder for the surface level's distances
 * (warm[0..n-1], see hpi_kin_head_distance_warm; NULL: cold): the same answers to rounding,
 * fewer root-find steps where the pose moved little since warm was written. */
hp_error hpi_setup_contact_scaled_warm(const hp_layout *L, const hp_geom *G, hp_level level,
                                       const double x[6], hp_kin_dist_warm *warm, double *rho_mm,
                                       double *J_s);
/* Whether every contact distance at scaled pose x lies inside [lo_mm[k], hi_mm[k]] (mm):
 * *inside 1 with rho_mm[0..n-1] the distances (mm, the bits hpi_setup_contact_scaled gives),
 * else *inside 0 (rho_mm partly written). The evaluation stops at the first bladder
 * outside, so a target beyond reach costs a fraction of a full evaluation. J_si (may be
 * NULL): when inside, the SI Jacobian there (n×6, per m and per rad). */
hp_error hpi_setup_contact_inside(const hp_layout *L, const hp_geom *G, hp_level level,
                                  const double x[6], const double *lo_mm, const double *hi_mm,
                                  double *rho_mm, double *J_si, int *inside);

/* The one home of the clamp of a bladder's pressure P into [p_lo, p_hi] (a plan's limits
 * and rate window): comparisons, not fmin/fmax, so a P of -0.0 at a bound of 0.0 keeps its
 * bits. */
static inline double hpi_setup_pressure_in(double P, double p_lo, double p_hi)
{
    if (P < p_lo) P = p_lo;
    if (P > p_hi) P = p_hi;
    return P;
}

/* A bladder's state from its outer radius ro [m]: ri, pressure (clamped into [p_lo, p_hi]
 * after the model is evaluated), stretch. HP_ERR_DOMAIN/INVALID on a non-finite result. */
hp_error hpi_setup_bladder_from_ro(const hp_bladder *B, double ro, double ri_lo, double ri_hi,
                                   double p_lo, double p_hi, hp_bladder_result *out, int *clamped);
/* The same with B's model already validated into s (hp_static_bounds.iab_s): the same codes
 * and bits, without validating the bladder again. */
hp_error hpi_setup_bladder_from_ro_s(const hp_bladder *B, const hp_iab_s *s, double ro,
                                     double ri_lo, double ri_hi, double p_lo, double p_hi,
                                     hp_bladder_result *out, int *clamped);
/* Its two halves, for a caller that runs each over every bladder in turn (several
 * bladders' chains of divisions and roots then overlap): the inner radius ri of ro, moved
 * into [ri_lo, ri_hi] (*clamped 1 when moved; HP_ERR_INVALID for a non-finite ro), then
 * the state from ro, that ri and that flag. The same codes and bits as the whole. */
hp_error hpi_setup_ri_from_ro_s(const hp_iab_s *s, double ro, double ri_lo, double ri_hi,
                                double *ri, int *clamped);
hp_error hpi_setup_bladder_from_ri_s(const hp_bladder *B, const hp_iab_s *s, double ro, double ri,
                                     int clamped, double p_lo, double p_hi, hp_bladder_result *out);

#endif
