/* The planner's level, resolved once at create over all four levels (hp_planner_create), and
 * why (hp_planner_level_choice): the one text that solve, batch's metadata record and the
 * Python module give for a level auto chose. */
#include "planner/planner_internal.h"
#include "common/units.h"
#include "kinematics/kin_geom.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Why auto chose contact level `chosen`: the bounds it compared (hp_contact_auto), every
 * cheaper level's exceeding the tolerance, the chosen one's (0 for surface) meeting it. */
static void contact_why(const hp_planner *p, hp_level chosen, char *why, size_t len)
{
    const hp_settings *s = &p->s;
    char range[96];
    snprintf(range, sizeof range, "model.tolerance_mm %g for corrections up to %g mm, %g deg",
             s->level_tolerance * 1e3, s->auto_trans * 1e3, s->auto_rot * HP_DEG_PER_RAD);
    double b[2] = {NAN, NAN};
    for (int l = HP_LEVEL_LINEAR; l < (int)chosen && l <= HP_LEVEL_PLANE; ++l)
        if (hpi_contact_error_bound_g(&p->L, &p->G, (hp_level)l, s->auto_trans, s->auto_rot,
                                      &b[l]) != HP_OK)
            b[l] = NAN;
    const char *name = hp_level_name(chosen);
    if (chosen == HP_LEVEL_SURFACE)
        snprintf(why, len,
                 "auto chose %s: the error bounds of linear (%.3g mm) and plane "
                 "(%.3g mm) exceed %s",
                 name, b[0] * 1e3, b[1] * 1e3, range);
    else if (chosen == HP_LEVEL_PLANE)
        snprintf(why, len,
                 "auto chose %s: the error bound of linear (%.3g mm) exceeds %s; "
                 "plane's meets it",
                 name, b[0] * 1e3, range);
    else snprintf(why, len, "auto chose %s: its error bound meets %s", name, range);
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
