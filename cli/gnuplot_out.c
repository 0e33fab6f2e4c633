/* Output options and the gnuplot run shared by render and plot (see gnuplot_out.h). The
 * script holds its data inline (gnuplot data blocks), so --script-out gives one file that
 * redraws the picture by hand (`gnuplot FILE.gp`); the drawing itself pipes the same script
 * into gnuplot. */
#define _POSIX_C_SOURCE 200809L
#include "cli/gnuplot_out.h"
#include "cli/cli_args.h"
#include "cli/cli_outfile.h"
#include "cli/exit_codes.h"

#include <errno.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

const char GP_HELP[] =
    "  -o FILE        the picture: FILE.png or FILE.svg (required unless --dry-run)\n"
    "  --size WxH     picture size in pixels (default: render 1500x700, plot 1400x900)\n"
    "  --script-out F also keep the gnuplot script, data inline (redraw: gnuplot F)\n"
    "  --dry-run      write the script (to stdout, or to --script-out) and do not draw\n";

int gp_option(const char *cmd, int argc, char **argv, int *i, gp_out *o)
{
    if (strcmp(argv[*i], "--dry-run") == 0) {
        o->dry_run = 1;
        return 1;
    }
    const char *v = NULL;
    int m;
    if ((m = cli_opt(cmd, argc, argv, i, "-o", &v)) != 0) {
        if (m < 0) return CLI_EXIT_USAGE;
        if (o->path) return cli_fail(CLI_EXIT_USAGE, cmd, "-o: given more than once");
        o->path = v;
        return 1;
    }
    if ((m = cli_opt(cmd, argc, argv, i, "--script-out", &v)) != 0) {
        if (m < 0) return CLI_EXIT_USAGE;
        if (o->script_out)
            return cli_fail(CLI_EXIT_USAGE, cmd, "--script-out: given more than once");
        o->script_out = v;
        return 1;
    }
    if ((m = cli_opt(cmd, argc, argv, i, "--size", &v)) != 0) {
        if (m < 0) return CLI_EXIT_USAGE;
        if (o->size_given) return cli_fail(CLI_EXIT_USAGE, cmd, "--size: given more than once");
        o->size_given = 1;
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
            return cli_fail(CLI_EXIT_USAGE, cmd,
                            "--size: expected WxH in pixels, each 200..10000 (got '%s')", v);
        o->width = w;
        o->height = h;
        return 1;
    }
    return 0;
}

int gp_option_of(const char *cmd, int argc, char **argv, int *i, void *ctx)
{
    return gp_option(cmd, argc, argv, i, ctx);
}

static int ends_with(const char *s, const char *suffix)
{
    size_t n = strlen(s), k = strlen(suffix);
    return n > k && strcmp(s + n - k, suffix) == 0;
}

/* The names the user gave the two outputs. */
static const char *path_opt(const gp_out *o) { return o->path_opt ? o->path_opt : "-o"; }
static const char *script_opt(const gp_out *o)
{
    return o->script_opt ? o->script_opt : "--script-out";
}

int gp_check_name(const char *cmd, const char *opt, const char *path, int *svg)
{
    int is_svg = ends_with(path, ".svg");
    if (!is_svg && !ends_with(path, ".png"))
        return cli_fail(CLI_EXIT_USAGE, cmd, "%s: '%s' must end in .png or .svg", opt, path);
    long at = gp_control_byte(path);
    if (at >= 0)
        return cli_fail(CLI_EXIT_USAGE, cmd,
                        "%s: '%s' holds a control character (byte %ld): a picture's name is "
                        "written into its gnuplot script",
                        opt, path, at + 1);
    if (svg) *svg = is_svg;
    return -1;
}

int gp_check(const char *cmd, gp_out *o)
{
    if (!o->width) {
        o->width = 1500;
        o->height = 700;
    }
    if (!o->path) {
        if (o->dry_run) return -1;
        return cli_fail(CLI_EXIT_USAGE, cmd, "-o: missing (FILE.png or FILE.svg)");
    }
    int rc = cli_outputs_distinct(cmd, script_opt(o), o->script_out, path_opt(o), o->path);
    if (rc) return rc;
    return gp_check_name(cmd, path_opt(o), o->path, &o->svg);
}

int gp_terminal(FILE *f, const gp_out *o)
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
    if (gp_path(f, o->drawing ? o->drawing : o->path ? o->path : "/dev/null") != 0) return -1;
    fprintf(f, "\nset encoding utf8\n");
    return 0;
}

/* Writes the script into f; 0, or 74 after one line naming what. Standard output is left
 * to main's one check of it (cli_finish_stdout), so a failure there is reported once. */
static int write_script(const char *cmd, const char *what, FILE *f,
                        int (*writer)(const void *, FILE *), const void *arg)
{
    int bad = writer(arg, f) != 0;
    if (f == stdout) return 0;
    bad |= ferror(f) != 0;
    if (bad) return cli_fail(CLI_EXIT_IOERR, cmd, "cannot write the script %s", what);
    return 0;
}

/* 1 when an executable "gnuplot" is in a folder of PATH. */
static int gnuplot_on_path(void)
{
    const char *path = getenv("PATH");
    if (!path) return 0;
    char dir[4096];
    while (*path) {
        size_t n = strcspn(path, ":");
        if (n > 0 && n < sizeof dir - 16) {
            memcpy(dir, path, n);
            strcpy(dir + n, "/gnuplot");
            if (access(dir, X_OK) == 0) return 1;
        }
        path += n;
        if (*path == ':') ++path;
    }
    return 0;
}

/* Pipes the script into gnuplot (its output to our stderr: stdout carries results only).
 * Returns gnuplot's exit status, or -1 when it could not be run. */
static int run_gnuplot(int (*writer)(const void *, FILE *), const void *arg)
{
    fflush(stdout);
    fflush(stderr);
    /* The scripts say "set encoding utf8"; in a C or other non-UTF-8 locale gnuplot warns that
     * it cannot convert its degree sign, a stray line on our stderr. */
    FILE *g = popen("LC_ALL=C.UTF-8 gnuplot 1>&2", "w");
    if (!g) return -1;
    /* gnuplot stopping early must not kill us with SIGPIPE: its status tells. */
    struct sigaction ign = {0}, old;
    ign.sa_handler = SIG_IGN;
    sigaction(SIGPIPE, &ign, &old);
    writer(arg, g);
    int st = pclose(g);
    sigaction(SIGPIPE, &old, NULL);
    return st >= 0 && WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

/* 1 when the picture at path ends as a whole one does: a PNG with its IEND chunk, an SVG
 * with its closing tag. gnuplot exits 0 when a write of its output fails (a full disk left
 * a 64 KiB SVG prefix, exit 0), so its status and a non-empty file prove nothing. */
static int picture_complete(const char *path, int svg)
{
    static const unsigned char iend[12] = {0, 0, 0, 0, 'I', 'E', 'N', 'D', 0xae, 0x42, 0x60, 0x82};
    unsigned char tail[64];
    FILE *f = fopen(path, "rb");
    if (!f) return 0;
    long want = svg ? (long)sizeof tail : (long)sizeof iend;
    size_t n = 0;
    if (fseek(f, -want, SEEK_END) == 0) n = fread(tail, 1, (size_t)want, f);
    fclose(f);
    if (!svg) return n == sizeof iend && memcmp(tail, iend, sizeof iend) == 0;
    while (n > 0 && (tail[n - 1] == '\n' || tail[n - 1] == '\r' || tail[n - 1] == ' ')) --n;
    return n >= 6 && memcmp(tail + n - 6, "</svg>", 6) == 0;
}

int gp_draw(const char *cmd, gp_out *o, int (*writer)(const void *arg, FILE *f), const void *arg)
{
    /* Only render and plot (the default option names) have --dry-run to point at. */
    if (!o->dry_run && !gnuplot_on_path())
        return cli_fail(CLI_EXIT_UNAVAILABLE, cmd,
                        "gnuplot not found on PATH (install gnuplot-nox%s)",
                        o->path_opt ? "" : "; --dry-run writes the script without it");
    if (!o->script_out && o->dry_run) return write_script(cmd, "(stdout)", stdout, writer, arg);
    /* Both files are created (and checked against the inputs) before either is written, and
     * appear under their names only when both are complete. */
    cli_out script = {.slot = -1}, picture = {.slot = -1};
    int rc = 0;
    if (o->script_out)
        rc = cli_out_open(&script, cmd, script_opt(o), o->script_out, o->inputs, o->ninputs);
    if (rc == 0 && !o->dry_run)
        rc = cli_out_open(&picture, cmd, path_opt(o), o->path, o->inputs, o->ninputs);
    if (rc == 0 && o->script_out) rc = write_script(cmd, o->script_out, script.f, writer, arg);
    if (rc == 0 && !o->dry_run) {
        /* gnuplot writes the picture to the temporary name itself; the kept script names
         * the final one. */
        fclose(picture.f);
        picture.f = NULL;
        o->drawing = cli_out_temp(&picture);
        int st = run_gnuplot(writer, arg);
        o->drawing = NULL;
        struct stat sb;
        if (st != 0)
            rc = cli_fail(CLI_EXIT_SOFTWARE, cmd, "gnuplot failed (exit %d) drawing %s", st,
                          o->path);
        else if (stat(cli_out_temp(&picture), &sb) != 0 || sb.st_size == 0)
            rc = cli_fail(CLI_EXIT_CANTCREAT, cmd, "%s: %s was not written", path_opt(o), o->path);
        else if (!picture_complete(cli_out_temp(&picture), o->svg))
            rc = cli_fail(CLI_EXIT_IOERR, cmd,
                          "cannot write %s: gnuplot's picture is cut short (a full disk?)",
                          o->path);
    }
    if (rc == 0 && o->script_out) rc = cli_out_commit(&script, cmd);
    if (rc == 0 && !o->dry_run) rc = cli_out_commit(&picture, cmd);
    if (rc) {
        cli_out_abandon(&script);
        cli_out_abandon(&picture);
    }
    return rc;
}
