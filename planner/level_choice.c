/* The planner's level, resolved once at create over all four levels (hp_planner_create), and
 * why (hp_planner_level_choice): the one text that solve, batch's metadata record and the
 * Python module give for a level auto chose. */
#include "planner/planner_internal.h"
#include "common/units.h"
#include "kinematics/kin_geom.h"
#include "kinematics/names.h"

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

hp_error hpi_planner_resolve_level(hp_planner *p, const hp_layout *layout, hp_diag *d)
{
    const hp_settings *s = &p->s;
    p->level = s->level;
    p->level_why[0] = '\0';
    const int has_load = !(s->load.mass == 0.0); /* hp_settings_validate checked it */
    char load_why[224] = ""; /* the sag line of hp_load_auto_choose (~80 characters) */
    if (s->level == HP_LEVEL_LOAD || (s->level == HP_LEVEL_AUTO && has_load)) {
        /* The load model, built once: auto decides on it, the load level plans with it. */
        p->load = calloc(1, sizeof *p->load);
        if (!p->load) return hp_diag_set(d, HP_ERR_NOMEM, "planner: out of memory");
        hp_error e = hpi_load_level_model(p->load, layout, s, d);
        if (e != HP_OK) return e;
        if (s->level == HP_LEVEL_AUTO) {
            /* The load level when the sag a kinematic plan would leave exceeds the
             * tolerance, else the contact level auto chooses below. */
            int use_load = 0;
            e = hp_load_auto_choose(&p->load->M, s->level_tolerance, &use_load, NULL, load_why,
                                    sizeof load_why);
            if (e != HP_OK)
                return hp_diag_set(d, e, "level: auto could not decide on the load level (%s)",
                                   hp_error_message(e));
            if (use_load) {
                p->level = HP_LEVEL_LOAD;
                snprintf(p->level_why, sizeof p->level_why, "%s", load_why);
            } else {
                free(p->load);
                p->load = NULL;
            }
        }
    }
    if (p->level != HP_LEVEL_AUTO) return HP_OK;
    hp_error e = hpi_contact_auto_g(&p->L, &p->G, s->level_tolerance, s->auto_trans, s->auto_rot,
                                    &p->level);
    if (e != HP_OK)
        return hp_diag_set(d, e, "level: auto could not choose a contact level (%s)",
                           hp_error_message(e));
    char why[256]; /* the bounds' line (~150 characters) */
    contact_why(p, p->level, why, sizeof why);
    /* A load kept kinematic says so first: the sag that did not call for the load level. */
    snprintf(p->level_why, sizeof p->level_why, "%s%s%s", load_why, *load_why ? "; " : "", why);
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
