/* The planner's level, resolved once at create over all four levels (hp_planner_create), and
 * why (hp_planner_level_choice): the one text that solve, batch's metadata record and the
 * Python module give for a level auto chose. */
#include "planner/planner_internal.h"
#include "common/units.h"
#include "kinematics/kin_geom.h"
#include "kinematics/names.h"
#include "planner/model_error.h"
#include "planner/nominal.h"

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
    snprintf(why, len, "auto chose %s: the error bound%s of %s %s %s%s%s%s", name,
             cheaper > 1 ? "s" : "", list, cheaper > 1 ? "exceed" : "exceeds", range,
             exact ? "" : "; ", exact ? "" : name, exact ? "" : "'s meets it");
}

/* One candidate of auto by model error: its error at the nominal pose against the reference
 * (model_error.h), a contact level's geometry bound over the auto range [mm], and its
 * tolerance-scaled size (<= 1 meets the tolerance; +inf without a rest; NaN not measured). */
typedef struct candidate {
    hp_level level;
    hpi_fidelity_result m;
    double bound_mm;
    double scaled;
} candidate;

/* The load level's plan of the nominal pose on a load level of its own (the planner's is
 * built after the level is known), measured against ref. 0 when measured. */
static int measure_load(const hp_planner *p, const hp_layout *layout, const hpi_fidelity_ref *ref,
                        hpi_fidelity_result *m)
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
        const double zero[6] = {0};
        if (hpi_load_level_model(L, layout, &s, NULL) == HP_OK &&
            hpi_load_level_build(L, &s, ops, err, NULL) == HP_OK &&
            hpi_load_level_plan(L, zero, &r) == HP_OK && hpi_fidelity_answered(r.status)) {
            double P[HP_MAX_BLADDERS];
            for (int k = 0; k < r.n; ++k) P[k] = r.bladders[k].pressure;
            hpi_fidelity_measure(ref, P, r.achieved, m);
            rc = 0;
        }
    }
    free(err);
    free(L);
    return rc;
}

/* "linear 1.07 mm, 0.342 deg (+1.56 mm geometry)", "surface no rest (0 % carried)",
 * "load not measured". */
static int candidate_text(const candidate *c, char *buf, size_t len)
{
    const char *name = hp_level_name(c->level);
    if (isnan(c->scaled)) return snprintf(buf, len, "%s not measured", name);
    if (!isfinite(c->m.pose_mm))
        return snprintf(buf, len, "%s no rest (%.0f %% carried)", name, 100.0 * c->m.carried + 0.0);
    if (c->bound_mm > 0)
        return snprintf(buf, len, "%s %.3g mm, %.3g deg (+%.3g mm geometry)", name, c->m.pose_mm,
                        c->m.pose_deg, c->bound_mm);
    return snprintf(buf, len, "%s %.3g mm, %.3g deg", name, c->m.pose_mm, c->m.pose_deg);
}

/* auto on settings that state a load: the cheapest level whose model error meets the
 * tolerance, else the smallest error (equal, unbounded errors: the most weight carried; the
 * dearer level on a full tie). The contact levels in their order (hpi_level_geometries), then
 * the load level. At the nominal pose every contact level's plan has the same pressures
 * (each bladder at its nominal contact distance), so one measurement serves them, and each
 * adds its geometry's error bound over the auto range (what the nominal pose cannot show).
 * A load level that cannot be planned, with nothing meeting the tolerance, is chosen all the
 * same (below). *chosen stays HP_LEVEL_AUTO (why untouched) only if no level is left. */
static hp_error auto_by_model_error(hp_planner *p, const hp_layout *layout, hp_level *chosen,
                                    char *why, size_t len)
{
    const hp_settings *s = &p->s;
    *chosen = HP_LEVEL_AUTO;
    const double tol_mm = s->level_tolerance * 1e3, tol_deg = tol_mm * s->weight_mm_per_deg;
    candidate c[HP_LEVEL_COUNT_];
    memset(c, 0, sizeof c); /* every field read is set below; zeros keep the rest defined */
    const int n = hpi_level_n_geometries + 1;
    hpi_fidelity_ref ref;
    hp_error e = hpi_fidelity_open(&p->L, &s->load, 0.0, &ref);
    double P[HP_MAX_BLADDERS];
    int bad = -1;
    const int kin = e == HP_OK && hpi_nominal_pressures_of(&p->L, &p->G, P, &bad) == HP_OK;
    hpi_fidelity_result nominal;
    const double zero[6] = {0};
    if (kin) hpi_fidelity_measure(&ref, P, zero, &nominal);
    for (int i = 0; i < n; ++i) {
        candidate *x = &c[i];
        x->level = i < hpi_level_n_geometries ? hpi_level_geometries[i] : HP_LEVEL_LOAD;
        x->bound_mm = 0.0;
        x->scaled = NAN;
        int measured = 0;
        if (x->level == HP_LEVEL_LOAD) {
            measured = e == HP_OK && measure_load(p, layout, &ref, &x->m) == 0;
        } else if (kin) {
            double b = 0.0;
            measured = hpi_contact_error_bound_g(&p->L, &p->G, x->level, s->auto_trans, s->auto_rot,
                                                 &b) == HP_OK;
            x->m = nominal;
            x->bound_mm = b * 1e3;
        }
        if (measured)
            x->scaled = fmax((x->m.pose_mm + x->bound_mm) / tol_mm, x->m.pose_deg / tol_deg);
    }
    hpi_fidelity_close(&ref);
    int pick = -1, meets = 0;
    for (int i = 0; i < n && pick < 0; ++i)
        if (c[i].scaled <= 1.0) pick = i, meets = 1;
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
    /* "auto chose L by model error at the nominal pose (tolerance T mm, D deg): A, B exceed
     * it; L ... meets it" or "...: A, B, C and L exceed it; L has the smallest" */
    size_t at = 0;
    int w = snprintf(why, len,
                     "auto chose %s by model error at the nominal pose (tolerance %g mm, "
                     "%g deg): ",
                     hp_level_name(c[pick].level), tol_mm, tol_deg);
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

hp_error hpi_planner_resolve_level(hp_planner *p, const hp_layout *layout, hp_diag *d)
{
    const hp_settings *s = &p->s;
    p->level = s->level;
    p->level_why[0] = '\0';
    const int has_load = !(s->load.mass == 0.0); /* hp_settings_validate checked it */
    char load_why[32] = "";                      /* why the geometry decides a load's level */
    if (s->level == HP_LEVEL_AUTO && has_load) {
        hp_level chosen = HP_LEVEL_AUTO;
        hp_error e = auto_by_model_error(p, layout, &chosen, p->level_why, sizeof p->level_why);
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
