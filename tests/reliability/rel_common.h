/* Shared by the reliability tests: layouts (default, sphere, soft, near-degenerate), the
 * backend × level matrix, and ONE checker of the safety invariants of hp_planner.h that
 * every plan in tests/reliability goes through.
 *
 * Fields that are valid per status (the "finite_valid_fields" invariant, hp_planner.h):
 *   every status: status, raw_code, backend, level, n, commanded[], uncommanded[] (0 on the
 *     safe output), iterations (>= 0),
 *     solve_time (finite, >= 0), achieved[] (finite), and for k < n every bladder's ri, ro,
 *     pressure, stretch (finite);
 *   pose_error: finite for an answer to this desired (REACHED, CLOSEST, and ITERATION_LIMIT /
 *     TIME_LIMIT carrying the last feasible iterate); exactly +inf marks the safe output
 *     (INVALID_INPUT, INFEASIBLE_START, SOLVER_ERROR, and a limit with no iterate); never NaN;
 *   desired[]: a copy of the input, so it may be NaN/Inf on INVALID_INPUT (not "valid").
 * Safe output: the bladders (ri, ro, pressure, stretch) and achieved pose of the previous
 * plan that returned an answer (finite pose_error), or of the nominal answer after create,
 * hp_planner_reset or hp_planner_set_previous, bit for bit. */
#ifndef HP_TEST_RELIABILITY_COMMON_H
#define HP_TEST_RELIABILITY_COMMON_H

#include "support/test_util.h"
#include "support/layout_fixture.h"

#include <stdlib.h>
#include <string.h>

static const hp_backend rel_backends[4] = {HP_BACKEND_REALTIME, HP_BACKEND_IPOPT,
                                           HP_BACKEND_NLOPT_SLSQP, HP_BACKEND_NLOPT_COBYLA};
/* Every level: the three contact levels and the load level. */
#define REL_LEVELS 4
static const hp_level rel_levels[REL_LEVELS] = {HP_LEVEL_LINEAR, HP_LEVEL_PLANE, HP_LEVEL_SURFACE,
                                                HP_LEVEL_LOAD};

/* Whether backend b plans level l: every backend plans the contact levels; the load level
 * needs a backend with a load HOLD (not nlopt-cobyla, which hp_planner_create refuses by
 * name: rel_planner checks that). */
static inline int rel_plans(hp_backend b, hp_level l)
{
    return l != HP_LEVEL_LOAD || b != HP_BACKEND_NLOPT_COBYLA;
}

/* The load the load level carries in these tests: 20 % of the head's mass along −Z (8.8 N;
 * the neck rest carries the rest), centre of mass at the head's centre, surface geometry.
 * Every layout the tests plan at the load level carries it: at most 15.9 N along +z inside
 * the indentation range with stretch_max 1.0999 (limits_not_representable), 10.3 N with the
 * soft material (C2 = 0); more would be refused at create. */
#define REL_LOAD_FRACTION 0.2

/* Layout kinds for the adversarial runs. */
enum { REL_DEFAULT = 0, REL_SPHERE, REL_SOFT, REL_DEGENERATE, REL_KINDS };
static const char *const rel_kind_names[REL_KINDS] = {"default", "sphere", "soft-C2=0",
                                                      "near-degenerate"};

/* REL_DEGENERATE: the eight bladders of the default layout on an almost-spherical ellipsoid
 * (90, 90.01, 90.02 mm): rotations are commandable in exact arithmetic (the Jacobian has
 * rank 6) but its smallest singular value is ~1e-4 of the largest (condition 1.3e4 at the
 * surface level, hp_layout_analyze). */
static inline hp_error rel_layout(hp_layout *L, int kind)
{
    if (kind == REL_SPHERE) return lf_layout_ex(L, 1, 2.2e4);
    if (kind == REL_SOFT) return lf_layout_ex(L, 0, 0.0);
    hp_error e = lf_layout_ex(L, 0, 2.2e4);
    if (e != HP_OK || kind != REL_DEGENERATE) return e;
    const double ax[3] = {0.090, 0.09001, 0.09002};
    for (int k = 0; k < L->n; ++k) {
        double u[3], p[3], c[3];
        e = hp_layout_contact(L, k, c, NULL, NULL);
        if (e != HP_OK) return e;
        for (int i = 0; i < 3; ++i) u[i] = c[i] / L->head.semi_axes[i];
        for (int i = 0; i < 3; ++i) p[i] = u[i] * ax[i];
        double r = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
        for (int i = 0; i < 3; ++i) p[i] /= r; /* back onto the unit sphere's image */
        hp_head h = L->head;
        for (int i = 0; i < 3; ++i) h.semi_axes[i] = ax[i];
        e = hp_head_center_from_touch(&h, p, L->bladders[k].iab.Ro, 0.0, L->bladders[k].center,
                                      NULL);
        if (e != HP_OK) return e;
    }
    for (int i = 0; i < 3; ++i) L->head.semi_axes[i] = ax[i];
    return hp_layout_prepare(L, NULL);
}

static inline hp_planner *rel_planner(const hp_layout *L, hp_backend b, hp_level level, double rate,
                                      int max_iter)
{
    hp_layout M = *L;
    for (int k = 0; k < M.n; ++k) M.bladders[k].rate_max = rate;
    hp_settings s;
    hp_settings_default(&s);
    s.backend = b;
    s.level = level;
    if (level == HP_LEVEL_LOAD) {
        hp_load_spec_default(&M.head, &s.load);
        s.load.law =
            HP_LOAD_LAW_CAP; /* the default bladders carry the head under the cap law only */
        s.load.mass *= REL_LOAD_FRACTION;
    }
    if (max_iter > 0) s.max_iter = max_iter;
    /* Generous: time budgets are tested in test_faults.c with a 1e-9 s budget; here an
     * outcome must not depend on the machine's speed (valgrind runs ~50x slower). */
    s.max_time = 60.0;
    hp_planner *p = NULL;
    hp_diag d = {{0}};
    hp_error e = hp_planner_create(&M, &s, &p, &d);
    if (!rel_plans(b, level)) { /* refused by name, and no planner to test */
        if (e != HP_ERR_INVALID || !strstr(d.text, "not available at the load level"))
            print_error("create %s/%s: not refused by name (%d: %s)\n", hp_backend_name(b),
                        hp_level_name(level), (int)e, d.text);
        hp_planner_destroy(p);
        return NULL;
    }
    if (e != HP_OK)
        print_error("create %s/%s: %s\n", hp_backend_name(b), hp_level_name(level), d.text);
    return e == HP_OK ? p : NULL;
}

/* What the checker needs between plans. */
typedef struct rel_ctx {
    const hp_planner *p;
    hp_iab_limit lp[HP_MAX_BLADDERS];
    hp_result safe; /* the expected safe output */
    int have_safe;
    int use_fk_limit; /* 1: hp_iab_fk_limit in the round trip (the same root, cheaper) */
    double worst_fk;  /* largest round-trip error of a REACHED plan (mm or deg) */
    long plans, by_status[HP_STATUS_COUNT_];
} rel_ctx;

/* The round-trip tolerance of REACHED [mm or deg]. The planner promises its pose to
 * `tolerance` (1e-9) at the model level; the round trip adds the inversion of the returned
 * pressure: a pressure rounded to 1 ulp (~1e-12 Pa at 10 kPa) moves ri by ulp/|dP/dri|, and
 * |dP/dri| falls to ~1e-3 of its nominal 1e6 Pa/m near the stable-branch cap, i.e. ~1e-12 m;
 * through the contact Jacobian's smallest singular value (~1e-2 mm per mm, deg on the
 * near-degenerate layout ~1e-4) that is ~1e-7 mm/deg at worst. 1e-6 leaves a factor 10. */
#define REL_FK_TOL 1e-6
#define REL_Q_TOL 1e-8

static inline void rel_ctx_init(rel_ctx *c, const hp_planner *p)
{
    memset(c, 0, sizeof *c);
    c->p = p;
    const hp_layout *L = hp_planner_layout(p);
    for (int k = 0; k < L->n; ++k) hp_iab_limit_point(&L->bladders[k].iab, &c->lp[k]);
}

/* The safe output right now: a NaN request returns it without changing it. */
static inline void rel_ctx_capture_safe(rel_ctx *c, hp_planner *p)
{
    const double bad[6] = {NAN, 0, 0, 0, 0, 0};
    hp_result r;
    hp_plan(p, bad, &r);
    c->safe = r;
    c->have_safe = 1;
}

static inline int rel_fail(char *why, size_t n, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;
static inline int rel_fail(char *why, size_t n, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(why, n, fmt, ap);
    va_end(ap);
    return 0;
}

/* Invariant bits, so each named test can check its own one through the same code. */
enum {
    REL_INV_PRESSURE = 1 << 0, /* pressure_within_limits */
    REL_INV_STRETCH = 1 << 1,  /* stretch_within_limits (and below the limit point) */
    REL_INV_FINITE = 1 << 2,   /* valid_fields_finite */
    REL_INV_SAFE = 1 << 3,     /* failure_labelled_with_safe_output */
    REL_INV_REACHED = 1 << 4,  /* reached_means_reached */
    REL_INV_BINDS = 1 << 5,    /* closest_names_binding */
    REL_INV_ALL = 63
};

/* A status that carries a new answer to this request. */
static inline int rel_answer_status(hp_status s)
{
    return s == HP_STATUS_REACHED || s == HP_STATUS_CLOSEST || s == HP_STATUS_UNCOMMANDED;
}

/* Checks one plan's result r (hp_plan returned ret) against the invariants in mask; 1 when
 * all hold, else 0 with the reason in why. Updates the expected safe output. */
static inline int rel_check(rel_ctx *c, hp_error ret, const double desired[6], const hp_result *r,
                            unsigned mask, char *why, size_t wn)
{
    const hp_planner *p = c->p;
    const hp_layout *L = hp_planner_layout(p);
    c->plans++;
    if (ret != HP_OK) return rel_fail(why, wn, "hp_plan returned %d", (int)ret);
    if ((int)r->status < 0 || r->status >= HP_STATUS_COUNT_)
        return rel_fail(why, wn, "status %d outside the enum", (int)r->status);
    c->by_status[r->status]++;
    if (r->n != L->n) return rel_fail(why, wn, "n = %d, layout has %d", r->n, L->n);
    for (int k = 0; k < L->n; ++k) {
        const hp_bladder *B = &L->bladders[k];
        const hp_bladder_result *b = &r->bladders[k];
        if ((mask & REL_INV_PRESSURE) && !(b->pressure >= B->p_min && b->pressure <= B->p_max))
            return rel_fail(why, wn, "%s: pressure %.17g outside [%g, %g] (%s)", B->name,
                            b->pressure, B->p_min, B->p_max, hp_status_name(r->status));
        if (mask & REL_INV_STRETCH) {
            if (!(b->stretch >= B->stretch_min && b->stretch <= B->stretch_max))
                return rel_fail(why, wn, "%s: stretch %.17g outside [%g, %g]", B->name, b->stretch,
                                B->stretch_min, B->stretch_max);
            if (c->lp[k].exists && !(b->ri < c->lp[k].ri))
                return rel_fail(why, wn, "%s: ri %.17g at/above the limit point %.17g", B->name,
                                b->ri, c->lp[k].ri);
            if (!(fabs(b->stretch - b->ri / B->iab.Ri) <= 1e-15 * b->stretch))
                return rel_fail(why, wn, "%s: stretch != ri/Ri", B->name);
        }
        if ((mask & REL_INV_FINITE) &&
            !(isfinite(b->ri) && isfinite(b->ro) && isfinite(b->pressure) && isfinite(b->stretch)))
            return rel_fail(why, wn, "%s: a bladder field is not finite", B->name);
    }
    int answer = isfinite(r->pose_error);
    if (mask & REL_INV_FINITE) {
        for (int i = 0; i < 6; ++i)
            if (!isfinite(r->achieved[i])) return rel_fail(why, wn, "achieved[%d] not finite", i);
        for (int i = 0; i < 6; ++i)
            if (!isfinite(r->uncommanded[i]) || (!answer && r->uncommanded[i] != 0.0))
                return rel_fail(why, wn, "uncommanded[%d] = %g (%s)", i, r->uncommanded[i],
                                hp_status_name(r->status));
        if (isnan(r->pose_error) || r->pose_error < 0)
            return rel_fail(why, wn, "pose_error %g", r->pose_error);
        if (!answer && rel_answer_status(r->status))
            return rel_fail(why, wn, "%s with pose_error +inf", hp_status_name(r->status));
        if (r->iterations < 0 || !isfinite(r->solve_time) || r->solve_time < 0)
            return rel_fail(why, wn, "iterations %d / solve_time %g", r->iterations, r->solve_time);
        if (r->level != hp_planner_level(p)) return rel_fail(why, wn, "level changed");
    }
    if (mask & REL_INV_SAFE) {
        /* Two text channels, one meaning each: an answer other than REACHED explains itself
         * in the note and leaves the error empty; anything else is a failure with text. */
        int explained = r->status == HP_STATUS_CLOSEST || r->status == HP_STATUS_UNCOMMANDED;
        if (explained && (hp_planner_note(p)[0] == '\0' || hp_planner_error(p)[0] != '\0'))
            return rel_fail(why, wn, "%s: note '%s', error '%s'", hp_status_name(r->status),
                            hp_planner_note(p), hp_planner_error(p));
        if (r->status == HP_STATUS_REACHED &&
            (hp_planner_note(p)[0] != '\0' || hp_planner_error(p)[0] != '\0'))
            return rel_fail(why, wn, "reached with a text");
        if (!explained && r->status != HP_STATUS_REACHED &&
            (hp_planner_error(p)[0] == '\0' || hp_planner_note(p)[0] != '\0'))
            return rel_fail(why, wn, "%s without an error text (or with a note)",
                            hp_status_name(r->status));
        int fail_st = r->status == HP_STATUS_INVALID_INPUT ||
                      r->status == HP_STATUS_INFEASIBLE_START ||
                      r->status == HP_STATUS_SOLVER_ERROR;
        if (fail_st && answer)
            return rel_fail(why, wn, "%s carries a new answer", hp_status_name(r->status));
        if (!answer && c->have_safe) {
            for (int k = 0; k < L->n; ++k)
                if (memcmp(&r->bladders[k].pressure, &c->safe.bladders[k].pressure,
                           sizeof(double)) != 0 ||
                    memcmp(&r->bladders[k].ri, &c->safe.bladders[k].ri, sizeof(double)) != 0)
                    return rel_fail(why, wn, "%s: %s pressure %.17g is not the safe %.17g",
                                    hp_status_name(r->status), L->bladders[k].name,
                                    r->bladders[k].pressure, c->safe.bladders[k].pressure);
            if (memcmp(r->achieved, c->safe.achieved, sizeof r->achieved) != 0)
                return rel_fail(why, wn, "safe output's pose changed");
        }
        for (int i = 0; desired && i < 6; ++i)
            if (memcmp(&r->desired[i], &desired[i], sizeof(double)) != 0)
                return rel_fail(why, wn, "desired[%d] not copied", i);
    }
    if ((mask & REL_INV_BINDS) && r->status == HP_STATUS_CLOSEST) {
        int any = 0;
        for (int k = 0; k < L->n; ++k) any |= r->bladders[k].binding != 0;
        if (!any) return rel_fail(why, wn, "CLOSEST names no binding limit");
        if (strstr(hp_planner_note(p), "binding none") || !strstr(hp_planner_note(p), "binding"))
            return rel_fail(why, wn, "CLOSEST text says 'binding none'");
    }
    if ((mask & REL_INV_REACHED) && r->status == HP_STATUS_REACHED &&
        hp_planner_level(p) == HP_LEVEL_LOAD) {
        /* At the load level REACHED means held at the desired pose: the achieved pose is the
         * desired one, and the load model's generalized force there with the returned
         * pressures vanishes. REL_Q_TOL: the planner accepts 1e-9 N on the force rows (and
         * 5.7e-11 N·m/rad on the moment rows); 10× that, far below the ~1 N/mm·1e-6 mm a
         * visible pose change would take. */
        double P[HP_MAX_BLADDERS], Q[6];
        for (int i = 0; i < 6; ++i)
            if (memcmp(&r->achieved[i], &desired[i], sizeof(double)) != 0)
                return rel_fail(why, wn, "load: reached, achieved[%d] %.17g is not desired %.17g",
                                i, r->achieved[i], desired[i]);
        for (int k = 0; k < L->n; ++k) P[k] = r->bladders[k].pressure;
        if (hp_load_eval(hp_planner_load_model(p), r->achieved, P, Q, NULL, NULL, NULL, NULL) !=
            HP_OK)
            return rel_fail(why, wn, "load: reached, the load model cannot evaluate the answer");
        for (int i = 0; i < 6; ++i)
            if (!(fabs(Q[i]) <= REL_Q_TOL))
                return rel_fail(why, wn, "load: reached, Q[%d] = %.3g", i, Q[i]);
    } else if ((mask & REL_INV_REACHED) &&
               (r->status == HP_STATUS_REACHED || r->status == HP_STATUS_UNCOMMANDED)) {
        /* The strict round trip: pressures -> radii -> forward contact kinematics started
         * from the NOMINAL pose (not from the answer) must give the desired pose (REACHED)
         * or its commanded part desired − uncommanded (UNCOMMANDED), in every component. */
        double ro[HP_MAX_BLADDERS], xi[6], resid, want[6];
        for (int k = 0; k < L->n; ++k) {
            double ri;
            const hp_iab *m = &L->bladders[k].iab;
            hp_error e = c->use_fk_limit
                             ? hp_iab_fk_limit(m, &c->lp[k], r->bladders[k].pressure, &ri)
                             : hp_iab_fk(m, r->bladders[k].pressure, &ri);
            if (e != HP_OK || hp_iab_ro(m, ri, &ro[k]) != HP_OK)
                return rel_fail(why, wn, "round trip: %s pressure %.17g not invertible",
                                L->bladders[k].name, r->bladders[k].pressure);
        }
        for (int i = 0; i < 6; ++i) {
            double u = r->uncommanded[i], s = i < 3 ? 1e3 : 57.295779513082320877;
            if (r->status == HP_STATUS_REACHED && !(fabs(u) * s <= HP_DEFAULT_TOLERANCE))
                return rel_fail(why, wn, "REACHED with uncommanded[%d] = %g", i, u);
            want[i] = r->desired[i] - u;
        }
        if (r->status == HP_STATUS_UNCOMMANDED) {
            double umax = 0;
            for (int i = 0; i < 6; ++i)
                umax = fmax(umax, fabs(r->uncommanded[i]) * (i < 3 ? 1e3 : 57.29577951308232));
            if (!(umax > HP_DEFAULT_TOLERANCE))
                return rel_fail(why, wn, "UNCOMMANDED with nothing uncommanded");
        }
        int dof = L->head.shape == HP_HEAD_SPHERE ? 3 : 6;
        if (L->n >= dof) {
            if (hp_contact_fk(L, r->level, ro, NULL, xi, &resid, NULL) != HP_OK)
                return rel_fail(why, wn, "round trip: hp_contact_fk from nominal failed");
            for (int i = 0; i < 6; ++i) {
                double s = i < 3 ? 1e3 : 57.295779513082320877;
                double err = fabs(xi[i] - want[i]) * s;
                if (err > c->worst_fk) c->worst_fk = err;
                if (!(err <= REL_FK_TOL))
                    return rel_fail(why, wn, "%s but FK from nominal pose[%d] is %.3g mm/deg off",
                                    hp_status_name(r->status), i, err);
            }
        }
        if (!(r->pose_error <= HP_DEFAULT_TOLERANCE))
            return rel_fail(why, wn, "%s with pose_error %g", hp_status_name(r->status),
                            r->pose_error);
    }
    if (answer) {
        c->safe = *r;
        c->have_safe = 1;
    }
    return 1;
}

/* Fails the cmocka test with the context when rel_check fails. */
static inline void rel_report(const rel_ctx *c, const char *tag, const char *why, const double *des)
{
    double z[6] = {0};
    if (!des) des = z;
    print_error("%s: %s [desired %.17g %.17g %.17g %.17g %.17g %.17g; msg '%s']\n", tag, why,
                des[0], des[1], des[2], des[3], des[4], des[5], hp_planner_error(c->p));
}

#define REL_ASSERT(c, ret, des, r, mask, tag)                                                      \
    do {                                                                                           \
        char why_[512];                                                                            \
        if (!rel_check((c), (ret), (des), (r), (mask), why_, sizeof why_)) {                       \
            rel_report((c), (tag), why_, (des));                                                   \
            fail();                                                                                \
        }                                                                                          \
    } while (0)

#endif
