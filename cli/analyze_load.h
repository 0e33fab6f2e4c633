/* headplan analyze: the load section (docs/load.md). */
#ifndef CLI_ANALYZE_LOAD_H
#define CLI_ANALYZE_LOAD_H

#include "headplan/headplan.h"

#include <jansson.h>

/* The head's load at the nominal pose for a scene whose head states a mass: the sag a
 * kinematic plan would leave, auto's choice, and (when the layout can hold the head there)
 * the holding pressures' stiffness, stability, weakest direction and compliance. Without a
 * `load` section the whole head mass under gravity along −Z is assumed and said so.
 * Prints nothing for a scene without mass. */
void cli_analyze_load_text(const hp_scene *sc);
/* The same as a JSON object (NULL for a scene without mass). */
json_t *cli_analyze_load_json(const hp_scene *sc);

#endif
