/* The kinematics module's name tables and the name/parse calls made from them. Parsing,
 * messages and the command line's help all read these tables (hp_scene_level_names adds the
 * scene's "load"). */
#include "headplan/hp_contact.h"
#include "headplan/hp_load.h"
#include "common/names.h"
#include "kinematics/names.h"

const char *const hpi_level_words[] = {"linear", "plane", "surface", "auto", "load", NULL};
_Static_assert(sizeof hpi_level_words / sizeof *hpi_level_words == HP_LEVEL_COUNT_ + 1,
               "one word per level");

/* The contact geometries in the order auto tries them: cheapest first, the exact distance
 * (whose error bound is 0, so that auto always ends on it) last. A new geometry is one entry
 * here, at its place by cost. */
const hp_level hpi_level_geometries[] = {HP_LEVEL_LINEAR, HP_LEVEL_PLANE, HP_LEVEL_SURFACE};
const int hpi_level_n_geometries = (int)(sizeof hpi_level_geometries /
                                         sizeof *hpi_level_geometries);

const char *const hpi_head_shape_words[] = {"sphere", "ellipsoid", NULL};

const char *const hpi_load_law_words[] = {"fem", "cap", NULL};
_Static_assert(sizeof hpi_load_law_words / sizeof *hpi_load_law_words == HP_LOAD_LAW_COUNT_ + 1,
               "one word per load law");

HP_NAMES_CALLS(hp_level, hpi_level_words, hp_level_name, hp_level_parse)

HP_NAMES_CALLS(hp_head_shape, hpi_head_shape_words, hp_head_shape_name, hp_head_shape_parse)

HP_NAMES_CALLS(hp_load_law, hpi_load_law_words, hp_load_law_name, hp_load_law_parse)

int hp_level_is_geometry(hp_level l)
{
    for (int i = 0; i < hpi_level_n_geometries; ++i)
        if (hpi_level_geometries[i] == l) return 1;
    return 0;
}

const char *hpi_level_geometry_names(char *buf, size_t len)
{
    const char *words[sizeof hpi_level_geometries / sizeof *hpi_level_geometries + 1];
    for (int i = 0; i < hpi_level_n_geometries; ++i)
        words[i] = hp_level_name(hpi_level_geometries[i]);
    words[hpi_level_n_geometries] = NULL;
    return hpi_names_join(words, " or ", buf, len);
}
