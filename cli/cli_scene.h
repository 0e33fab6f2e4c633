/* Loading a layout scene and turning it into planner settings: shared by solve, batch and
 * bench so that every subcommand reads a scene the same way. */
#ifndef CLI_SCENE_H
#define CLI_SCENE_H

#include "headplan/headplan.h"
#include "headplan/hp_planner.h"

#include <stddef.h>

/* Reads the whole input `what` at path ("-": standard input, <stdin> in messages) into *buf
 * (malloc'd; the caller frees it) and its length into *len, at most max bytes (beyond: 65,
 * "larger than the LIMIT limit"). 66 when it cannot be opened or read, 73 when standard
 * output is that input; 0 on success. */
int cli_read_input(const char *cmd, const char *what, const char *path, size_t max,
                   const char *limit, char **buf, size_t *len);

/* Loads the layout scene SCENE ("-": standard input, named <stdin> in messages; allocated
 * into *out; free() it). Prints the parser's message
 * and returns 66 (cannot open) or 65 (malformed) on failure. A single-bladder study is read
 * as one (its own errors first), then refused with 65 and study_msg (a format with one %s,
 * the path; NULL: "a single-bladder study has no layout (see headplan ik/fk)"). Returns 0
 * on success. */
int cli_load_scene(const char *cmd, const char *path, const char *study_msg, hp_scene **out);

/* The same, and (when bytes is not NULL) the very bytes parsed in *bytes (malloc'd; the
 * caller frees it) and their count in *nbytes: the file is read once, so a scene on a pipe
 * parses like a file, and a hash of *bytes is of what was planned. */
int cli_load_scene_text(const char *cmd, const char *path, const char *study_msg, hp_scene **out,
                        char **bytes, size_t *nbytes);

/* A correction given on the command line (--correction, SI) becomes the scene's, so that
 * what the scene decides from it follows the correction planned: the settings' auto_pose
 * (hp_scene_settings: where auto measures the levels' model error, for a scene with a load)
 * and the level analyze and render report (hp_scene_plan_level). Prints and returns 65 when
 * the settings refuse it as auto_pose (not finite, beyond 1 m or pi rad), naming
 * --correction; else 0. */
int cli_scene_set_correction(const char *cmd, hp_scene *sc, const double desired[6]);

/* Settings from the scene's model and solver sections, then the command-line overrides
 * (backend/level: NULL = keep the scene's). Prints and returns 64 for an unknown name given
 * on the command line, 65 for one in the scene; 0 on success. */
int cli_settings(const char *cmd, const hp_scene *sc, const char *backend, const char *level,
                 hp_settings *s);

#endif
