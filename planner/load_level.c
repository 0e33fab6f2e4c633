/* The load level of hp_planner (load_level.h): bounds, the layout's ability to carry the
 * load, and the plan (HOLD at the desired pose; when unreachable POSE then HOLD), with the
 * details (forces, residuals, the forward statics' rest, the holding) on request. */
#include "planner/load_level.h"
#include "common/units.h"
#include "kinematics/contact_law.h"
#include "kinematics/kin_geom.h"
#include "planner/clock.h"
#include "planner/load_stable.h"
#include "planner/load_walk.h"
#include "planner/plan_range.h"
#include "planner/problem_setup.h"
#include "planner/text.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* Pressure bounds of bladder k: the pressures of its envelope (hpi_bladder_envelope, the one
 * home of the pressure, stretch, stress and limit-point limits, as the kinematic levels),
 * and the radii the answer is kept inside. Each bound remembers which limits set it. */
static hp_error bladder_bounds(hp_load_level *p, int k, hp_diag *diag)
{
    hp_envelope env;
    hp_error e = hpi_bladder_envelope(&p->M.layout.bladders[k], &env, diag);
    if (e != HP_OK) return e;
    p->lo[k] = env.p_lo;
    p->lo_bind[k] = env.lo_flags;
    p->hi[k] = env.p_hi;
    p->hi_bind[k] = env.hi_flags;
    p->ri_lo[k] = env.ri_lo;
    p->ri_hi[k] = env.ri_hi;
    return HP_OK;
}

static const char *direction_words(const double v[3], char *buf, size_t len)
{
    static const char *const names[3] = {"x", "y", "z"};
    int d = 0;
    for (int i = 1; i < 3; ++i)
        if (fabs(v[i]) > fabs(v[d])) d = i;
    snprintf(buf, len, "%c%s", v[d] >= 0 ? '+' : '-', names[d]);
    return buf;
}

/* Can the bladders push against gravity at all, and hard enough? Each bladder pushes the
 * head along u_k = −n_k (into the head) with at most p_hi·pi·(ro² − rho²) at ro = ro(p_hi)
 * and rho >= (1 − HP_LOAD_INDENT_MAX)·ro (the indentation range where the contact law is
 * trusted), so the support along −g is at most sum_k max(0, −ĝ·u_k)·that. */
static hp_error check_carry(hp_load_level *p, hp_diag *diag)
{
    const hp_load_model *M = &p->M;
    double g = 0.0, up[3];
    for (int a = 0; a < 3; ++a) g += M->spec.gravity[a] * M->spec.gravity[a];
    g = sqrt(g);
    for (int a = 0; a < 3; ++a) up[a] = -M->spec.gravity[a] / g;
    double cap = 0.0;
    int any = 0;
    for (int k = 0; k < M->layout.n; ++k) {
        const double *n = p->M.geom.normal[k];
        double s = -(n[0] * up[0] + n[1] * up[1] + n[2] * up[2]);
        if (s <= 1e-9 || p->hi[k] <= 0) continue;
        any = 1;
        double ro;
        hp_claw c;
        if (hp_load_radius(M, k, p->hi[k], &ro, NULL) == HP_OK) {
            hpi_load_claw(M, k, p->hi[k], ro, (1.0 - HP_LOAD_INDENT_MAX) * ro, &c);
            cap += s * c.F;
        }
    }
    char w[8];
    if (!any)
        return hp_diag_set(diag, HP_ERR_INVALID,
                           "load: no bladder pushes against gravity (the head needs support "
                           "along %s)",
                           direction_words(up, w, sizeof w));
    double weight = M->spec.mass * g;
    if (!(cap >= weight))
        return hp_diag_set(diag, HP_ERR_INVALID,
                           "load: the bladders can carry at most %.4g N along %s at their "
                           "largest pressures (indented at most %g of their radius, "
                           "indent_max); the load weighs %.4g N",
                           cap, direction_words(up, w, sizeof w), HP_LOAD_INDENT_MAX, weight);
    return HP_OK;
}

hp_error hpi_load_level_model(hp_load_level *p, const hp_layout *L, const hp_settings *s,
                              hp_diag *diag)
{
    return hpi_load_model_setup(&p->M, L, &s->load, s->load_geometry, diag);
}

hp_error hpi_load_level_build(hp_load_level *p, const hp_settings *s, const hp_backend_ops *ops,
                              char *err, hp_diag *diag)
{
    if (p->M.layout.head.shape == HP_HEAD_SPHERE)
        return hp_diag_set(diag, HP_ERR_INVALID,
                           "load: a sphere head cannot be held at the load level (its contact "
                           "forces all pass through its centre, so nothing holds its "
                           "rotation): use an ellipsoid head");
    if (!(ops->caps & HP_BACKEND_LOAD) || !ops->load_hold)
        return hp_diag_set(diag, HP_ERR_INVALID,
                           "backend: %s is not available at the load level (use a backend "
                           "that plans it: realtime, ipopt or nlopt-slsqp)",
                           ops->name);
    if (s->load_tiebreak == HP_TIE_STIFFNESS && !(ops->caps & HP_BACKEND_LOAD_STIFFNESS))
        return hp_diag_set(diag, HP_ERR_INVALID,
                           "load_tiebreak: tie-breaker stiffness needs the ipopt backend (%s "
                           "solves the distance tie-breakers only)",
                           ops->name);
    hp_error e = hp_layout_identify(&p->M.layout, &p->id);
    if (e != HP_OK)
        return hp_diag_set(diag, e, "layout: the contact Jacobian at the nominal pose: %s",
                           hp_error_message(e));
    for (int k = 0; k < p->M.layout.n; ++k)
        if ((e = bladder_bounds(p, k, diag)) != HP_OK) return e;
    if ((e = check_carry(p, diag)) != HP_OK) return e;
    p->set = *s;
    p->ops = ops;
    p->err = err;
    for (int k = 0; k < p->M.layout.n; ++k) p->start_P[k] = fmin(fmax(0.0, p->lo[k]), p->hi[k]);
    hpi_load_level_reset(p);
    return HP_OK;
}

void hpi_load_level_reset(hp_load_level *p)
{
    const int n = p->M.layout.n;
    memcpy(p->prev_P, p->start_P, (size_t)n * sizeof *p->prev_P);
    memset(p->prev_xi, 0, sizeof p->prev_xi);
    memcpy(p->last_P, p->start_P, (size_t)n * sizeof *p->last_P);
    memset(p->last_xi, 0, sizeof p->last_xi);
    p->have_prev = 0;
}

/* The equilibrium residual a returned answer must meet: every generalized force below
 * 1e-9 N (moment rows: N·m per rad times 1°/1 mm), i.e. far below what moves the head by
 * 1e-9 mm at the stiffnesses of a held head (>= 1 N/mm). */
#define HOLD_TOL 1e-9

static int holds(const hp_load_model *M, const double xi[6], const double *P)
{
    double Q[6];
    if (hp_load_eval(M, xi, P, Q, NULL, NULL, NULL, NULL) != HP_OK) return 0;
    for (int i = 0; i < 6; ++i)
        if (!(fabs(Q[i]) * (i < 3 ? 1.0 : hpi_load_unit(i) / 1e-3) <= HOLD_TOL)) return 0;
    return 1;
}

/* The independent check a returned answer must also meet at the plane and surface levels,
 * where Q's translation rows are exactly the net force and its rotation rows the net moment
 * through the Euler angles' Jacobian (docs/load.md): the Newton–Euler residual from the
 * contact points. An equilibrium to HOLD_TOL has it below 1e-9 N and, with that Jacobian's
 * conditioning 1/cos(roll), below 6e-11 N·m / cos(roll) (3e-8 N·m at roll 89.9°); a
 * disagreement of the two models is newtons. At the linear level the geometry is
 * linearised and the two differ at second order, so only Q is checked there. */
#define NEWTON_EULER_TOL 1e-6

static int newton_euler_holds(const hp_load_model *M, const double xi[6], const double *P)
{
    if (M->level == HP_LEVEL_LINEAR) return 1;
    double f[3], m[3];
    if (hp_load_newton_euler(M, xi, P, f, m) != HP_OK) return 0;
    return sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]) <= NEWTON_EULER_TOL &&
           sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]) <= NEWTON_EULER_TOL;
}

/* The largest component of xi − to in mm and degrees (result.pose_error's measure). */
static double pose_dist(const double xi[6], const double to[6])
{
    double e = 0.0;
    for (int i = 0; i < 6; ++i) e = fmax(e, fabs(xi[i] - to[i]) / hpi_load_unit(i));
    return e;
}

/* The weights of the closest-pose distance: the objective's (problem.h). */
static void pose_weights(const hp_load_level *p, double W[6])
{
    for (int i = 0; i < 6; ++i) W[i] = hpi_pose_weight(p->set.weight_mm_per_deg, i);
}

/* Is the pose `depth` metres below desired (along gravity) held inside this plan's bounds?
 * Feasibility only: HOLD's exact phase 1 (max_iter 0 skips the tie-breaker), checked by
 * the equilibrium. 1: held (x gets the pose, Pt the pressures); 0: not held with every
 * bladder centre outside the head; -1: some centre inside it, past its panel, where the
 * load model is not defined (hpi_load_domain): the head has sunk too far. */
static int held_pose(const hp_load_level *p, const double x[6], const double *target, double *Pt)
{
    const hp_load_model *M = &p->M;
    double F[HP_MAX_BLADDERS], rho[HP_MAX_BLADDERS];
    if (hpi_contact_eval_g(&M->layout, &M->geom, M->level, x, rho, NULL, NULL) != HP_OK ||
        hpi_load_domain(M, rho) != HP_OK)
        return -1;
    return hpi_load_hold(M, x, p->elo, p->ehi, target, NULL, 0, Pt, F, NULL) == HP_LOAD_SOLVE_OK &&
           holds(M, x, Pt);
}

static int held_at(const hp_load_level *p, const double desired[6], double depth,
                   const double *target, double x[6], double *Pt)
{
    const hp_load_model *M = &p->M;
    double g = 0.0;
    for (int a = 0; a < 3; ++a) g += M->spec.gravity[a] * M->spec.gravity[a];
    g = sqrt(g);
    memcpy(x, desired, 6 * sizeof *x);
    for (int a = 0; a < 3; ++a) x[a] += depth * M->spec.gravity[a] / g;
    return held_pose(p, x, target, Pt);
}

/* The sinking search's best held depth so far: its pose and pressures. */
static void keep_held(double xs[6], double *Ps, const double x[6], const double *Pt, int n)
{
    memcpy(xs, x, 6 * sizeof *xs);
    memcpy(Ps, Pt, (size_t)n * sizeof *Ps);
}

/* The held pose nearest to the desired one along gravity: the head sinks (translation along
 * ĝ) until some pressures inside the limits hold it, found by doubling the depth from
 * 1/16 mm to 64 mm and bisecting the boundary to 1e-9 mm. The panels below the head bound
 * the held depths from below: a doubling that jumps past every held depth into a panel
 * (held_at −1) is followed by a bisection between the last shallow depth and that one,
 * until a held depth is found. This is where a head too heavy for the limits comes to
 * rest, and the start of the 6-D refinement. Returns 1 with the pose and its pressures
 * (feasible, not tie-broken: the caller's HOLD at the final pose does that), 0 when no
 * depth up to 64 mm is held. At most 11 + 2·36 feasibility checks, each one HOLD phase 1
 * (one contact evaluation and one bounded QP), most of them unreachable depths that the
 * row-interval test of HOLD (or the domain check) rejects without a QP. */
static int sink(const hp_load_level *p, const double desired[6], const double *target, double sign,
                double xs[6], double *Ps)
{
    const int n = p->M.layout.n;
    double Pt[HP_MAX_BLADDERS], x[6];
    double lo = 0.0, hi = -1.0, deep = -1.0;
    for (double depth = 6.25e-5; depth <= 0.0641; depth *= 2.0) {
        int h = held_at(p, desired, sign * depth, target, x, Pt);
        if (h > 0) {
            hi = depth;
            keep_held(xs, Ps, x, Pt, n);
            break;
        }
        if (h < 0) {
            deep = depth;
            break;
        }
        lo = depth;
    }
    while (hi < 0 && deep > 0 && deep - lo > 1e-12) {
        double mid = 0.5 * (lo + deep);
        int h = held_at(p, desired, sign * mid, target, x, Pt);
        if (h > 0) {
            hi = mid;
            keep_held(xs, Ps, x, Pt, n);
        } else if (h < 0) {
            deep = mid;
        } else {
            lo = mid;
        }
    }
    if (hi < 0) return 0;
    while (hi - lo > 1e-12) {
        double mid = 0.5 * (lo + hi);
        if (held_at(p, desired, sign * mid, target, x, Pt) > 0) {
            hi = mid;
            keep_held(xs, Ps, x, Pt, n);
        } else {
            lo = mid;
        }
    }
    return 1;
}

/* hpi_load_closest from (x0, F0), then HOLD's exact feasibility at the pose it stops at.
 * When that pose is not held to the checks' tolerance (the SQP meets the rows to its
 * rounding, HOLD asks them exactly) and x0 is held, the held pose nearest to it on the
 * segment from x0 is taken (bisection to 2^-30 of the segment): never farther than x0, as
 * the distance is convex. 1 with (x, P) a held pose, else 0. */
static int closest_from(const hp_load_level *p, const double desired[6], const double W[6],
                        const double *target, const double x0[6], const double *F0, double x[6],
                        double *P, int *iters)
{
    const hp_load_model *M = &p->M;
    const int n = M->layout.n;
    double xc[6], Pt[HP_MAX_BLADDERS], xt[6];
    int it = 0;
    hpi_load_solve_status st = hpi_load_closest(M, desired, W, p->elo, p->ehi, x0, F0,
                                                p->set.max_iter, xc, &it);
    *iters += it;
    if (st != HP_LOAD_SOLVE_OK && st != HP_LOAD_SOLVE_ITERATION_LIMIT) return 0;
    if (held_pose(p, xc, target, P) > 0) {
        memcpy(x, xc, 6 * sizeof *x);
        return 1;
    }
    if (!F0) return 0;
    double a = 0.0, b = 1.0;
    int moved = 0;
    for (int step = 0; step < 30; ++step) {
        double t = 0.5 * (a + b);
        for (int i = 0; i < 6; ++i) xt[i] = x0[i] + t * (xc[i] - x0[i]);
        if (held_pose(p, xt, target, Pt) > 0) {
            a = t;
            memcpy(x, xt, 6 * sizeof *x);
            memcpy(P, Pt, (size_t)n * sizeof *P);
            moved = 1;
        } else {
            b = t;
        }
    }
    return moved;
}

#define RESTARTS 4

/* The closest held pose as a program (hpi_load_closest), from several starts: the desired
 * pose itself with every bladder at the middle of its force range (the program's
 * restoration steps find a held pose from a start that is not held), the held pose (xi, P)
 * the search found, when have, and the held pose nearest to the nominal one (the same
 * program asked for the nominal pose, where a layout is meant to hold the head). Like any
 * SQP, the restoration can stall where the rows' residual is locally least; a held start
 * does not need it. The nearest held pose wins; (xi, P) gets it. Returns 1 when there is
 * one. */
static int closest_program(const hp_load_level *p, const double desired[6], const double W[6],
                           const double *target, int have, double xi[6], double *P, int *iters)
{
    const hp_load_model *M = &p->M;
    const int n = M->layout.n;
    static const double nominal[6] = {0, 0, 0, 0, 0, 0};
    double F0[HP_MAX_BLADDERS], Q[6], x[6], Px[HP_MAX_BLADDERS], x0[6];
    for (int start = 0; start < 3; ++start) {
        if (start == 0 && !closest_from(p, desired, W, target, desired, NULL, x, Px, iters))
            continue;
        if (start == 1) { /* from the held pose found so far (the search's, or start 0's) */
            if (!have || hp_load_eval(M, xi, P, Q, NULL, NULL, F0, NULL) != HP_OK) continue;
            memcpy(x0, xi, sizeof x0);
            if (!closest_from(p, desired, W, target, x0, F0, x, Px, iters)) continue;
        }
        if (start == 2) { /* from the held pose nearest to the nominal one */
            if (!closest_from(p, nominal, W, target, nominal, NULL, x0, Px, iters) ||
                hp_load_eval(M, x0, Px, Q, NULL, NULL, F0, NULL) != HP_OK)
                continue;
            double P0[HP_MAX_BLADDERS];
            memcpy(P0, Px, (size_t)n * sizeof *P0);
            if (!closest_from(p, desired, W, target, x0, F0, x, Px, iters)) {
                memcpy(x, x0, sizeof x); /* the nominal's held pose itself */
                memcpy(Px, P0, (size_t)n * sizeof *Px);
            }
        }
        if (have && !(hpi_load_pose_err(x, desired, W) < hpi_load_pose_err(xi, desired, W)))
            continue;
        memcpy(xi, x, 6 * sizeof *xi);
        memcpy(P, Px, (size_t)n * sizeof *P);
        have = 1;
    }
    /* Restarted from the winner (fresh trust region and multipliers) while that helps, at
     * most RESTARTS times: a run that ended on its trust region's floor can go on. */
    for (int again = 0; again < RESTARTS && have; ++again) {
        if (hp_load_eval(M, xi, P, Q, NULL, NULL, F0, NULL) != HP_OK) break;
        memcpy(x0, xi, sizeof x0);
        if (!closest_from(p, desired, W, target, x0, F0, x, Px, iters) ||
            !(hpi_load_pose_err(x, desired, W) < hpi_load_pose_err(xi, desired, W)))
            break;
        memcpy(xi, x, 6 * sizeof *xi);
        memcpy(P, Px, (size_t)n * sizeof *P);
    }
    return have;
}

/* This plan's bounds: the pressure, stretch and limit-point bounds, cut by each bladder's
 * rate window (hpi_rate_window) around the previous pressures when the settings use rate limits and a previous
 * pressure is known (a plan, hp_planner_set_previous or hp_planner_set_previous_result gave one). prev_P is always
 * inside the static bounds, so the cut box is never empty. */
static void plan_bounds(hp_load_level *p)
{
    for (int k = 0; k < p->M.layout.n; ++k) {
        const hp_bladder *b = &p->M.layout.bladders[k];
        p->elo[k] = p->lo[k];
        p->ehi[k] = p->hi[k];
        p->elo_bind[k] = p->lo_bind[k];
        p->ehi_bind[k] = p->hi_bind[k];
        if (!p->set.use_rate_limits || !p->have_prev || !isfinite(b->rate_max)) continue;
        double wl, wh;
        hpi_rate_window(p->prev_P[k], b->rate_max, &wl, &wh);
        if (wl > p->elo[k]) {
            p->elo[k] = wl;
            p->elo_bind[k] = HP_BIND_RATE_DOWN;
        }
        if (wh < p->ehi[k]) {
            p->ehi[k] = wh;
            p->ehi_bind[k] = HP_BIND_RATE_UP;
        }
    }
}

/* HOLD with the configured backend's tie-breaker (its load_hold: Ipopt's and NLopt's raw
 * code in *raw), then the stable member of the holding family (hpi_load_stable_hold) when
 * the tie-breaker's pick is not stable: the same for every backend. Where the search finds
 * no stable member the pick stands, and the plan's stability check refuses it. */
static hpi_load_solve_status hold(const hp_load_level *p, const double xi[6], const double *target,
                                  const double *start, double *P, double *F, int *iters, int *raw)
{
    /* The distance tie-breaker of a backend that keeps its holding set and scan hands both
     * to the stable search (load_hold_keep): the search then replays the scan. */
    const int keep = p->ops->load_hold_keep && p->set.load_tiebreak != HP_TIE_STIFFNESS;
    hp_load_hold_set hs;
    hp_load_scan_rec rec;
    hpi_load_solve_status st = keep ? p->ops->load_hold_keep(&p->M, xi, p->elo, p->ehi, target,
                                                             start, p->set.max_iter, P, F, iters,
                                                             &hs, &rec)
                                    : p->ops->load_hold(&p->M, xi, p->elo, p->ehi, target, start,
                                                        p->set.max_iter,
                                                        p->set.load_tiebreak == HP_TIE_STIFFNESS, P,
                                                        F, iters, raw);
    if (st != HP_LOAD_SOLVE_OK) return st;
    /* The search replaces (P, F) only with a stable hold it found (OK), else leaves them. */
    if (keep) hpi_load_stable_hold_set(&hs, &rec, xi, P, F, NULL);
    else hpi_load_stable_hold(&p->M, xi, p->elo, p->ehi, target, P, F, NULL);
    return st;
}

/* What a REACHED answer must also have (docs/load.md, "Stable holds"): the forward model
 * confirms it. The holding stiffness at (xi, P), the one hp_planner_load_info reports, is
 * positive definite, and the forward statics of P started at xi rests within 1e-6 mm/deg of
 * xi (the tolerance of hp_planner.h's reached_means_reached). 1 when confirmed. */
static int confirmed_hold(const hp_load_model *M, const double xi[6], const double *P)
{
    hp_load_holding h;
    double rest[6];
    if (hp_load_holding_at(M, xi, P, &h) != HP_OK || !h.stable ||
        hp_load_rest(M, P, xi, rest, NULL) != HP_OK)
        return 0;
    for (int i = 0; i < 6; ++i)
        if (!(fabs(rest[i] - xi[i]) / hpi_load_unit(i) <= 1e-6)) return 0;
    return 1;
}

/* The smallest eigenvalue [N/mm] of the holding stiffness at (xi, P), for the message of a
 * refused hold only (confirmed_hold asks no eigenvalue); NaN when the model fails. */
static double hold_lambda(const hp_load_model *M, const double xi[6], const double *P)
{
    hp_load_holding h;
    double lam;
    if (hp_load_holding_at(M, xi, P, &h) != HP_OK || hpi_load_stiff_lambda_min(h.K, &lam) != 0)
        return NAN;
    return lam;
}

/* The indentation check a returned answer must meet: every carrying bladder inside the
 * range where the contact law is trusted (HOLD caps the pressures there; the 6-D
 * refinement's forward statics does not know the range). INDENT_TOL covers the round trip
 * pressure -> radius of the cap (~1e-13 in the ratio). */
#define INDENT_TOL 1e-9

static int indent_ok(const hp_load_model *M, const double xi[6], const double *P)
{
    double ratio[HP_MAX_BLADDERS];
    if (hp_load_indentation(M, xi, P, ratio) != HP_OK) return 0;
    for (int k = 0; k < M->layout.n; ++k)
        if (!(ratio[k] <= HP_LOAD_INDENT_MAX + INDENT_TOL)) return 0;
    return 1;
}

/* The fitted contact law's domain at an answer (load_internal.h, hpi_load_claw_check): HP_OK
 * when every bladder that presses on the head does so inside the tables the law was fitted
 * to (always under the cap law, which has no such domain), else HP_ERR_INVALID with the
 * bladder and the group it leaves in diag. */
static hp_error law_domain_ok(const hp_load_model *M, const double xi[6], const double *P,
                              hp_diag *diag)
{
    double rho[HP_MAX_BLADDERS];
    hp_error err = hpi_contact_eval_g(&M->layout, &M->geom, M->level, xi, rho, NULL, NULL);
    if (err) return hp_diag_set(diag, err, "load: the contact distances at the answer");
    for (int k = 0; k < M->layout.n; ++k) {
        double ro;
        if ((err = hp_load_radius(M, k, P[k], &ro, NULL)))
            return hp_diag_set(diag, err, "load: the radius of bladder '%s'",
                               M->layout.bladders[k].name);
        if (P[k] > 0.0 && ro > rho[k] && (err = hpi_load_claw_check(M, k, P[k], ro, rho[k], diag)))
            return err;
    }
    return HP_OK;
}

/* What binds a CLOSEST answer (pressures P held at pose xi), per bladder in flags: the
 * pressure bounds it sits on, the indentation range, and carrying nothing (it cannot pull
 * the head toward the desired pose); with stab (an answer found because the nearer held
 * pose is a saddle: stable_answer) stability on every bladder that carries load, whose
 * contacts make the holding stiffness (hp_planner.h, HP_BIND_STABILITY). Returns how many
 * bladders have a flag, or -1 when the model fails. */
static int closest_binding(const hp_load_level *p, const double xi[6], const double *P, int stab,
                           unsigned *flags)
{
    const hp_load_model *M = &p->M;
    double force[HP_MAX_BLADDERS], ratio[HP_MAX_BLADDERS], Q[6];
    if (hp_load_eval(M, xi, P, Q, NULL, NULL, force, NULL) != HP_OK ||
        hp_load_indentation(M, xi, P, ratio) != HP_OK)
        return -1;
    int any = 0;
    for (int k = 0; k < M->layout.n; ++k) {
        double eps = 1e-9 * (p->hi[k] - p->lo[k]);
        flags[k] = 0;
        if (P[k] <= p->elo[k] + eps) flags[k] |= p->elo_bind[k];
        if (P[k] >= p->ehi[k] - eps) flags[k] |= p->ehi_bind[k];
        if (ratio[k] >= HP_LOAD_INDENT_MAX - INDENT_TOL) flags[k] |= HP_BIND_INDENT_MAX;
        if (force[k] == 0.0) flags[k] |= HP_BIND_CANNOT_PULL;
        if (stab && force[k] > 0.0) flags[k] |= HP_BIND_STABILITY;
        any += flags[k] != 0;
    }
    return any;
}

/* Fills the per-bladder part of r from pressures P held at pose xi; a CLOSEST answer names
 * what binds (closest_binding, stab as there). */
static hp_error fill_bladders(const hp_load_level *p, const double xi[6], const double *P,
                              int closest, int stab, hp_result *r)
{
    const hp_load_model *M = &p->M;
    r->n = M->layout.n;
    unsigned flags[HP_MAX_BLADDERS] = {0};
    if (closest && closest_binding(p, xi, P, stab, flags) < 0) return HP_ERR_DOMAIN;
    for (int k = 0; k < M->layout.n; ++k) {
        const hp_iab *b = &M->layout.bladders[k].iab;
        hp_bladder_result *o = &r->bladders[k];
        double ri, ro;
        hp_error err = hp_iab_fk_limit(b, &M->limit[k], P[k], &ri);
        /* The root of a pressure inside the bounds lies inside [ri_lo, ri_hi] up to an ulp or
         * two (a pressure at the stretch cap's bound gave stretch 1.3000000000000003 against
         * stretch_max 1.3): keep the stretch inside its limits to the last bit. */
        ri = fmin(fmax(ri, p->ri_lo[k]), p->ri_hi[k]);
        if (!err) err = hp_iab_ro(b, ri, &ro);
        if (err) return err;
        o->pressure = P[k];
        o->ri = ri;
        o->ro = ro;
        o->stretch = ri / b->Ri;
        o->binding = flags[k];
    }
    return HP_OK;
}

/* The checks every returned answer meets (the plan's, below), for a candidate of the stable
 * walk: an equilibrium by both checks, inside the indentation range and the fitted law's
 * domain, confirmed by the forward model (confirmed_hold), and, as every CLOSEST answer,
 * naming a limit that binds (closest_binding). Stability counts: what keeps a candidate
 * from the desired pose may be only that the nearer holds are saddles, named on the
 * bladders that carry (at least one does: the head's weight rests on some). */
static int walk_answer_ok(const void *ctx, const double xi[6], const double *P)
{
    const hp_load_level *p = ctx;
    const hp_load_model *M = &p->M;
    unsigned flags[HP_MAX_BLADDERS];
    hp_diag dom;
    return holds(M, xi, P) && newton_euler_holds(M, xi, P) && indent_ok(M, xi, P) &&
           law_domain_ok(M, xi, P, &dom) == HP_OK && closest_binding(p, xi, P, 1, flags) > 0 &&
           confirmed_hold(M, xi, P);
}

/* Depths of the stable search along gravity: 1/16 mm to 64 mm in steps of 2^(1/4). */
#define GRAVITY_STEPS 41

/* The stable hold nearest the desired pose along gravity: the head sunk (sign +1) or lifted
 * (−1) from the desired pose by depths 1/16 mm · 2^(j/4), j = 0..40, the first depth held
 * inside this plan's bounds (held_at) whose HOLD answer the checks accept (walk_answer_ok:
 * stable among them) is the candidate of that side. Where the shallowest held depth (the
 * sinking search's) is a saddle, a deeper one can be stable (load_heavy.yaml's nominal pose:
 * the hold 8 mm lower is). At most 2·41 feasibility checks and one HOLD and its checks per
 * held depth tried. */
static void stable_along_gravity(const hp_load_level *p, const hpi_load_walk_goal *g,
                                 const double *target, hpi_load_pick *best)
{
    const int n = p->M.layout.n;
    for (int sign = 1; sign >= -1; sign -= 2)
        for (int j = 0; j < GRAVITY_STEPS; ++j) {
            double x[6], Pt[HP_MAX_BLADDERS], Ph[HP_MAX_BLADDERS], F[HP_MAX_BLADDERS];
            int it = 0, raw = 0;
            int h = held_at(p, g->desired, sign * 6.25e-5 * pow(2.0, 0.25 * j), target, x, Pt);
            if (h < 0) break; /* into a panel: deeper is outside the model */
            if (h == 0) continue;
            if (hold(p, x, target, Pt, Ph, F, &it, &raw) != HP_LOAD_SOLVE_OK ||
                !g->check(g->ctx, x, Ph))
                continue;
            double e = hpi_load_pose_err(x, g->desired, g->W);
            if (e < best->err) {
                best->err = e;
                memcpy(best->xi, x, sizeof best->xi);
                memcpy(best->P, Ph, (size_t)n * sizeof *Ph);
            }
            break;
        }
}

/* An answer (xi, P) that the forward model does not confirm (a saddle): the stable answer
 * nearest the desired pose among two kinds of candidates, each checked as every answer is
 * (walk_answer_ok). The stable holds along gravity (stable_along_gravity). And, from a
 * previous answer the forward model can start from (a previous pose its pressures hold: not
 * after create or reset, where the head's pose is not known, and the rest of pressures
 * depends on where the head starts), the stable walk (load_walk.h) toward the stable hold of
 * xi inside the static limits (which the rate windows cut off; where there is none, toward P
 * itself), its candidates inside this plan's bounds; its candidate t = 0 is the previous
 * answer itself, so the winner is never farther from the desired pose than the previous
 * pose. 1 with (xi, P) replaced by the winner. */
static int stable_answer(const hp_load_level *p, const double desired[6], const double *target,
                         double xi[6], double *P)
{
    const hp_load_model *M = &p->M;
    const int n = M->layout.n;
    double W[6];
    pose_weights(p, W);
    const hpi_load_walk_goal g = {desired, W, walk_answer_ok, p};
    hpi_load_pick best;
    best.err = INFINITY;
    if (p->have_prev && holds(M, p->prev_xi, p->prev_P)) {
        double goal[HP_MAX_BLADDERS], Fs[HP_MAX_BLADDERS];
        memcpy(goal, P, (size_t)n * sizeof *goal);
        int cut = 0;
        for (int k = 0; k < n; ++k) cut |= p->elo[k] > p->lo[k] || p->ehi[k] < p->hi[k];
        /* Without a window the search inside the static limits already ran (hold) and
         * failed. */
        if (cut) {
            double Ps[HP_MAX_BLADDERS];
            memcpy(Ps, P, (size_t)n * sizeof *Ps);
            if (hpi_load_stable_hold(M, xi, p->lo, p->hi, target, Ps, Fs, NULL) == HP_LOAD_SOLVE_OK)
                memcpy(goal, Ps, (size_t)n * sizeof *goal);
        }
        hpi_load_walk(M, p->prev_P, p->prev_xi, goal, p->elo, p->ehi, &g, &best);
    }
    stable_along_gravity(p, &g, target, &best);
    if (!(best.err < INFINITY)) return 0;
    memcpy(xi, best.xi, sizeof best.xi);
    memcpy(P, best.P, (size_t)n * sizeof *P);
    return 1;
}

hp_error hpi_load_level_plan(hp_load_level *p, const double desired[6], hp_result *r)
{
    if (!desired) {
        hpi_text_set(p->err, "desired: NULL");
        return HP_ERR_NULL;
    }
    double t0 = hpi_plan_now();
    memset(r, 0, sizeof *r);
    const hp_load_model *M = &p->M;
    const int n = M->layout.n;
    r->backend = p->set.backend;
    r->level = HP_LEVEL_LOAD;
    memcpy(r->desired, desired, sizeof r->desired);
    for (int i = 0; i < 6; ++i) r->commanded[i] = 1;
    p->err[0] = '\0';
    /* The request check of hp_plan: the same corrections refused with the same words. */
    int bad = !hpi_plan_desired_ok(&p->id, desired, p->err);
    plan_bounds(p);
    double target[HP_MAX_BLADDERS], P[HP_MAX_BLADDERS], xi[6];
    for (int k = 0; k < n; ++k)
        target[k] = p->set.load_tiebreak == HP_TIE_PREVIOUS ? p->prev_P[k] : 0.0;
    hpi_load_solve_status st = HP_LOAD_SOLVE_ERROR;
    int it1 = 0, it2 = 0, it3 = 0, held = 0; /* held: holds(M, xi, P) already checked */
    if (!bad) {
        double F[HP_MAX_BLADDERS];
        /* HOLD at the desired pose, accepted only when its equilibrium checks out. */
        memcpy(xi, desired, sizeof xi);
        st = hold(p, xi, target, p->prev_P, P, F, &it1, &r->raw_code);
        if (st == HP_LOAD_SOLVE_OK && !(held = holds(M, xi, P))) st = HP_LOAD_SOLVE_UNREACHABLE;
        r->status = HP_STATUS_REACHED;
        if (st != HP_LOAD_SOLVE_OK) {
            /* POSE: the nearest held pose (the desired one itself when HOLD's tie-breaking
             * solve failed on a reachable pose), then HOLD there for the tie-breaker. */
            double W[6];
            pose_weights(p, W);
            double Pa[HP_MAX_BLADDERS], xs[6], Ps[HP_MAX_BLADDERS], xu[6], Pu[HP_MAX_BLADDERS];
            int sunk = sink(p, desired, target, 1.0, xs, Ps);
            /* Lifted against gravity: where the indentation range caps the forces, a
             * shallower pose may be held where a deeper one is not. */
            if (sink(p, desired, target, -1.0, xu, Pu) &&
                (!sunk || hpi_load_pose_err(xu, desired, W) < hpi_load_pose_err(xs, desired, W))) {
                memcpy(xs, xu, sizeof xs);
                memcpy(Ps, Pu, (size_t)n * sizeof *Ps);
                sunk = 1;
            }
            st = hpi_load_pose(M, desired, W, p->elo, p->ehi, sunk ? xs : p->prev_xi,
                               sunk ? Ps : p->prev_P, p->set.max_iter, xi, Pa, &it2);
            /* The 6-D refinement must end on a held pose nearer than the sunk one. */
            if (st == HP_LOAD_SOLVE_OK || st == HP_LOAD_SOLVE_ITERATION_LIMIT) {
                int ok = holds(M, xi, Pa) && indent_ok(M, xi, Pa);
                if (sunk && (!ok || hpi_load_pose_err(xi, desired, W) >
                                        hpi_load_pose_err(xs, desired, W))) {
                    memcpy(xi, xs, sizeof xi);
                    memcpy(Pa, Ps, (size_t)n * sizeof *Pa);
                    st = HP_LOAD_SOLVE_OK;
                } else if (!ok) {
                    st = HP_LOAD_SOLVE_UNREACHABLE;
                }
            } else if (sunk) {
                memcpy(xi, xs, sizeof xi);
                memcpy(Pa, Ps, (size_t)n * sizeof *Pa);
                st = HP_LOAD_SOLVE_OK;
            }
            /* The closest held pose as a program, warm-started at the held pose found. */
            int have = st == HP_LOAD_SOLVE_OK || st == HP_LOAD_SOLVE_ITERATION_LIMIT;
            if (closest_program(p, desired, W, target, have, xi, Pa, &it2)) st = HP_LOAD_SOLVE_OK;
            if (st == HP_LOAD_SOLVE_OK || st == HP_LOAD_SOLVE_ITERATION_LIMIT) {
                int reached = pose_dist(xi, desired) <= p->set.tolerance;
                double xp[6]; /* POSE's pose, which its pressures Pa hold */
                memcpy(xp, xi, sizeof xp);
                if (reached) memcpy(xi, desired, sizeof xi);
                hpi_load_solve_status s2 = hold(p, xi, target, Pa, P, F, &it3, &r->raw_code);
                /* POSE's pressures hold the head at xi by construction (a forward-statics
                 * rest); HOLD only tie-breaks among the holding pressures, and where it
                 * finds no verified answer (a family squeezed against the limits) POSE's
                 * pressures stand. */
                held = s2 == HP_LOAD_SOLVE_OK && holds(M, xi, P);
                if (!held) {
                    memcpy(P, Pa, (size_t)n * sizeof *P);
                    /* Pa holds xp, not necessarily the desired pose within the tolerance. */
                    if (reached && !holds(M, xi, P)) {
                        reached = 0;
                        memcpy(xi, xp, sizeof xi);
                    }
                }
                r->status = reached                  ? HP_STATUS_REACHED
                            : st == HP_LOAD_SOLVE_OK ? HP_STATUS_CLOSEST
                                                     : HP_STATUS_ITERATION_LIMIT;
                st = HP_LOAD_SOLVE_OK;
            }
        }
    }
    r->iterations = it1 + it2 + it3;
    if (r->status == HP_STATUS_ITERATION_LIMIT)
        hpi_text_set(p->err, "load planner: iteration-limit: the closest-pose search ran out of "
                             "solver.max_iter; the pose returned is held inside the limits "
                             "but not proven the closest");
    /* Whichever path gave it (HOLD, the sinking search, the 6-D refinement from the previous
     * pose), an answer is returned only when it is an equilibrium by both checks. */
    int unverified = !bad && st == HP_LOAD_SOLVE_OK &&
                     !((held || holds(M, xi, P)) && newton_euler_holds(M, xi, P));
    int beyond = !bad && st == HP_LOAD_SOLVE_OK && !unverified && !indent_ok(M, xi, P);
    /* An answer the fitted law describes only outside its tables is not returned: refused
     * by name (the bladder and the group), never silent. */
    hp_diag dom;
    dom.text[0] = '\0';
    int outside = !bad && st == HP_LOAD_SOLVE_OK && !unverified && !beyond &&
                  law_domain_ok(M, xi, P, &dom) != HP_OK;
    /* A hold at the desired pose that the forward model does not confirm is not REACHED: the
     * head, let go there, leaves it. HOLD has already looked for a stable member of the
     * holding family; none was found inside the limits. */
    int unstable = !bad && st == HP_LOAD_SOLVE_OK && !unverified && !beyond && !outside &&
                   (r->status == HP_STATUS_REACHED || r->status == HP_STATUS_CLOSEST) &&
                   !confirmed_hold(M, xi, P);
    const int was_reached = r->status == HP_STATUS_REACHED;
    /* Nor a CLOSEST one: the stable walk from the previous answer and the stable holds along
     * gravity, else refused. An answer so found is limited by stability (HP_BIND_STABILITY):
     * the nearest stable hold among the candidates tried, not a proven nearest one. */
    double saddle[6];
    memcpy(saddle, xi, sizeof saddle);
    p->stab_found = 0;
    if (unstable && stable_answer(p, desired, target, xi, P)) {
        unstable = 0;
        r->status = HP_STATUS_CLOSEST;
        p->stab_found = 1;
        p->stab_was_reached = was_reached;
        p->stab_from_desired = pose_dist(xi, desired);
        p->stab_from_saddle = pose_dist(xi, saddle);
    }
    if (bad || st != HP_LOAD_SOLVE_OK || unverified || beyond || outside || unstable) {
        r->status = bad ? HP_STATUS_INVALID_INPUT : HP_STATUS_SOLVER_ERROR;
        if (unstable) {
            char t[HP_DIAG_MAX];
            snprintf(t, sizeof t,
                     "load planner: the %s pose is held inside the limits only at an "
                     "unstable equilibrium (no stable hold found: the holding stiffness's "
                     "smallest eigenvalue is %.3g N/mm, and the forward statics does not "
                     "rest within 1e-6 mm/deg of it; no stable rest found near it), so it is "
                     "not returned",
                     was_reached ? "desired" : "closest", hold_lambda(M, xi, P));
            hpi_text_set(p->err, t);
        } else if (outside) {
            hpi_text_set(p->err, "load planner: the pose found near the desired one is not "
                                 "returned: ");
            hpi_text_add(p->err, dom.text);
        } else if (beyond)
            hpi_text_set(p->err, "load planner: the pose found near the desired one indents a "
                                 "bladder beyond the range where the contact law is trusted "
                                 "(indent_max), so it is not returned");
        else if (unverified)
            hpi_text_set(p->err, "load planner: the pose found near the desired one is not an "
                                 "equilibrium of the load model (its residual exceeds 1e-9 N), "
                                 "so it is not returned");
        else if (!bad)
            hpi_text_set(p->err, "load planner: no pose near the desired one is held inside the "
                                 "limits");
        /* Safe output: the previous pressures at the previous pose. */
        memcpy(xi, p->prev_xi, sizeof xi);
        memcpy(P, p->prev_P, (size_t)n * sizeof *P);
    }
    hp_error err = fill_bladders(p, xi, P, r->status == HP_STATUS_CLOSEST, p->stab_found, r);
    if (err) return err;
    memcpy(r->achieved, xi, sizeof xi);
    r->pose_error = pose_dist(xi, desired);
    if (r->status == HP_STATUS_INVALID_INPUT || r->status == HP_STATUS_SOLVER_ERROR)
        r->pose_error = INFINITY;
    else {
        memcpy(p->prev_P, P, (size_t)n * sizeof *P);
        memcpy(p->prev_xi, xi, sizeof xi);
        p->have_prev = 1;
    }
    /* What hp_planner_load_info describes: the returned pressures at the returned pose. */
    memcpy(p->last_P, P, (size_t)n * sizeof *P);
    memcpy(p->last_xi, xi, sizeof xi);
    r->solve_time = hpi_plan_now() - t0;
    return HP_OK;
}

void hpi_load_level_note(const hp_load_level *p, char *buf)
{
    if (!p->stab_found) return;
    hpi_text_add(buf, "; the nearest stable hold the search found (the stable walk's "
                      "candidates and the holds along gravity), not a proven nearest stable "
                      "pose: ");
    hpi_text_add_num(buf, p->stab_from_desired, 3);
    hpi_text_add(buf, " mm/deg from the desired pose");
    if (!p->stab_was_reached) {
        hpi_text_add(buf, ", ");
        hpi_text_add_num(buf, p->stab_from_saddle, 3);
        hpi_text_add(buf, " mm/deg from the closest held pose");
    }
    hpi_text_add(buf, ", which is held only at an unstable equilibrium");
}

hp_error hpi_load_level_info(const hp_load_level *p, hp_load_info *info)
{
    const hp_load_model *M = &p->M;
    const double *xi = p->last_xi, *P = p->last_P;
    memset(info, 0, sizeof *info);
    double Q[6], f[3], m[3];
    hp_error err = hp_load_eval(M, xi, P, Q, NULL, NULL, info->force, NULL);
    if (!err) err = hp_load_newton_euler(M, xi, P, f, m);
    if (err) return err;
    info->residual_force = sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
    info->residual_moment = sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
    /* The holding describes the answer: the stiffness at the achieved pose with the
     * returned pressures. The rest of those pressures may lie elsewhere (a saddle's
     * descent leaves it), and its stiffness is not the answer's. */
    err = hp_load_holding_at(M, xi, P, &info->holding);
    if (!err) err = hp_load_indentation(M, xi, P, info->indent);
    if (err) return err;
    if (hp_load_rest(M, P, xi, info->rest, NULL) == HP_OK) {
        info->rest_error = 0.0;
        for (int i = 0; i < 6; ++i)
            info->rest_error = fmax(info->rest_error,
                                    fabs(info->rest[i] - xi[i]) / hpi_load_unit(i));
    } else {
        for (int i = 0; i < 6; ++i) info->rest[i] = NAN;
        info->rest_error = INFINITY;
    }
    return HP_OK;
}

void hpi_load_level_bounds(const hp_load_level *p, double *lo, double *hi)
{
    memcpy(lo, p->lo, (size_t)p->M.layout.n * sizeof *lo);
    memcpy(hi, p->hi, (size_t)p->M.layout.n * sizeof *hi);
}

/* Pressures a previous answer may hold: each inside its bladder's static bounds. HP_OK, or
 * HP_ERR_INVALID naming the bladder (who: the call, for the message). */
static hp_error previous_ok(hp_load_level *p, const char *who, const double *pressures)
{
    for (int k = 0; k < p->M.layout.n; ++k) {
        double P = pressures[k];
        if (!(P >= p->lo[k] && P <= p->hi[k])) { /* NaN too */
            snprintf(p->err, HP_DIAG_MAX,
                     "%s: previous pressure of bladder '%s': %.6g Pa is outside [%.6g, %.6g] Pa",
                     who, p->M.layout.bladders[k].name, P, p->lo[k], p->hi[k]);
            return HP_ERR_INVALID;
        }
    }
    return HP_OK;
}

hp_error hpi_load_level_set_previous(hp_load_level *p, const double *pressures)
{
    hp_error e = previous_ok(p, "set_previous", pressures);
    if (e != HP_OK) return e;
    memcpy(p->prev_P, pressures, (size_t)p->M.layout.n * sizeof *pressures);
    memcpy(p->last_P, pressures, (size_t)p->M.layout.n * sizeof *pressures);
    memcpy(p->last_xi, p->prev_xi, sizeof p->last_xi);
    p->have_prev = 1;
    p->err[0] = '\0';
    return HP_OK;
}

hp_error hpi_load_level_set_previous_result(hp_load_level *p, const hp_result *r)
{
    const int n = p->M.layout.n;
    if (r->n != n) {
        hpi_text_set(p->err, "set_previous_result: n is not the layout's number of bladders");
        return HP_ERR_INVALID;
    }
    for (int i = 0; i < 6; ++i)
        if (!isfinite(r->achieved[i])) {
            hpi_text_set(p->err, "set_previous_result: achieved: not finite");
            return HP_ERR_INVALID;
        }
    if (hpi_plan_range_check(&p->id, r->achieved, NULL) != 0) {
        hpi_text_set(p->err, "set_previous_result: achieved: outside the identifiable range");
        return HP_ERR_INVALID;
    }
    double P[HP_MAX_BLADDERS];
    for (int k = 0; k < n; ++k) P[k] = r->bladders[k].pressure;
    hp_error e = previous_ok(p, "set_previous_result", P);
    if (e != HP_OK) return e;
    /* The state a plan that returned r leaves: its pressures at its pose. */
    memcpy(p->prev_P, P, (size_t)n * sizeof *P);
    memcpy(p->prev_xi, r->achieved, sizeof p->prev_xi);
    memcpy(p->last_P, p->prev_P, (size_t)n * sizeof *p->last_P);
    memcpy(p->last_xi, p->prev_xi, sizeof p->last_xi);
    p->have_prev = 1;
    return HP_OK;
}
