/* The planner's level, resolved once at create over all four levels (hp_planner_create), and
 * why (hp_planner_level_choice): the one text that solve, batch's metadata record and the
 * Python module give for a level auto chose. */
#include "planner/planner_internal.h"
#include "common/units.h"
#include "kinematics/kin_geom.h"
#include "kinematics/names.h"
#include "planner/model_error.h"
#include "planner/nominal.h"
#include "planner/plan_range.h"
#include "planner/settings_check.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Why auto chose contact level `chosen`: the bounds it compared (hp_contact_auto, the
 * geometries in its order), every cheaper geometry's exceeding the tolerance, the chosen
 * one's meeting it (said only of an inexact one: the last geometry's bound is 0). E.g.
 * "auto chose plane: the error bound of linear (1.56 mm) exceeds RANGE; plane's meets it". */
static void contact_why(const hp_planner *p, hp_level chosen, char *why, size_t len)
{
    const hp_settings *s = &p->s;
    char range[96];
    snprintf(range, sizeof range, "model.tolerance_mm %g for corrections up to %g mm, %g deg",
             s->level_tolerance * 1e3, s->auto_trans * 1e3, s->auto_rot * HP_DEG_PER_RAD);
    const char *name = hp_level_name(chosen);
    int cheaper = 0;
    while (cheaper < hpi_level_n_geometries && hpi_level_geometries[cheaper] != chosen) ++cheaper;
    if (cheaper == 0 || cheaper == hpi_level_n_geometries) {
        snprintf(why, len, "auto chose %s: its error bound meets %s", name, range);
        return;
    }
    char list[160] = "";
    size_t at = 0;
    for (int i = 0; i < cheaper && at < sizeof list; ++i) {
        hp_level l = hpi_level_geometries[i];
        double b = NAN;
        if (hpi_contact_error_bound_g(&p->L, &p->G, l, s->auto_trans, s->auto_rot, &b) != HP_OK)
            b = NAN;
        const char *sep = i == 0 ? "" : i == cheaper - 1 ? " and " : ", ";
        int w = snprintf(list + at, sizeof list - at, "%s%s (%.3g mm)", sep, hp_level_name(l),
                         b * 1e3);
        if (w < 0) break;
        at += (size_t)w;
    }
    const int exact = cheaper == hpi_level_n_geometries - 1;
    /* A text longer than len is cut there and ends in "...", so a reader sees the cut. */
    int w = snprintf(why, len, "auto chose %s: the error bound%s of %s %s %s%s%s%s", name,
                     cheaper > 1 ? "s" : "", list, cheaper > 1 ? "exceed" : "exceeds", range,
                     exact ? "" : "; ", exact ? "" : name, exact ? "" : "'s meets it");
    if (w >= 0 && (size_t)w >= len && len >= 4) memcpy(why + len - 4, "...", 4);
}

/* One candidate of auto by model error: its error at auto_pose against the reference
 * (model_error.h), whether its plan there was the closest answer, a contact level's geometry
 * bound over the auto range [mm], and its tolerance-scaled size (<= 1 meets the tolerance;
 * +inf without a rest; NaN not measured). */
typedef struct candidate {
    hp_level level;
    hpi_fidelity_result m;
    int closest;
    double bound_mm;
    double scaled;
} candidate;

/* A plan's pressures at its claimed pose against ref, into x. */
static void measure_result(const hpi_fidelity_ref *ref, const hp_result *r, candidate *x)
{
    double P[HP_MAX_BLADDERS];
    for (int k = 0; k < r->n; ++k) P[k] = r->bladders[k].pressure;
    hpi_fidelity_measure(ref, P, r->achieved, &x->m);
    x->closest = r->status == HP_STATUS_CLOSEST;
}

/* The load level's plan of auto_pose on a load level of its own (the planner's is built
 * after the level is known), measured against ref. 0 when measured. */
static int measure_load(const hp_planner *p, const hp_layout *layout, const hpi_fidelity_ref *ref,
                        candidate *x)
{
    hp_settings s = p->s;
    s.level = HP_LEVEL_LOAD;
    s.use_rate_limits = 0;
    s.warm_start = 0;
    const hp_backend_ops *ops = hpi_backend_table(s.backend);
    hp_load_level *L = calloc(1, sizeof *L);
    char *err = malloc(HP_DIAG_MAX);
    int rc = -1;
    if (L && err && ops) {
        err[0] = '\0';
        hp_result r;
        if (hpi_load_level_model(L, layout, &s, NULL) == HP_OK &&
            hpi_load_level_build(L, &s, ops, err, NULL) == HP_OK &&
            hpi_load_level_plan(L, s.auto_pose, &r) == HP_OK && hpi_fidelity_answered(r.status)) {
            measure_result(ref, &r, x);
            rc = 0;
        }
    }
    free(err);
    free(L);
    return rc;
}

/* A contact level's plan of auto_pose (away from the nominal pose), by plan_at, measured
 * against ref. 0 when measured. */
static int measure_contact(const hp_planner *p, const hp_layout *layout, hpi_plan_at_fn plan_at,
                           hp_level level, const hpi_fidelity_ref *ref, candidate *x)
{
    hp_result r;
    if (plan_at(layout, &p->s, level, p->s.auto_pose, &r) != HP_OK ||
        !hpi_fidelity_answered(r.status))
        return -1;
    measure_result(ref, &r, x);
    return 0;
}

/* The nominal pose's measurement, shared by the contact levels: at the nominal pose every
 * contact level's plan has the same pressures (each bladder at its nominal contact
 * distance). 0 when measured. */
static int measure_nominal(const hp_planner *p, const hpi_fidelity_ref *ref, candidate *x)
{
    double P[HP_MAX_BLADDERS];
    int bad = -1;
    if (hpi_nominal_pressures_of(&p->L, &p->G, P, &bad) != HP_OK) return -1;
    const double zero[6] = {0};
    hpi_fidelity_measure(ref, P, zero, &x->m);
    x->closest = 0;
    return 0;
}

static int is_nominal(const double xi[6])
{
    for (int i = 0; i < 6; ++i)
        if (xi[i] != 0.0) return 0;
    return 1;
}

/* "the nominal pose" or "the pose x 1 mm, y 0 mm, z -0.5 mm, pitch 0.3 deg, roll 0 deg,
 * yaw -0.2 deg" (hp_plan's components, in the command line's units). */
static void pose_text(const double xi[6], char *buf, size_t len)
{
    if (is_nominal(xi)) {
        snprintf(buf, len, "the nominal pose");
        return;
    }
    double c[6];
    hp_pose_to_clinical(xi, c);
    snprintf(buf, len, "the pose x %g mm, y %g mm, z %g mm, pitch %g deg, roll %g deg, yaw %g deg",
             c[0] + 0.0, c[1] + 0.0, c[2] + 0.0, c[3] + 0.0, c[4] + 0.0, c[5] + 0.0);
}

/* "linear 1.07 mm, 0.342 deg (+1.56 mm geometry)", "surface no rest (0 % carried)",
 * "linear 0.403 mm, 0.97 deg at its closest answer", "load not measured". */
static int candidate_text(const candidate *c, char *buf, size_t len)
{
    const char *name = hp_level_name(c->level);
    const char *at = c->closest ? " at its closest answer" : "";
    if (isnan(c->scaled)) return snprintf(buf, len, "%s not measured", name);
    if (!isfinite(c->m.pose_mm))
        return snprintf(buf, len, "%s no rest (%.0f %% carried)%s", name,
                        100.0 * c->m.carried + 0.0, at);
    if (c->bound_mm > 0)
        return snprintf(buf, len, "%s %.3g mm, %.3g deg%s (+%.3g mm geometry)", name, c->m.pose_mm,
                        c->m.pose_deg, at, c->bound_mm);
    return snprintf(buf, len, "%s %.3g mm, %.3g deg%s", name, c->m.pose_mm, c->m.pose_deg, at);
}

/* auto on settings that state a load: the cheapest level whose model error at auto_pose
 * meets the tolerance, else the smallest error (equal, unbounded errors: the most weight
 * carried; the dearer level on a full tie). The contact levels in their order
 * (hpi_level_geometries), then the load level, each measured only when no cheaper one met
 * the tolerance. Each level plans auto_pose as solve would (a level that cannot reach it is
 * measured at its closest answer, said so); at the nominal pose the contact levels share one
 * measurement (measure_nominal). A contact level adds its geometry's error bound over the
 * auto range: the other corrections of that range, which one pose cannot show. A load level
 * that cannot be planned, with nothing meeting the tolerance, is chosen all the same
 * (below). *chosen stays HP_LEVEL_AUTO (why untouched) only if no level is left. */
static hp_error auto_by_model_error(hp_planner *p, const hp_layout *layout, hpi_plan_at_fn plan_at,
                                    hp_level *chosen, char *why, size_t len)
{
    const hp_settings *s = &p->s;
    *chosen = HP_LEVEL_AUTO;
    const double tol_mm = s->level_tolerance * 1e3, tol_deg = tol_mm * s->weight_mm_per_deg;
    candidate c[HP_LEVEL_COUNT_];
    memset(c, 0, sizeof c); /* every field read is set below; zeros keep the rest defined */
    const int n = hpi_level_n_geometries + 1;
    const int nominal = is_nominal(s->auto_pose);
    hpi_fidelity_ref ref;
    hp_error e = hpi_fidelity_open(&p->L, &s->load, 0.0, &ref);
    int shared = -1; /* nominal: the contact candidate whose measurement the others share */
    int pick = -1, meets = 0;
    for (int i = 0; i < n && !meets; ++i) {
        candidate *x = &c[i];
        x->level = i < hpi_level_n_geometries ? hpi_level_geometries[i] : HP_LEVEL_LOAD;
        x->bound_mm = 0.0;
        x->scaled = NAN;
        int measured = 0;
        double b = 0.0;
        if (e != HP_OK) {
            /* no reference: nothing is measured */
        } else if (x->level == HP_LEVEL_LOAD) {
            measured = measure_load(p, layout, &ref, x) == 0;
        } else if (hpi_contact_error_bound_g(&p->L, &p->G, x->level, s->auto_trans, s->auto_rot,
                                             &b) == HP_OK) {
            x->bound_mm = b * 1e3;
            if (!nominal) measured = measure_contact(p, layout, plan_at, x->level, &ref, x) == 0;
            else if (shared >= 0) x->m = c[shared].m, measured = 1;
            else {
                measured = measure_nominal(p, &ref, x) == 0;
                if (measured) shared = i;
            }
        }
        if (measured)
            x->scaled = fmax((x->m.pose_mm + x->bound_mm) / tol_mm, x->m.pose_deg / tol_deg);
        if (x->scaled <= 1.0) pick = i, meets = 1;
    }
    hpi_fidelity_close(&ref);
    /* No level meets it and the load level could not be planned (its refusal, say that the
     * bladders cannot carry the head): the load level, whose create then refuses it by name,
     * rather than a contact level that leaves the weight out in silence. */
    if (!meets && isnan(c[n - 1].scaled)) pick = n - 1;
    for (int i = 0; i < n && !meets && !(pick == n - 1 && isnan(c[pick].scaled)); ++i) {
        if (isnan(c[i].scaled)) continue;
        if (pick < 0 || c[i].scaled < c[pick].scaled ||
            (c[i].scaled == c[pick].scaled && !(c[i].m.carried < c[pick].m.carried)))
            pick = i;
    }
    if (pick < 0) return HP_OK;
    *chosen = c[pick].level;
    /* "auto chose L by model error at POSE (tolerance T mm, D deg): A, B exceed it; L ...
     * meets it" or "...: A, B, C and L exceed it; L has the smallest" */
    char pose[160];
    pose_text(s->auto_pose, pose, sizeof pose);
    size_t at = 0;
    int w = snprintf(why, len, "auto chose %s by model error at %s (tolerance %g mm, %g deg): ",
                     hp_level_name(c[pick].level), pose, tol_mm, tol_deg);
    at = w > 0 ? (size_t)w : 0;
    const int last = meets ? pick : n - 1;
    for (int i = 0; i <= last && at < len; ++i) {
        if (meets && i == pick && i > 0)
            at += (size_t)snprintf(why + at, len - at, " exceed%s it; ", pick > 1 ? "" : "s");
        else if (i > 0) at += (size_t)snprintf(why + at, len - at, ", ");
        if (at >= len) break;
        w = candidate_text(&c[i], why + at, len - at);
        if (w < 0) break;
        at += (size_t)w;
    }
    if (at < len) {
        if (meets) snprintf(why + at, len - at, " meets it");
        else if (isnan(c[pick].scaled))
            snprintf(why + at, len - at, ": none meets it; %s models the weight",
                     hp_level_name(c[pick].level));
        else
            snprintf(why + at, len - at, " exceed it; %s has the %s", hp_level_name(c[pick].level),
                     isfinite(c[pick].scaled) ? "smallest" : "most weight carried");
    }
    return HP_OK;
}

hp_error hpi_planner_resolve_level(hp_planner *p, const hp_layout *layout, hpi_plan_at_fn plan_at,
                                   hp_diag *d)
{
    const hp_settings *s = &p->s;
    p->level = s->level;
    p->level_why[0] = '\0';
    const int has_load = !(s->load.mass == 0.0); /* hp_settings_validate checked it */
    char load_why[32] = "";                      /* why the geometry decides a load's level */
    if (s->level == HP_LEVEL_AUTO && has_load) {
        /* A pose auto cannot plan is refused by name, as hp_plan would refuse it. */
        hp_identifiable id;
        char err[HP_DIAG_MAX];
        if (!is_nominal(s->auto_pose) && hp_layout_identify(&p->L, &id) == HP_OK &&
            !hpi_plan_range_ok(&id, s->auto_pose, HPI_AUTO_POSE_NAME, err))
            return hp_diag_set(d, HP_ERR_INVALID, "%s", err);
        hp_level chosen = HP_LEVEL_AUTO;
        hp_error e = auto_by_model_error(p, layout, plan_at, &chosen, p->level_why,
                                         sizeof p->level_why);
        if (e != HP_OK)
            return hp_diag_set(d, e, "level: auto could not compare the levels' model error (%s)",
                               hp_error_message(e));
        p->level = chosen;
        if (chosen == HP_LEVEL_AUTO) { /* nothing measured: the geometry decides, said so */
            snprintf(load_why, sizeof load_why, "model error not measured; ");
            p->level_why[0] = '\0';
        } else if (chosen != HP_LEVEL_LOAD) {
            return HP_OK;
        }
    }
    if (p->level == HP_LEVEL_LOAD) {
        /* The load model, built once: the load level plans with it. */
        p->load = calloc(1, sizeof *p->load);
        if (!p->load) return hp_diag_set(d, HP_ERR_NOMEM, "planner: out of memory");
        return hpi_load_level_model(p->load, layout, s, d);
    }
    if (p->level != HP_LEVEL_AUTO) return HP_OK;
    hp_error e = hpi_contact_auto_g(&p->L, &p->G, s->level_tolerance, s->auto_trans, s->auto_rot,
                                    &p->level);
    if (e != HP_OK)
        return hp_diag_set(d, e, "level: auto could not choose a contact level (%s)",
                           hp_error_message(e));
    char why[256]; /* the bounds' line (~150 characters) */
    contact_why(p, p->level, why, sizeof why);
    /* Without a load the levels differ by their geometry alone: the reason says so. */
    snprintf(p->level_why, sizeof p->level_why, "%s%s%s", load_why, why,
             has_load ? ""
                      : "; no load stated, so the weight of the head is left out (no sag, no "
                        "indentation) and the levels differ by geometry alone");
    return HP_OK;
}

hp_error hp_planner_level_choice(const hp_planner *p, char *why, size_t len)
{
    if (!why || !len) return HP_ERR_NULL;
    why[0] = '\0';
    if (!p) return HP_ERR_NULL;
    if (!p->built) return HP_ERR_STATE;
    snprintf(why, len, "%s", p->level_why);
    return HP_OK;
}
