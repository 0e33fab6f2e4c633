/* The planner's lifecycle: create (the only call that allocates), the previous answer
 * (reset, set_previous), options, accessors, destroy. The plan itself is in plan.c. */
#define _POSIX_C_SOURCE 200809L
#include "planner/planner_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

double hp_plan_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

void hp_plan_to_scaled(const double xi[6], double x[6])
{
    for (int i = 0; i < 6; ++i) x[i] = xi[i] * hp_pose_scaled_per_si(i);
}

void hp_plan_from_scaled(const double x[6], double xi[6]) { hp_setup_pose_from_scaled(x, xi); }

int hp_plan_answer_from_pose(hp_planner *p, const double x[6], const double *rho_known,
                             hp_result *res, double *clamp_mm)
{
    double rho[HP_MAX_BLADDERS];
    *clamp_mm = 0;
    if (rho_known) memcpy(rho, rho_known, sizeof(double) * (size_t)p->L.n);
    else if (hp_setup_contact_scaled(&p->L, &p->G, p->level, x, rho, NULL) != HP_OK) return 0;
    /* Every bladder's inner radius first, then the pressures: each half is a chain of
     * roots and divisions, and back to back the processor overlaps one bladder's chain with
     * the next one's (the same bits as one pass). */
    double ri[HP_MAX_BLADDERS];
    int clamped[HP_MAX_BLADDERS];
    for (int k = 0; k < p->L.n; ++k)
        if (hp_setup_ri_from_ro_s(&p->sb.iab_s[k], rho[k] / HP_MM_PER_M, p->pb.ri_lo_si[k],
                                  p->pb.ri_hi_si[k], &ri[k], &clamped[k]) != HP_OK)
            return 0;
    for (int k = 0; k < p->L.n; ++k) {
        const hp_bladder *B = &p->L.bladders[k];
        double plo = p->sb.p_lo[k], phi = p->sb.p_hi[k];
        if (p->s.use_rate_limits && isfinite(B->rate_max)) {
            plo = fmax(plo, p->prev.bladders[k].pressure - B->rate_max);
            phi = fmin(phi, p->prev.bladders[k].pressure + B->rate_max);
        }
        int c = clamped[k];
        hp_bladder_result *br = &res->bladders[k];
        if (hp_setup_bladder_from_ri_s(B, &p->sb.iab_s[k], rho[k] / HP_MM_PER_M, ri[k], c, plo,
                                       phi, br) != HP_OK)
            return 0;
        if (c) *clamp_mm = fmax(*clamp_mm, fabs(br->ro * HP_MM_PER_M - rho[k]));
        double ro_mm = br->ro * HP_MM_PER_M;
        if (ro_mm <= p->pb.ro_lo[k] + HP_BINDING_TOL_MM) br->binding |= p->lo_flags[k];
        if (ro_mm >= p->pb.ro_hi[k] - HP_BINDING_TOL_MM) br->binding |= p->hi_flags[k];
        if (!(br->pressure >= B->p_min && br->pressure <= B->p_max) || !isfinite(br->ri) ||
            !isfinite(br->ro))
            return 0;
    }
    hp_plan_from_scaled(x, res->achieved);
    return 1;
}

/* rate_free (planner_internal.h) from the settings and the bladders' rate limits. */
static void set_rate_free(hp_planner *p)
{
    p->rate_free = 1;
    for (int k = 0; k < p->L.n; ++k)
        p->rate_free &= !p->s.use_rate_limits || !isfinite(p->L.bladders[k].rate_max);
}

/* The nominal pose's answer: the first safe output. */
static hp_error build_nominal(hp_planner *p, hp_diag *d)
{
    hp_result *r = &p->nominal;
    memset(r, 0, sizeof *r);
    r->status = HP_STATUS_REACHED;
    r->backend = p->s.backend;
    r->level = p->level;
    r->n = p->L.n;
    for (int i = 0; i < 6; ++i) r->commanded[i] = p->commanded[i];
    double x0[6] = {0}, rho[HP_MAX_BLADDERS];
    if (hp_setup_contact_scaled(&p->L, &p->G, p->level, x0, rho, NULL) != HP_OK)
        return hp_diag_set(d, HP_ERR_INVALID, "layout: contact model fails at the nominal pose");
    for (int k = 0; k < p->L.n; ++k) {
        int c = 0;
        if (hp_setup_bladder_from_ro_s(&p->L.bladders[k], &p->sb.iab_s[k], rho[k] / HP_MM_PER_M,
                                       p->sb.ri_lo[k], p->sb.ri_hi[k], p->sb.p_lo[k],
                                       p->sb.p_hi[k], &r->bladders[k], &c) != HP_OK)
            return hp_diag_set(d, HP_ERR_INVALID, "bladder %s: no valid state at the nominal pose",
                               p->L.bladders[k].name);
    }
    /* When a limit excludes the nominal radii, the clamped radii hold some other pose. */
    double ro[HP_MAX_BLADDERS], xi[6], resid;
    for (int k = 0; k < p->L.n; ++k) ro[k] = r->bladders[k].ro;
    if (hp_plan_fit_from_nominal(p, ro, p->fk_free, NULL, xi, &resid) == HP_OK) {
        for (int i = 0; i < 6; ++i) r->achieved[i] = p->commanded[i] ? xi[i] : 0.0;
    }
    for (int k = 0; k < p->L.n; ++k) r->bladders[k].binding = 0;
    return HP_OK;
}

hp_error hp_plan_fit_from_nominal(const hp_planner *p, const double *ro, const int free_[6],
                                  const hp_kin_fit_near *near, double xi[6],
                                  double *residual_rms)
{
    /* With fk_free: hp_contact_fk's own checks, so this is a drop-in for it. */
    if (free_ == p->fk_free) {
        int nf = 0;
        for (int i = 0; i < 6; ++i) nf += free_[i] != 0;
        if (p->L.n < nf) return HP_ERR_INVALID;
        for (int k = 0; k < p->L.n; ++k)
            if (!(ro[k] > 0) || !isfinite(ro[k])) return HP_ERR_INVALID;
    }
    const double zero[6] = {0};
    return hp_kin_fit(&p->L, &p->G, p->level, ro, free_, zero, p->nom_ok ? &p->nom : NULL, near, xi,
                      residual_rms, NULL);
}

void hp_plan_set_previous_answer(hp_planner *p, const hp_result *r)
{
    if (r != &p->prev) p->prev = *r;
    p->prev_checked = 1; /* hp_planner_set_previous clears it after this call */
    hp_plan_to_scaled(r->achieved, p->x_prev);
    for (int k = 0; k < p->L.n; ++k) p->x_prev[6 + k] = r->bladders[k].ri * HP_MM_PER_M;
    for (int k = 0; k < p->L.n; ++k) p->pb.p_prev[k] = r->bladders[k].pressure;
    /* The next start is this answer's pose and radii, not a backend's own last point. */
    if (p->ops && p->ops->warm_point && p->bstate) p->ops->warm_point(p->bstate, 0);
}

void hp_planner_reset(hp_planner *p)
{
    if (!p || !p->built) return;
    hp_plan_set_previous_answer(p, &p->nominal);
}

hp_error hp_planner_create(const hp_layout *layout, const hp_settings *settings,
                           hp_planner **out, hp_diag *d)
{
    if (out) *out = NULL;
    if (!layout || !out) return hp_diag_set(d, HP_ERR_NULL, "layout or out is NULL");
    hp_settings s;
    if (settings) s = *settings;
    else hp_settings_default(&s);
    hp_error e = hp_settings_validate(&s, d);
    if (e != HP_OK) return e;
    const hp_backend_ops *ops = hp_backend_table(s.backend);
    if (!ops || !ops->create || !ops->solve)
        return hp_diag_set(d, HP_ERR_INVALID, "backend: '%s' is not built into this library",
                           hp_backend_name(s.backend));

    hp_planner *p = calloc(1, sizeof *p);
    if (!p) return hp_diag_set(d, HP_ERR_NOMEM, "planner: out of memory");
    p->L = *layout;
    p->s = s;
    e = hp_layout_prepare(&p->L, d);
    if (e == HP_OK) e = hp_geom_derive(&p->L, &p->G, d);
    if (e != HP_OK) goto fail;
    p->level = s.level;
    if (p->level == HP_LEVEL_AUTO) {
        e = hp_contact_auto_g(&p->L, &p->G, s.level_tolerance, s.auto_trans, s.auto_rot, &p->level);
        if (e != HP_OK) {
            hp_diag_set(d, e, "level: auto could not choose a contact level (%s)",
                        hp_error_message(e));
            goto fail;
        }
    }
    if ((e = hp_layout_identify_g(&p->L, &p->G, &p->id)) != HP_OK) {
        hp_diag_set(d, e, "layout: the contact Jacobian at the nominal pose: %s",
                    hp_error_message(e));
        goto fail;
    }
    memcpy(p->commanded, p->id.commanded, sizeof p->commanded);
    {
        /* The round-trip fits all start at the nominal pose: its model once, here. */
        const double zero[6] = {0};
        p->nom_ok = hp_kin_fit_start_at(&p->L, &p->G, p->level, zero, &p->nom) == HP_OK;
        int dof = p->L.head.shape == HP_HEAD_SPHERE ? 3 : 6;
        for (int i = 0; i < 6; ++i) p->fk_free[i] = i < dof;
    }
    if ((e = hp_setup_static_bounds(&p->L, &p->sb, d)) != HP_OK) goto fail;

    hp_problem *pb = &p->pb;
    pb->layout = &p->L;
    pb->geom = &p->G;
    pb->level = p->level;
    pb->n = p->L.n;
    pb->nx = 6 + p->L.n;
    for (int i = 0; i < 6; ++i) {
        double w = i < 3 ? 1.0 : 1.0 / (s.weight_mm_per_deg * s.weight_mm_per_deg);
        pb->w[i] = p->commanded[i] ? w : 0.0;
    }
    pb->mu = s.mu;
    if ((e = build_nominal(p, d)) != HP_OK) goto fail;
    hp_plan_set_previous_answer(p, &p->nominal);
    e = hp_setup_cycle_bounds(&p->L, &p->sb, pb->p_prev, s.use_rate_limits, pb, p->lo_flags,
                              p->hi_flags, d);
    if (e != HP_OK) goto fail;
    set_rate_free(p);
    p->ops = ops;
    e = ops->create(&p->bstate, pb, &s, d);
    if (e != HP_OK) goto fail;
    p->built = 1;
    *out = p;
    return HP_OK;
fail:
    hp_planner_destroy(p);
    return e;
}

void hp_planner_destroy(hp_planner *p)
{
    if (!p) return;
    if (p->ops && p->ops->destroy && p->bstate) p->ops->destroy(p->bstate);
    free(p);
}

const char *hp_planner_error(const hp_planner *p) { return p ? p->err : "planner is NULL"; }

const char *hp_planner_note(const hp_planner *p)
{
    if (!p) return "";
    /* The planner is the caller's own, never a const object: the pending text is written
     * here (hp_plan_note_flush), as hp_plan would have. */
    if (p->note_pending) hp_plan_note_flush((hp_planner *)p);
    return p->note;
}

const char *hp_planner_message(const hp_planner *p)
{
    if (!p) return hp_planner_error(p);
    /* A failure clears the note and an answer clears the error, so at most one is set. */
    return *p->err ? p->err : hp_planner_note(p);
}

hp_level hp_planner_level(const hp_planner *p) { return p ? p->level : HP_LEVEL_AUTO; }

const hp_layout *hp_planner_layout(const hp_planner *p) { return p ? &p->L : NULL; }

const hp_geom *hp_planner_geom(const hp_planner *p) { return p ? &p->G : NULL; }

const hp_identifiable *hp_planner_identifiable(const hp_planner *p) { return p ? &p->id : NULL; }

hp_error hp_planner_set_option(hp_planner *p, const char *name, double value)
{
    if (!p) return HP_ERR_NULL;
    if (!name) {
        hp_text_set(p->err, "set_option: name is NULL");
        return HP_ERR_NULL;
    }
    if (!p->built) return HP_ERR_STATE;
    if (!p->ops->set_option) {
        hp_text_set(p->err, "set_option: the ");
        hp_text_add(p->err, p->ops->name);
        hp_text_add(p->err, " backend has no options ('");
        hp_text_add(p->err, name);
        hp_text_add(p->err, "')");
        return HP_ERR_INVALID;
    }
    p->diag.text[0] = '\0';
    hp_error e = p->ops->set_option(p->bstate, name, value, &p->diag);
    if (e != HP_OK) {
        hp_text_set(p->err, "set_option: ");
        hp_text_add(p->err, p->diag.text);
    }
    return e;
}

hp_error hp_planner_set_previous(hp_planner *p, const double *pressures)
{
    if (!p) return HP_ERR_NULL;
    if (!pressures) {
        hp_text_set(p->err, "set_previous: pressures is NULL");
        return HP_ERR_NULL;
    }
    if (!p->built) return HP_ERR_STATE;
    for (int k = 0; k < p->L.n; ++k)
        if (!(pressures[k] >= p->sb.p_lo[k] && pressures[k] <= p->sb.p_hi[k])) {
            hp_text_set(p->err, "set_previous: a pressure is outside its limits or not finite: ");
            hp_text_add(p->err, p->L.bladders[k].name);
            return HP_ERR_INVALID;
        }
    return hp_plan_previous_from(p, pressures, 0, "set_previous");
}

/* The consistency hp_planner_set_previous_result asks of a result's bladders. ro against the
 * volume law of ri: HP_BINDING_TOL_MM (1e-9 m), far above the few ulps by which hp_plan's
 * ro (the contact distance) and the law's ro of the ri it inverted to differ, far below
 * anything physical. The pressure against IK(ri): 1e-9 of the bladder's pressure range
 * (p_max − p_min; 1.5e-5 Pa for 15 kPa), far above the rounding by which hp_plan's clamp
 * into a cycle's pressure window moves it (a few ulps), far below any clinical meaning. */
#define PREV_RO_TOL_M (HP_BINDING_TOL_MM / HP_MM_PER_M)
#define PREV_P_REL_TOL 1e-9

/* "set_previous_result: WHAT[: NAME]" into p->err; returns HP_ERR_INVALID. */
static hp_error prev_refused(hp_planner *p, const char *what, const char *name)
{
    hp_text_set(p->err, "set_previous_result: ");
    hp_text_add(p->err, what);
    if (name) {
        hp_text_add(p->err, ": ");
        hp_text_add(p->err, name);
    }
    return HP_ERR_INVALID;
}

/* The pose a previous answer may hold: finite, 0 where not commanded, inside the
 * identifiable range. Returns HP_OK or the refusal (p->err). */
static hp_error prev_pose_ok(hp_planner *p, const double xi[6])
{
    static const char *const axis[6] = {"x", "y", "z", "pitch", "roll", "yaw"};
    for (int i = 0; i < 6; ++i) {
        if (!isfinite(xi[i])) return prev_refused(p, "achieved: not finite", axis[i]);
        if (!p->commanded[i] && xi[i] != 0.0)
            return prev_refused(p, "achieved: not 0 in a component the planner does not command",
                                axis[i]);
    }
    int out = hp_plan_range_check(&p->id, xi, NULL);
    if (out == 1)
        return prev_refused(p, "achieved: translation outside the identifiable range", NULL);
    if (out == 2)
        return prev_refused(p, "achieved: rotation outside the identifiable range", NULL);
    return HP_OK;
}

/* Bladder k of a previous answer: pressure and ri inside the static limits, pressure =
 * IK(ri) and ro = the law's ro of ri to the tolerances above. HP_OK or the refusal. */
static hp_error prev_bladder_ok(hp_planner *p, int k, const hp_bladder_result *b)
{
    const hp_bladder *B = &p->L.bladders[k];
    double P, ro;
    if (!(b->pressure >= p->sb.p_lo[k] && b->pressure <= p->sb.p_hi[k]))
        return prev_refused(p, "pressure outside its limits or not finite", B->name);
    if (!(b->ri >= p->sb.ri_lo[k] && b->ri <= p->sb.ri_hi[k]))
        return prev_refused(p, "ri outside its stretch limits or not finite", B->name);
    if (hp_iab_ik(&B->iab, b->ri, &P) != HP_OK ||
        !(fabs(P - b->pressure) <= PREV_P_REL_TOL * (B->p_max - B->p_min)))
        return prev_refused(p, "pressure is not the pressure of ri", B->name);
    if (hp_iab_ro(&B->iab, b->ri, &ro) != HP_OK || !(fabs(ro - b->ro) <= PREV_RO_TOL_M))
        return prev_refused(p, "ro is not the outer radius of ri", B->name);
    return HP_OK;
}

hp_error hp_planner_set_previous_result(hp_planner *p, const hp_result *r)
{
    if (!p) return HP_ERR_NULL;
    if (!r) {
        hp_text_set(p->err, "set_previous_result: result is NULL");
        return HP_ERR_NULL;
    }
    if (!p->built) return HP_ERR_STATE;
    if (r->n != p->L.n) return prev_refused(p, "n is not the layout's number of bladders", NULL);
    hp_error e = prev_pose_ok(p, r->achieved);
    if (e != HP_OK) return e;
    /* Bladders bit for bit those of the previous answer, which passes the checks below by
     * construction (p->prev_checked): hp_plan's pressure is IK(ri) clamped into a window
     * whose ends IK meets to a few ulps, and its ro and the law's ro of ri differ by a few
     * ulps, 10^7 times below the tolerances. Along a trace, where the previous row is the
     * planner's own last answer, this skips 2n bladder-law evaluations; what is accepted
     * is the same either way, so the state still depends on the fields alone. */
    int same = p->prev_checked;
    for (int k = 0; same && k < p->L.n; ++k) {
        const hp_bladder_result *b = &r->bladders[k], *q = &p->prev.bladders[k];
        same = memcmp(&b->ri, &q->ri, sizeof b->ri) == 0 &&
               memcmp(&b->ro, &q->ro, sizeof b->ro) == 0 &&
               memcmp(&b->pressure, &q->pressure, sizeof b->pressure) == 0;
    }
    hp_result s = p->nominal;
    for (int k = 0; k < p->L.n; ++k) {
        const hp_bladder *B = &p->L.bladders[k];
        const hp_bladder_result *b = &r->bladders[k];
        if (!same && (e = prev_bladder_ok(p, k, b)) != HP_OK) return e;
        s.bladders[k].ri = b->ri;
        s.bladders[k].ro = b->ro;
        s.bladders[k].pressure = b->pressure;
        s.bladders[k].stretch = b->ri / B->iab.Ri; /* as hp_plan computes it */
        s.bladders[k].binding = 0;
    }
    memcpy(s.achieved, r->achieved, sizeof s.achieved);
    hp_plan_set_previous_answer(p, &s);
    return HP_OK;
}


/* Internal (horizon/horizon_internal.h): the rate limits of the next plans. */
hp_error hp_planner_set_rate_max(hp_planner *p, const double *rate_max)
{
    if (!p || !rate_max) return HP_ERR_NULL;
    for (int k = 0; k < p->L.n; ++k)
        if (!(rate_max[k] > 0.0)) return HP_ERR_INVALID; /* NaN, 0 and negatives */
    for (int k = 0; k < p->L.n; ++k) p->L.bladders[k].rate_max = rate_max[k];
    set_rate_free(p);
    /* Rate-free now: hp_plan no longer sets the cycle's bounds, so they return to the
     * static ones here (what it would set; they held at create). */
    if (p->rate_free &&
        hp_setup_cycle_bounds(&p->L, &p->sb, p->pb.p_prev, p->s.use_rate_limits, &p->pb,
                              p->lo_flags, p->hi_flags, NULL) != HP_OK)
        return HP_ERR_STATE;
    return HP_OK;
}
