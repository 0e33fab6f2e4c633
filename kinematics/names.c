/* The kinematics module's name tables and the name/parse calls made from them. Parsing,
 * messages and the command line's help all read these tables (hp_scene_level_names adds the
 * scene's "load"). */
#include "headplan/hp_contact.h"
#include "common/names.h"
#include "kinematics/names.h"

const char *const hpi_level_words[] = {"linear", "plane", "surface", "auto", "load", NULL};
_Static_assert(sizeof hpi_level_words / sizeof *hpi_level_words == HP_LEVEL_LOAD + 2,
               "one word per level");

const char *const hpi_head_shape_words[] = {"sphere", "ellipsoid", NULL};

HP_NAMES_CALLS(hp_level, hpi_level_words, hp_level_name, hp_level_parse)

HP_NAMES_CALLS(hp_head_shape, hpi_head_shape_words, hp_head_shape_name, hp_head_shape_parse)
