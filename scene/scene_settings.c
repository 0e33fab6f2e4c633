/* A loaded scene -> planner settings: the one place this happens (see hp_scene.h). */
#include "headplan/hp_scene.h"

#include <string.h>

hp_error hp_scene_settings(const hp_scene *sc, hp_settings *out, hp_diag *diag)
{
    if (!sc || !out) return hp_diag_set(diag, HP_ERR_NULL, "scene settings: NULL argument");
    hp_settings s;
    hp_settings_default(&s);
    s.backend = sc->backend;
    /* `model.level: load` plans the load level; sc->level is then the surface level a
     * caller analysing the scene's contact geometry uses. */
    s.level = sc->level_load ? HP_LEVEL_LOAD : sc->level;
    if (sc->has_load) {
        s.load = sc->load;
        s.load_geometry = sc->load_geometry;
        s.load_tiebreak = (hp_load_tiebreak)sc->load_tiebreak;
    }
    s.level_tolerance = sc->level_tolerance;
    if (sc->has_auto_range) {
        s.auto_trans = sc->auto_trans;
        s.auto_rot = sc->auto_rot;
    }
    s.tolerance = sc->tolerance;
    s.max_iter = sc->max_iter;
    s.max_time = sc->max_time;
    s.weight_mm_per_deg = sc->weight_mm_per_deg;
    s.restarts = sc->restarts;
    /* auto measures the levels' model error at the correction the scene plans (it matters
     * only with a load: without one auto compares geometry bounds over its range). */
    if (sc->has_load && sc->has_correction) memcpy(s.auto_pose, sc->correction, sizeof s.auto_pose);
    hp_error e = hp_settings_validate(&s, diag);
    if (e != HP_OK) return e;
    *out = s;
    return HP_OK;
}
