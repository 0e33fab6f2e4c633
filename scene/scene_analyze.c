/* The layout analysis of a scene (hp_scene.h, hp_scene_analyze): the one sequence behind
 * `headplan analyze` and the Python module's analyze(). */
#include "headplan/hp_scene.h"

#include <math.h>
#include <string.h>

hp_error hp_scene_analyze(const hp_layout *L, const hp_settings *s, hp_scene_analysis *out,
                          hp_diag *d)
{
    if (!L || !s || !out) return hp_diag_set(d, HP_ERR_NULL, "analysis: NULL argument");
    memset(out, 0, sizeof *out);
    out->requested = s->level;
    out->trans = s->auto_trans;
    out->rot = s->auto_rot;
    hp_error e = HP_OK;
    for (int l = 0; l < HP_LEVEL_COUNT_; ++l) {
        out->bound[l] = NAN;
        if (!e && hp_level_is_geometry((hp_level)l))
            e = hp_contact_error_bound(L, (hp_level)l, out->trans, out->rot, &out->bound[l]);
    }
    if (!e) e = hp_contact_auto(L, s->level_tolerance, out->trans, out->rot, &out->auto_level);
    if (e) return hp_diag_set(d, e, "error bounds: %s", hp_error_message(e));
    out->level = s->level == HP_LEVEL_AUTO ? out->auto_level : s->level;
    if ((e = hp_layout_identify(L, &out->id)))
        return hp_diag_set(d, e, "identifiable range: %s", hp_error_message(e));
    if ((e = hp_layout_analyze(L, out->level, &out->an)))
        return hp_diag_set(d, e, "layout analysis: %s", hp_error_message(e));
    /* The reach reported is the planner's (its caps, its commanded components), so that a
     * plan at 99 % of it reaches and at 101 % binds a limit. */
    hp_settings ps = *s;
    ps.level = out->level;
    hp_planner *p = NULL;
    hp_diag pd = {{0}};
    e = hp_planner_create(L, &ps, &p, &pd);
    if (!e) e = hp_planner_reach(p, out->an.reach);
    hp_planner_destroy(p);
    if (e) return hp_diag_set(d, e, "reach: %s", pd.text[0] ? pd.text : hp_error_message(e));
    return HP_OK;
}
