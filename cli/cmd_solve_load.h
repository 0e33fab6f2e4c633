/* headplan solve at the load level (docs/load.md). */
#ifndef CLI_CMD_SOLVE_LOAD_H
#define CLI_CMD_SOLVE_LOAD_H

#include "cli/cli_args.h"
#include "headplan/headplan.h"

#include <stddef.h>

/* Which level a scene gets, for analyze's note: the library's decision (hp_scene_plan_level)
 * with level_arg = --level (NULL: the scene's). *use_load gets 1 for the
 * load level; why (len bytes) the reason. Prints and returns an exit status on error (64:
 * --level load on a scene without a `load` section; 65: its load cannot be modelled), 0
 * otherwise (an unknown --level is left to cli_settings to name). */
int cli_load_level(const char *cmd, const hp_scene *sc, const char *level_arg, int *use_load,
                   char *why, size_t len);

/* For the subcommands that plan at the kinematic levels only (render): 0 when the
 * scene with level_arg (--level; NULL: the scene's model.level) is planned kinematically,
 * else prints and returns 64 (--level load) or 65 (the scene's model.level: load, or auto
 * choosing load for its predicted sag), with instead (what the user can do) in the
 * message. headplan solve plans such a scene with the head's weight: planning it
 * kinematically instead would give other pressures for the same scene and correction. */
int cli_kinematic_only(const char *cmd, const hp_scene *sc, const char *level_arg,
                       const char *instead);

/* Prints why hp_planner_create refused the settings of scene `name` (diag d, error e) and
 * returns the exit status: 64 naming --backend when backend_opt (its value) chose a backend
 * the planner refused for the level (the load level's backends and tie-breakers), else 65
 * for bad data, 70 otherwise. */
int cli_planner_refused(const char *cmd, const char *name, const char *backend_opt, hp_error e,
                        const hp_diag *d);

/* Plans desired[6] (SI) with planner p at the load level (built from settings s, for scene
 * sc) and prints the answer (table or JSON): pressures, forces, binding limits, equilibrium
 * residual, compliance, forward statics' round trip and the model error (cli_fidelity.h). from names where desired came from
 * ("--correction" or "correction") in the message of a refused one. Returns the exit
 * status (0 reached, 1 closest, 65 a correction outside the identifiable range, 70 no
 * confirmed answer). */
int cli_solve_load(const char *cmd, const hp_scene *sc, const char *name, hp_planner *p,
                   const hp_settings *s, const double desired[6], const char *from, int json,
                   const char *why);

/* When a bladder of L has a stress limit: a table of every bladder's hoop stress at the
 * inner surface (kPa) beside its limit. Prints nothing otherwise. */
void cli_print_hoop(const hp_layout *L, const hp_result *r);

#endif
