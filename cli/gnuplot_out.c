/* Output options and the gnuplot run shared by render and plot (see gnuplot_out.h). The
 * script holds its data inline (gnuplot data blocks), so --script-out gives one file that
 * redraws the picture by hand: `gnuplot FILE.gp`. */
#define _POSIX_C_SOURCE 200809L
#include "cli/gnuplot_out.h"
#include "cli/bench_report.h"
#include "cli/cli_args.h"
#include "cli/exit_codes.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

const char HP_GP_HELP[] =
    "  -o FILE        the picture: FILE.png or FILE.svg (required unless --dry-run)\n"
    "  --size WxH     picture size in pixels (default 1500x700)\n"
    "  --script-out F also keep the gnuplot script, data inline (redraw: gnuplot F)\n"
    "  --dry-run      write the script (to stdout, or to --script-out) and do not draw\n";

int hp_gp_option(const char *cmd, int argc, char **argv, int *i, hp_gp_out *o)
{
    if (strcmp(argv[*i], "--dry-run") == 0) {
        o->dry_run = 1;
        return 1;
    }
    const char *v = NULL;
    int m;
    if ((m = hp_cli_opt(cmd, argc, argv, i, "-o", &v)) != 0) {
        if (m < 0) return HP_EXIT_USAGE;
        if (o->path) return hp_cli_fail(HP_EXIT_USAGE, cmd, "-o: given more than once");
        o->path = v;
        return 1;
    }
    if ((m = hp_cli_opt(cmd, argc, argv, i, "--script-out", &v)) != 0) {
        if (m < 0) return HP_EXIT_USAGE;
        if (o->script_out)
            return hp_cli_fail(HP_EXIT_USAGE, cmd, "--script-out: given more than once");
        o->script_out = v;
        return 1;
    }
    if ((m = hp_cli_opt(cmd, argc, argv, i, "--size", &v)) != 0) {
        if (m < 0) return HP_EXIT_USAGE;
        char *end;
        errno = 0;
        long w = strtol(v, &end, 10), h = 0;
        int ok = end != v && *end == 'x' && errno == 0;
        if (ok) {
            const char *hs = end + 1;
            h = strtol(hs, &end, 10);
            ok = end != hs && *end == '\0' && errno == 0;
        }
        if (!ok || w < 200 || w > 10000 || h < 200 || h > 10000)
            return hp_cli_fail(HP_EXIT_USAGE, cmd,
                               "--size: expected WxH in pixels, each 200..10000 (got '%s')", v);
        o->width = w;
        o->height = h;
        return 1;
    }
    return 0;
}

static int ends_with(const char *s, const char *suffix)
{
    size_t n = strlen(s), k = strlen(suffix);
    return n > k && strcmp(s + n - k, suffix) == 0;
}

int hp_gp_check(const char *cmd, hp_gp_out *o)
{
    if (!o->width) {
        o->width = 1500;
        o->height = 700;
    }
    if (!o->path) {
        if (o->dry_run) return -1;
        return hp_cli_fail(HP_EXIT_USAGE, cmd, "-o: missing (FILE.png or FILE.svg)");
    }
    if (ends_with(o->path, ".svg")) o->svg = 1;
    else if (!ends_with(o->path, ".png"))
        return hp_cli_fail(HP_EXIT_USAGE, cmd, "-o: '%s' must end in .png or .svg", o->path);
    return -1;
}

void hp_gp_quote(FILE *f, const char *s)
{
    fputc('\'', f);
    for (; *s; ++s) {
        if (*s == '\'') fputc('\'', f);
        fputc(*s, f);
    }
    fputc('\'', f);
}

void hp_gp_terminal(FILE *f, const hp_gp_out *o)
{
    if (o->svg) {
        fprintf(f, "set terminal svg size %ld,%ld enhanced font 'Sans,12' background 'white'\n",
                o->width, o->height);
    } else {
        fprintf(f,
                "if (strstrt(GPVAL_TERMINALS, 'pngcairo') > 0) {\n"
                "  set terminal pngcairo size %ld,%ld enhanced font 'Sans,11'\n"
                "} else {\n  set terminal png size %ld,%ld\n}\n",
                o->width, o->height, o->width, o->height);
    }
    fprintf(f, "set output ");
    hp_gp_quote(f, o->path ? o->path : "/dev/null");
    fprintf(f, "\nset encoding utf8\n");
}

static int write_script(const char *cmd, const char *path, FILE *f,
                        int (*writer)(const void *, FILE *), const void *arg)
{
    int bad = writer(arg, f) != 0;
    bad |= ferror(f) != 0;
    if (f != stdout) bad |= fclose(f) != 0;
    else bad |= fflush(f) != 0;
    if (bad) return hp_cli_fail(HP_EXIT_CANTCREAT, cmd, "cannot write the script %s", path);
    return 0;
}

int hp_gp_draw(const char *cmd, const hp_gp_out *o, int (*writer)(const void *arg, FILE *f),
               const void *arg)
{
    if (!o->dry_run && hp_bench_gnuplot_available() != 0)
        return hp_cli_fail(HP_EXIT_UNAVAILABLE, cmd,
                           "gnuplot not found on PATH (install gnuplot-nox; --dry-run writes "
                           "the script without it)");
    char tmp[] = "/tmp/headplan-gnuplot-XXXXXX";
    const char *script = o->script_out;
    FILE *f;
    if (script) {
        f = fopen(script, "w");
        if (!f)
            return hp_cli_fail(HP_EXIT_CANTCREAT, cmd, "--script-out: cannot create '%s': %s",
                               script, strerror(errno));
    } else if (o->dry_run) {
        f = stdout;
        script = "(stdout)";
    } else {
        int fd = mkstemp(tmp);
        f = fd >= 0 ? fdopen(fd, "w") : NULL;
        if (!f) {
            if (fd >= 0) close(fd);
            return hp_cli_fail(HP_EXIT_CANTCREAT, cmd, "cannot create a temporary script: %s",
                               strerror(errno));
        }
        script = tmp;
    }
    int rc = write_script(cmd, script, f, writer, arg);
    if (rc || o->dry_run) {
        if (script == tmp) unlink(tmp);
        return rc;
    }
    /* An unwritable picture is the user's to fix (73), not a gnuplot failure; and a stale
     * picture must not pass for a new one. */
    FILE *probe = fopen(o->path, "w");
    if (!probe) {
        int err = errno;
        if (script == tmp) unlink(tmp);
        return hp_cli_fail(HP_EXIT_CANTCREAT, cmd, "-o: cannot create '%s': %s", o->path,
                           strerror(err));
    }
    fclose(probe);
    remove(o->path);
    char *const argv[] = {"gnuplot", (char *)script, NULL};
    int st = hp_bench_run_child(argv, NULL, 0);
    if (script == tmp) unlink(tmp);
    struct stat sb;
    if (st != 0)
        return hp_cli_fail(HP_EXIT_SOFTWARE, cmd, "gnuplot failed (exit %d) drawing %s", st,
                           o->path);
    if (stat(o->path, &sb) != 0 || sb.st_size == 0)
        return hp_cli_fail(HP_EXIT_CANTCREAT, cmd, "-o: %s was not written", o->path);
    return 0;
}
