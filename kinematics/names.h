/* The kinematics module's name tables (common/names.h), each in enum order, and the table of
 * contact geometries. */
#ifndef HP_KINEMATICS_NAMES_H
#define HP_KINEMATICS_NAMES_H

#include "headplan/hp_contact.h"

#include <stddef.h>

extern const char *const hpi_level_words[]; /* every level, auto and load after the geometries */
extern const char *const hpi_head_shape_words[];
extern const char *const hpi_load_law_words[]; /* hp_load_law: the load model's contact laws */

/* The contact geometries (hp_level_is_geometry), in the order auto tries them: cheapest
 * first, the exact one (error bound 0) last. */
extern const hp_level hpi_level_geometries[];
extern const int hpi_level_n_geometries;

/* The geometries' words in that order, "linear, plane or surface", into buf (len bytes,
 * always terminated), for messages and help texts. Returns buf. */
const char *hpi_level_geometry_names(char *buf, size_t len);

#endif
