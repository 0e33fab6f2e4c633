/* The planner's lifecycle: create (the only call that allocates), the previous answer
 * (reset, set_previous), options, accessors, destroy. The plan itself is in plan.c, the
 * load level's in load_level.c. */
#include "planner/planner_internal.h"
#include "planner/nominal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

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
    if (hpi_setup_contact_scaled(&p->L, &p->G, p->level, x0, rho, NULL) != HP_OK)
        return hp_diag_set(d, HP_ERR_INVALID, "layout: contact model fails at the nominal pose");
    for (int k = 0; k < p->L.n; ++k) {
        int c = 0;
        if (hpi_setup_bladder_from_ro_s(&p->L.bladders[k], &p->sb.iab_s[k], rho[k] / HP_MM_PER_M,
                                        p->sb.ri_lo[k], p->sb.ri_hi[k], p->sb.p_lo[k],
                                        p->sb.p_hi[k], &r->bladders[k], &c) != HP_OK)
            return hp_diag_set(d, HP_ERR_INVALID, "bladder %s: no valid state at the nominal pose",
                               p->L.bladders[k].name);
    }
    /* When a limit excludes the nominal radii, the clamped radii hold some other pose. */
    double ro[HP_MAX_BLADDERS], xi[6], resid;
    for (int k = 0; k < p->L.n; ++k) ro[k] = r->bladders[k].ro;
    if (hpi_plan_fit_from_nominal(p, ro, p->fk_free, NULL, xi, &resid) == HP_OK) {
        for (int i = 0; i < 6; ++i) r->achieved[i] = p->commanded[i] ? xi[i] : 0.0;
    }
    for (int k = 0; k < p->L.n; ++k) r->bladders[k].binding = 0;
    return HP_OK;
}

void hp_planner_reset(hp_planner *p)
{
    if (!p || !p->built) return;
    if (p->load) {
        hpi_load_level_reset(p->load);
        return;
    }
    hpi_plan_set_previous_answer(p, &p->nominal);
}

/* hpi_plan_at_fn: the plan of one correction at a named contact level (level_choice.c's
 * measurement of auto_pose). */
static hp_error plan_at(const hp_layout *layout, const hp_settings *settings, hp_level level,
                        const double desired[6], hp_result *r)
{
    hp_settings s = *settings;
    s.level = level;
    s.use_rate_limits = 0;
    s.warm_start = 0;
    hp_planner *q = NULL;
    hp_error e = hp_planner_create(layout, &s, &q, NULL);
    if (e == HP_OK) e = hp_plan(q, desired, r);
    hp_planner_destroy(q);
    return e;
}

/* The part of create that decides the level, and all that hp_planner_level_for runs: the
 * layout prepared, its geometry derived, the level resolved once (level_choice.c). s is
 * validated. On failure *out is NULL and nothing is left allocated. */
static hp_error begin(const hp_layout *layout, const hp_settings *s, hp_planner **out, hp_diag *d)
{
    *out = NULL;
    hp_planner *p = calloc(1, sizeof *p);
    if (!p) return hp_diag_set(d, HP_ERR_NOMEM, "planner: out of memory");
    p->L = *layout;
    p->s = *s;
    hp_error e = hp_layout_prepare(&p->L, d);
    if (e == HP_OK) e = hpi_geom_derive(&p->L, &p->G, d);
    if (e == HP_OK) e = hpi_planner_resolve_level(p, layout, plan_at, d);
    if (e != HP_OK) {
        hp_planner_destroy(p);
        return e;
    }
    *out = p;
    return HP_OK;
}

hp_error hp_planner_level_for(const hp_layout *layout, const hp_settings *settings, hp_level *level,
                              char *why, size_t len, hp_diag *d)
{
    if (why && len) why[0] = '\0';
    if (!layout || !level) return hp_diag_set(d, HP_ERR_NULL, "layout or level is NULL");
    hp_settings s;
    if (settings) s = *settings;
    else hp_settings_default(&s);
    hp_error e = hp_settings_validate(&s, d);
    hp_planner *p = NULL;
    if (e == HP_OK) e = begin(layout, &s, &p, d);
    if (e != HP_OK) return e;
    *level = p->level;
    if (why && len) snprintf(why, len, "%s", p->level_why);
    hp_planner_destroy(p);
    return HP_OK;
}

hp_error hp_planner_create(const hp_layout *layout, const hp_settings *settings, hp_planner **out,
                           hp_diag *d)
{
    if (out) *out = NULL;
    if (!layout || !out) return hp_diag_set(d, HP_ERR_NULL, "layout or out is NULL");
    hp_settings s;
    if (settings) s = *settings;
    else hp_settings_default(&s);
    hp_error e = hp_settings_validate(&s, d);
    if (e != HP_OK) return e;
    const hp_backend_ops *ops = hpi_backend_table(s.backend);
    if (!ops || !ops->create || !ops->solve)
        return hp_diag_set(d, HP_ERR_INVALID, "backend: '%s' is not built into this library",
                           hp_backend_name(s.backend));

    hp_planner *p = NULL;
    if ((e = begin(layout, &s, &p, d)) != HP_OK) return e;
    if ((e = hpi_layout_identify_g(&p->L, &p->G, &p->id)) != HP_OK) {
        hp_diag_set(d, e, "layout: the contact Jacobian at the nominal pose: %s",
                    hp_error_message(e));
        goto fail;
    }
    memcpy(p->commanded, p->id.commanded, sizeof p->commanded);
    p->ops = ops;
    if (p->level == HP_LEVEL_LOAD) {
        /* The load level plans with its own model and bounds (load_level.c) and the
         * backend's load_hold; the contact levels' problem and solver state are not built. */
        if ((e = hpi_load_level_build(p->load, &s, ops, p->err, d)) != HP_OK) goto fail;
        p->built = 1;
        *out = p;
        return HP_OK;
    }
    {
        /* The round-trip fits all start at the nominal pose: its model once, here. */
        const double zero[6] = {0};
        p->nom_ok = hpi_kin_fit_start_at(&p->L, &p->G, p->level, zero, &p->nom) == HP_OK;
        int dof = p->L.head.shape == HP_HEAD_SPHERE ? 3 : 6;
        for (int i = 0; i < 6; ++i) p->fk_free[i] = i < dof;
    }
    if ((e = hpi_setup_static_bounds(&p->L, &p->sb, d)) != HP_OK) goto fail;

    hp_problem *pb = &p->pb;
    pb->layout = &p->L;
    pb->geom = &p->G;
    pb->level = p->level;
    pb->n = p->L.n;
    pb->nx = 6 + p->L.n;
    for (int i = 0; i < 6; ++i) {
        pb->w[i] = p->commanded[i] ? hpi_pose_weight(s.weight_mm_per_deg, i) : 0.0;
    }
    pb->mu = s.mu;
    if ((e = build_nominal(p, d)) != HP_OK) goto fail;
    hpi_plan_set_previous_answer(p, &p->nominal);
    e = hpi_setup_cycle_bounds(&p->L, &p->sb, pb->p_prev, s.use_rate_limits, pb, p->lo_flags,
                               p->hi_flags, d);
    if (e != HP_OK) goto fail;
    set_rate_free(p);
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
    free(p->load);
    free(p);
}

hp_level hp_planner_level(const hp_planner *p) { return p ? p->level : HP_LEVEL_AUTO; }

const hp_layout *hp_planner_layout(const hp_planner *p) { return p ? &p->L : NULL; }

const hp_geom *hpi_planner_geom(const hp_planner *p) { return p ? &p->G : NULL; }

const hp_identifiable *hp_planner_identifiable(const hp_planner *p) { return p ? &p->id : NULL; }

hp_error hp_planner_set_option(hp_planner *p, const char *name, double value)
{
    if (!p) return HP_ERR_NULL;
    if (!name) {
        hpi_text_set(p->err, "set_option: name is NULL");
        return HP_ERR_NULL;
    }
    if (!p->built) return HP_ERR_STATE;
    if (p->load) {
        hpi_text_set(p->err, "set_option: the load level has no backend options ('");
        hpi_text_add(p->err, name);
        hpi_text_add(p->err, "')");
        return HP_ERR_INVALID;
    }
    if (!p->ops->set_option) {
        hpi_text_set(p->err, "set_option: the ");
        hpi_text_add(p->err, p->ops->name);
        hpi_text_add(p->err, " backend has no options ('");
        hpi_text_add(p->err, name);
        hpi_text_add(p->err, "')");
        return HP_ERR_INVALID;
    }
    p->diag.text[0] = '\0';
    hp_error e = p->ops->set_option(p->bstate, name, value, &p->diag);
    if (e != HP_OK) {
        hpi_text_set(p->err, "set_option: ");
        hpi_text_add(p->err, p->diag.text);
    }
    return e;
}

hp_error hp_planner_set_previous(hp_planner *p, const double *pressures)
{
    if (!p) return HP_ERR_NULL;
    if (!pressures) {
        hpi_text_set(p->err, "set_previous: pressures is NULL");
        return HP_ERR_NULL;
    }
    if (!p->built) return HP_ERR_STATE;
    if (p->load) return hpi_load_level_set_previous(p->load, pressures);
    for (int k = 0; k < p->L.n; ++k)
        if (!(pressures[k] >= p->sb.p_lo[k] && pressures[k] <= p->sb.p_hi[k])) {
            hpi_text_set(p->err, "set_previous: a pressure is outside its limits or not finite: ");
            hpi_text_add(p->err, p->L.bladders[k].name);
            return HP_ERR_INVALID;
        }
    return hpi_plan_previous_from(p, pressures, 0, "set_previous");
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
    hpi_text_set(p->err, "set_previous_result: ");
    hpi_text_add(p->err, what);
    if (name) {
        hpi_text_add(p->err, ": ");
        hpi_text_add(p->err, name);
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
    int out = hpi_plan_range_check(&p->id, xi, NULL);
    if (out == 1)
        return prev_refused(p, "achieved: translation outside the identifiable range", NULL);
    if (out == 2) return prev_refused(p, "achieved: rotation outside the identifiable range", NULL);
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
        hpi_text_set(p->err, "set_previous_result: result is NULL");
        return HP_ERR_NULL;
    }
    if (!p->built) return HP_ERR_STATE;
    if (p->load) return hpi_load_level_set_previous_result(p->load, r);
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
    hpi_plan_set_previous_answer(p, &s);
    return HP_OK;
}

hp_error hp_planner_set_rate_max(hp_planner *p, const double *rate_max)
{
    if (!p || !rate_max) return HP_ERR_NULL;
    for (int k = 0; k < p->L.n; ++k)
        if (!(rate_max[k] > 0.0)) return HP_ERR_INVALID; /* NaN, 0 and negatives */
    for (int k = 0; k < p->L.n; ++k) p->L.bladders[k].rate_max = rate_max[k];
    if (p->load) { /* the load level reads them from its model's copy of the layout */
        for (int k = 0; k < p->L.n; ++k) p->load->M.layout.bladders[k].rate_max = rate_max[k];
        return HP_OK;
    }
    set_rate_free(p);
    /* Rate-free now: hp_plan no longer sets the cycle's bounds, so they return to the
     * static ones here (what it would set; they held at create). */
    if (p->rate_free && hpi_setup_cycle_bounds(&p->L, &p->sb, p->pb.p_prev, p->s.use_rate_limits,
                                               &p->pb, p->lo_flags, p->hi_flags, NULL) != HP_OK)
        return HP_ERR_STATE;
    return HP_OK;
}

hp_error hp_planner_pressure_bounds(const hp_planner *p, double *lo, double *hi)
{
    if (!p || !lo || !hi) return HP_ERR_NULL;
    if (!p->built) return HP_ERR_STATE;
    if (p->load) {
        hpi_load_level_bounds(p->load, lo, hi);
        return HP_OK;
    }
    memcpy(lo, p->sb.p_lo, (size_t)p->L.n * sizeof *lo);
    memcpy(hi, p->sb.p_hi, (size_t)p->L.n * sizeof *hi);
    return HP_OK;
}

hp_error hp_planner_load_info(const hp_planner *p, hp_load_info *info)
{
    if (!p || !info) return HP_ERR_NULL;
    if (!p->built || !p->load) return HP_ERR_STATE;
    return hpi_load_level_info(p->load, info);
}

const hp_load_model *hp_planner_load_model(const hp_planner *p)
{
    return p && p->load ? &p->load->M : NULL;
}

/* The pressures of the nominal pose (hp_planner.h): nominal.c computes them. */
hp_error hp_planner_nominal_pressures(const hp_planner *p, double *pressures)
{
    if (!p || !pressures) return HP_ERR_NULL;
    const hp_layout *L = hp_planner_layout(p);
    if (!L) return HP_ERR_STATE;
    int bad = 0;
    hp_error e = hpi_nominal_pressures_of(L, hpi_planner_geom(p), pressures, &bad);
    if (e != HP_OK)
        for (int j = 0; j < L->n; ++j) pressures[j] = NAN;
    return e;
}
