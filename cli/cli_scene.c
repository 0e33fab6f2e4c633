/* Scene loading and planner settings for the subcommands (see cli_scene.h). */
#define _POSIX_C_SOURCE 200809L
#include "cli/cli_scene.h"
#include "cli/cli_args.h"
#include "cli/cli_outfile.h"
#include "cli/exit_codes.h"

#include "common/names.h"
#include "common/units.h"
#include "planner/names.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The file's bytes, read once (at most max; *buf malloc'd): the kind, the parse and the hash
 * all see the same bytes, so an input on a pipe or a process substitution (/dev/stdin,
 * <(...)) is read like a file instead of coming out empty on the second read. "-" is
 * standard input, named <stdin>. */
int cli_read_input(const char *cmd, const char *what, const char *path, size_t max,
                   const char *limit, char **buf, size_t *len)
{
    *buf = NULL;
    const int std = strcmp(path, "-") == 0;
    path = cli_name(path);
    FILE *f = std ? stdin : fopen(path, "rb");
    if (!f) return cli_fail(CLI_EXIT_NOINPUT, cmd, "%s: cannot open: %s", path, strerror(errno));
    int rc = cli_stdout_not_input(cmd, what, path, fileno(f), NULL);
    char *b = rc ? NULL : malloc(max + 1);
    if (!rc && !b) rc = cli_fail(CLI_EXIT_SOFTWARE, cmd, "out of memory");
    if (rc) {
        if (!std) fclose(f);
        return rc;
    }
    errno = 0;
    size_t n = fread(b, 1, max + 1, f);
    int failed = ferror(f), why = errno;
    if (!std) fclose(f);
    if (failed)
        rc = cli_fail(CLI_EXIT_NOINPUT, cmd, "%s: cannot read: %s", path,
                      why ? strerror(why) : "read error");
    else if (n > max)
        rc = cli_fail(CLI_EXIT_DATAERR, cmd, "%s: larger than the %s limit", path, limit);
    if (rc) {
        free(b);
        return rc;
    }
    *buf = b;
    *len = n;
    return 0;
}

int cli_load_scene_text(const char *cmd, const char *path, const char *study_msg, hp_scene **out,
                        char **bytes, size_t *nbytes)
{
    *out = NULL;
    char *text = NULL;
    size_t len = 0;
    int rc = cli_read_input(cmd, "scene", path, HP_SCENE_MAX_BYTES, "1 MiB", &text, &len);
    if (rc) return rc;
    path = cli_name(path);
    hp_diag d = {{0}};
    if (hp_scene_kind_of(text, len) == HP_SCENE_BLADDER) {
        hp_bladder_study st;
        hp_error e = hp_study_parse(text, len, path, &st, &d);
        free(text);
        if (e != HP_OK) return cli_fail(CLI_EXIT_DATAERR, cmd, "%s", d.text);
        return cli_fail(CLI_EXIT_DATAERR, cmd,
                        study_msg ? study_msg
                                  : "%s: a single-bladder study has no layout (see headplan "
                                    "ik/fk)",
                        path);
    }
    hp_scene *sc = calloc(1, sizeof *sc);
    if (!sc) {
        free(text);
        return cli_fail(CLI_EXIT_SOFTWARE, cmd, "out of memory");
    }
    hp_error e = hp_scene_parse(text, len, path, sc, &d);
    if (e != HP_OK) {
        free(text);
        free(sc);
        return cli_fail(CLI_EXIT_DATAERR, cmd, "%s", d.text);
    }
    if (bytes) {
        *bytes = text;
        *nbytes = len;
    } else {
        free(text);
    }
    *out = sc;
    return 0;
}

int cli_load_scene(const char *cmd, const char *path, const char *study_msg, hp_scene **out)
{
    return cli_load_scene_text(cmd, path, study_msg, out, NULL, NULL);
}

int cli_scene_set_correction(const char *cmd, hp_scene *sc, const double desired[6])
{
    memcpy(sc->correction, desired, sizeof sc->correction);
    sc->has_correction = 1;
    if (!sc->has_load) return 0; /* hp_scene_settings makes auto_pose of a load scene's only */
    hp_settings s;               /* auto_pose's own check, the rest at its defaults */
    hp_settings_default(&s);
    memcpy(s.auto_pose, desired, sizeof s.auto_pose);
    hp_diag d = {{0}};
    if (hp_settings_validate(&s, &d) != HP_OK)
        return cli_fail(CLI_EXIT_DATAERR, cmd, "--correction: %s", d.text);
    return 0;
}

int cli_settings(const char *cmd, const hp_scene *sc, const char *backend, const char *level,
                 hp_settings *s)
{
    hp_diag d = {{0}};
    if (hp_scene_settings(sc, s, &d) != HP_OK) return cli_fail(CLI_EXIT_DATAERR, cmd, "%s", d.text);
    /* The library's overrides; its message starts with the option's name. */
    if ((backend && hp_scene_settings_override(s, "backend", backend, 0, &d) != HP_OK) ||
        (level && hp_scene_settings_override(s, "level", level, 0, &d) != HP_OK))
        return cli_fail(CLI_EXIT_USAGE, cmd, "--%s", d.text);
    if (s->level == HP_LEVEL_LOAD && !sc->has_load)
        return cli_fail(CLI_EXIT_USAGE, cmd,
                        "--level: load needs a scene with a 'load' section (%s has none)",
                        sc->file);
    return 0;
}
