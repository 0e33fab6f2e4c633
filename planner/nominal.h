/* Internal: the pressures that hold a layout's nominal pose, the one computation behind
 * hp_planner_nominal_pressures and hp_horizon_nominal_pressures. */
#ifndef HP_PLANNER_NOMINAL_H
#define HP_PLANNER_NOMINAL_H

#include "headplan/hp_layout.h"
#include "kinematics/kin_geom.h"

/* Every bladder's pressure at its nominal contact distance (G derived from L). Returns HP_OK,
 * or the bladder model's error with *bad set to the failing bladder (pressures before it
 * are written, the rest untouched). */
hp_error hpi_nominal_pressures_of(const hp_layout *L, const hp_geom *G, double *pressures,
                                  int *bad);

#endif
