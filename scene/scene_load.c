/* The `load` section of a layout scene: what part of the head's weight the bladders carry,
 * where its centre of mass is, which way gravity points, the contact law, and the load
 * planner's choices. */
#include "headplan/hp_planner.h"
#include "scene/scene_parts.h"

#include <math.h>
#include <string.h>

hp_error sp_load(const sr_ctx *c, const yt_node *node, hp_scene *s)
{
    static const char *const KEYS[] = {"carried_fraction", "com_mm", "gravity_dir", "geometry",
                                       "tiebreak",         "law",    NULL};
    hp_error e = sr_map(c, node, "load", KEYS, NULL);
    if (e) return e;
    const hp_head *h = &s->layout.head;
    if (!(h->mass > 0))
        return sr_fail(c, node, "load", HP_ERR_INVALID,
                       "needs the head's mass (head.mass_kg) to know what the bladders carry");
    const yt_node *n;
    double f;
    if ((e = sr_require(c, node, "load", "carried_fraction", &n))) return e;
    if ((e = sr_number(c, n, "load.carried_fraction", &f))) return e;
    if (!(f > 0 && f <= 1))
        return sr_fail(c, n, "load.carried_fraction", HP_ERR_INVALID,
                       "must be in (0, 1]: the part of the head's weight on the bladders "
                       "(got %g)",
                       f);
    hp_load_spec_default(h, &s->load);
    s->load.mass = f * h->mass;
    s->load_fraction = f;
    if ((n = yt_map_get(node, "com_mm"))) {
        double x[3];
        if ((e = sr_vector(c, n, "load.com_mm", 3, x))) return e;
        for (int i = 0; i < 3; ++i) s->load.com[i] = x[i] * 1e-3;
    }
    if ((n = yt_map_get(node, "gravity_dir"))) {
        double g[3];
        if ((e = sr_vector(c, n, "load.gravity_dir", 3, g))) return e;
        /* Only the direction counts: divided by its largest component first, so that the
         * squares of 1e308 (overflow) or of 1e-200 (underflow) do not make a direction
         * "zero". */
        double big = fmax(fabs(g[0]), fmax(fabs(g[1]), fabs(g[2])));
        if (!(big > 0))
            return sr_fail(c, n, "load.gravity_dir", HP_ERR_INVALID,
                           "must be a non-zero direction (unitless; scaled to 9.80665 m/s^2)");
        for (int i = 0; i < 3; ++i) g[i] /= big;
        double len = sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]); /* in [1, √3] */
        for (int i = 0; i < 3; ++i) s->load.gravity[i] = HP_GRAVITY * g[i] / len;
    }
    s->load_geometry = HP_LEVEL_SURFACE;
    if ((n = yt_map_get(node, "geometry"))) {
        const char *GEOMS[HP_LEVEL_AUTO + 1]; /* the contact levels but auto, NULL */
        for (int l = HP_LEVEL_LINEAR; l < HP_LEVEL_AUTO; ++l) GEOMS[l] = hp_level_name((hp_level)l);
        GEOMS[HP_LEVEL_AUTO] = NULL;
        char name[16];
        if ((e = sr_word(c, n, "load.geometry", "geometry", GEOMS, name, sizeof name))) return e;
        (void)hp_level_parse(name, &s->load_geometry); /* cannot fail: name is in GEOMS */
    }
    s->load_tiebreak = HP_TIE_LEAST_SQUEEZE;
    if ((n = yt_map_get(node, "tiebreak"))) {
        const char *TIES[HP_TIE_COUNT_ + 1]; /* the tie-breaker table's words, NULL */
        for (int i = 0; i < HP_TIE_COUNT_; ++i)
            TIES[i] = hp_load_tiebreak_name((hp_load_tiebreak)i);
        TIES[HP_TIE_COUNT_] = NULL;
        char name[16];
        hp_load_tiebreak t;
        if ((e = sr_word(c, n, "load.tiebreak", "tie-breaker", TIES, name, sizeof name))) return e;
        (void)hp_load_tiebreak_parse(name, &t); /* cannot fail: name is in TIES */
        s->load_tiebreak = (int)t;
    }
    if ((n = yt_map_get(node, "law"))) {
        const char *LAWS[HP_LOAD_LAW_COUNT_ + 1]; /* the contact law table's words, NULL */
        for (int i = 0; i < HP_LOAD_LAW_COUNT_; ++i) LAWS[i] = hp_load_law_name((hp_load_law)i);
        LAWS[HP_LOAD_LAW_COUNT_] = NULL;
        char name[16];
        if ((e = sr_word(c, n, "load.law", "contact law", LAWS, name, sizeof name))) return e;
        (void)hp_load_law_parse(name, &s->load.law); /* cannot fail: name is in LAWS */
    }
    s->has_load = 1;
    return HP_OK;
}
