/* Why a planner plans at its level (hp_planner_level_choice): the one text that solve, batch's
 * metadata record and the Python module give for a level auto chose. */
#include "planner/planner_internal.h"
#include "common/units.h"
#include "kinematics/kin_geom.h"

#include <math.h>
#include <stdio.h>

hp_error hp_planner_level_choice(const hp_planner *p, char *why, size_t len)
{
    if (!why || !len) return HP_ERR_NULL;
    why[0] = '\0';
    if (!p) return HP_ERR_NULL;
    if (!p->built) return HP_ERR_STATE;
    if (p->s.level != HP_LEVEL_AUTO) return HP_OK;
    const hp_settings *s = &p->s;
    const hp_level chosen = p->level;
    /* The bounds auto compared (hp_contact_auto): every cheaper level's exceeds the
     * tolerance, the chosen one's (0 for surface) meets it. */
    char range[96];
    snprintf(range, sizeof range, "model.tolerance_mm %g for corrections up to %g mm, %g deg",
             s->level_tolerance * 1e3, s->auto_trans * 1e3, s->auto_rot * HP_DEG_PER_RAD);
    double b[2] = {NAN, NAN};
    for (int l = HP_LEVEL_LINEAR; l < (int)chosen && l <= HP_LEVEL_PLANE; ++l)
        if (hp_contact_error_bound_g(&p->L, &p->G, (hp_level)l, s->auto_trans, s->auto_rot,
                                     &b[l]) != HP_OK)
            b[l] = NAN;
    const char *name = hp_level_name(chosen);
    if (chosen == HP_LEVEL_SURFACE)
        snprintf(why, len, "auto chose %s: the error bounds of linear (%.3g mm) and plane "
                 "(%.3g mm) exceed %s", name, b[0] * 1e3, b[1] * 1e3, range);
    else if (chosen == HP_LEVEL_PLANE)
        snprintf(why, len, "auto chose %s: the error bound of linear (%.3g mm) exceeds %s; "
                 "plane's meets it", name, b[0] * 1e3, range);
    else
        snprintf(why, len, "auto chose %s: its error bound meets %s", name, range);
    return HP_OK;
}
