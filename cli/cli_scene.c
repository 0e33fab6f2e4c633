/* Scene loading and planner settings for the subcommands (see cli_scene.h). */
#include "cli/cli_scene.h"
#include "cli/cli_args.h"
#include "cli/exit_codes.h"

#include <stdlib.h>

int cli_load_scene(const char *cmd, const char *path, const char *study_msg, hp_scene **out)
{
    *out = NULL;
    hp_diag d = {{0}};
    if (hp_scene_file_kind(path) == HP_SCENE_BLADDER) {
        hp_bladder_study st;
        hp_error e = hp_study_load(path, &st, &d);
        if (e != HP_OK)
            return cli_fail(e == HP_ERR_IO ? CLI_EXIT_NOINPUT : CLI_EXIT_DATAERR, cmd, "%s",
                            d.text);
        return cli_fail(CLI_EXIT_DATAERR, cmd,
                        study_msg ? study_msg
                                  : "%s: a single-bladder study has no layout (see headplan "
                                    "ik/fk)",
                        path);
    }
    hp_scene *sc = calloc(1, sizeof *sc);
    if (!sc) return cli_fail(CLI_EXIT_SOFTWARE, cmd, "out of memory");
    hp_error e = hp_scene_load(path, sc, &d);
    if (e != HP_OK) {
        free(sc);
        return cli_fail(e == HP_ERR_IO ? CLI_EXIT_NOINPUT : CLI_EXIT_DATAERR, cmd, "%s",
                           d.text);
    }
    *out = sc;
    return 0;
}

int cli_settings(const char *cmd, const hp_scene *sc, const char *backend,
                    const char *level, hp_settings *s)
{
    hp_diag d = {{0}};
    if (hp_scene_settings(sc, s, &d) != HP_OK)
        return cli_fail(CLI_EXIT_DATAERR, cmd, "%s", d.text);
    if (backend && hp_backend_parse(backend, &s->backend) != HP_OK)
        return cli_fail(CLI_EXIT_USAGE, cmd,
                           "--backend: unknown backend '%s' (realtime, ipopt, nlopt-slsqp, "
                           "nlopt-cobyla)",
                           backend);
    if (level && hp_level_parse(level, &s->level) != HP_OK)
        return cli_fail(CLI_EXIT_USAGE, cmd,
                           "--level: unknown level '%s' (linear, plane, surface, auto)", level);
    return 0;
}
