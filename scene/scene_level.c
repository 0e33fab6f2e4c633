/* Which planner a scene is planned with (hp_scene.h, hp_scene_plan_level): the one decision
 * the command line and the Python module share, so a scene plans at the same level
 * whichever entry point loads it. */
#include "headplan/hp_planner.h"
#include "headplan/hp_scene.h"

#include <stdio.h>
#include <string.h>

const char *hp_scene_level_names(int with_load, const char *last, char *buf, size_t len)
{
    if (!buf || !len) return buf;
    buf[0] = '\0';
    const int n = with_load ? HP_LEVEL_LOAD + 1 : HP_LEVEL_AUTO + 1;
    size_t at = 0;
    for (int i = 0; i < n && at < len; ++i) {
        const char *name = hp_level_name((hp_level)i);
        const char *sep = i == 0 ? "" : i == n - 1 ? (last ? last : ", ") : ", ";
        int w = snprintf(buf + at, len - at, "%s%s", sep, name);
        if (w < 0) break;
        at += (size_t)w;
    }
    return buf;
}

hp_error hp_scene_plan_level(const hp_scene *sc, const char *level, int *use_load, char *why,
                             size_t len, hp_level_refusal *refused, hp_diag *diag)
{
    if (refused) *refused = HP_LEVEL_REFUSED_NONE;
    if (!sc || !use_load) return hp_diag_set(diag, HP_ERR_NULL, "scene level: NULL argument");
    *use_load = 0;
    if (why && len) why[0] = '\0';
    hp_level parsed = HP_LEVEL_AUTO;
    int asked = level ? strcmp(level, HP_SCENE_LEVEL_LOAD) == 0 : sc->level_load;
    if (level && !asked && hp_level_parse(level, &parsed) != HP_OK) {
        if (refused) *refused = HP_LEVEL_REFUSED_UNKNOWN;
        char names[96];
        return hp_diag_set(diag, HP_ERR_INVALID, "level: unknown level '%s' (%s)", level,
                           hp_scene_level_names(1, ", ", names, sizeof names));
    }
    int automatic = level ? parsed == HP_LEVEL_AUTO : sc->level == HP_LEVEL_AUTO;
    if (asked && !sc->has_load) {
        if (refused) *refused = HP_LEVEL_REFUSED_NO_LOAD;
        return hp_diag_set(diag, HP_ERR_INVALID,
                           "level: load needs a scene with a 'load' section (%s has none)",
                           sc->file);
    }
    if (asked) {
        *use_load = 1;
        if (why && len)
            snprintf(why, len, "load: asked for by %s",
                     level ? "the caller's level" : "model.level");
        return HP_OK;
    }
    if (!automatic || !sc->has_load) return HP_OK;
    /* auto on a scene that states its load: the planner's own decision (hp_planner_level_for,
     * the code hp_planner_create runs), so that this answer and the level solve, batch and
     * Python plan at are one. */
    hp_settings s;
    hp_error e = hp_scene_settings(sc, &s, diag);
    if (e) return e;
    s.level = HP_LEVEL_AUTO;
    hp_level chosen = HP_LEVEL_AUTO;
    if ((e = hp_planner_level_for(&sc->layout, &s, &chosen, why, len, diag))) return e;
    *use_load = chosen == HP_LEVEL_LOAD;
    return HP_OK;
}

hp_error hp_scene_kinematic_only(const hp_scene *sc, const char *level, const char *who,
                                 hp_level_refusal *refused, hp_diag *diag)
{
    if (refused) *refused = HP_LEVEL_REFUSED_NONE;
    if (!sc || !who) return hp_diag_set(diag, HP_ERR_NULL, "scene level: NULL argument");
    int use_load = 0;
    char why[256];
    hp_level_refusal r = HP_LEVEL_REFUSED_NONE;
    hp_diag d = {{0}};
    hp_error e = hp_scene_plan_level(sc, level, &use_load, why, sizeof why, &r, &d);
    if (refused) *refused = r;
    if (e && r != HP_LEVEL_REFUSED_NONE) return hp_diag_set(diag, e, "%s", d.text);
    if (e)
        return hp_diag_set(diag, e, "%s: load: %s", sc->file,
                           d.text[0] ? d.text : hp_error_message(e));
    if (!use_load) return HP_OK;
    if (refused) *refused = HP_LEVEL_REFUSED_LOAD;
    /* What to do instead is the caller's to append: the diag's fixed size keeps room for a
     * long path. */
    return hp_diag_set(diag, HP_ERR_DOMAIN,
                       "%s: the scene is planned at the load level (%s), which %s does not "
                       "plan: it would plan without the head's weight and disagree with solve",
                       sc->file, why, who);
}
