/* Pictures drawn by gnuplot for headplan render and headplan plot: the output options they
 * share, the terminal preamble, and running gnuplot on the script. The program needs gnuplot
 * only for these two subcommands: without it they fail with exit 69 and one line. */
#ifndef CLI_GNUPLOT_OUT_H
#define CLI_GNUPLOT_OUT_H

#include "cli/cli_gptext.h"
#include "cli/cli_outfile.h"

#include <stdio.h>

typedef struct gp_out {
    const char *path;       /* -o FILE.png | FILE.svg */
    int svg;                /* 1 for .svg */
    long width, height;     /* --size WxH in pixels (a command's default until given) */
    int size_given;         /* --size seen: a second one is refused */
    const char *script_out; /* --script-out FILE: keep the gnuplot script (data inline) */
    int dry_run;            /* --dry-run: write the script (stdout unless --script-out) only */
    cli_input inputs[3];    /* files the command reads: never written over */
    int ninputs;
    const char *drawing;    /* set by gp_draw while gnuplot draws: the temporary picture */
    const char *path_opt;   /* the options' names in messages (NULL: "-o", "--script-out"; */
    const char *script_opt; /* fit layout's are --plot and --plot-script, and it has no
                               --dry-run for a message to suggest) */
} gp_out;

/* Matches one of the shared options at argv[*i] (-o, --size, --script-out, --dry-run) and
 * stores it. Returns 1 when matched, 0 when not, or the exit status (64) after a message. */
int gp_option(const char *cmd, int argc, char **argv, int *i, gp_out *o);

/* gp_option for cli_grammar's extra matcher (ctx is the gp_out). */
int gp_option_of(const char *cmd, int argc, char **argv, int *i, void *ctx);

/* Checks the options once parsed: -o given (unless --dry-run) with a name gp_check_name
 * accepts. Returns -1 to go on, or 64 after a message. */
int gp_check(const char *cmd, gp_out *o);

/* Checks a picture's name given to option opt: it ends in .png or .svg (*svg says which;
 * svg may be NULL) and holds no control character (the name is written into the script,
 * see cli_gptext.h). Returns -1 to go on, or 64 after one line naming opt. */
int gp_check_name(const char *cmd, const char *opt, const char *path, int *svg);

/* Help text lines of the shared options, for a subcommand's --help. */
extern const char GP_HELP[];

/* Writes "set terminal ...; set output '...'" for o (pngcairo when this gnuplot has it, else
 * png; svg). Returns 0, or -1 when the picture's name cannot be quoted (gp_check refuses
 * such a name first). */
int gp_terminal(FILE *f, const gp_out *o);

/* Writes the script with writer(arg, f) to --script-out (if given) or, for --dry-run alone,
 * to stdout; then (unless --dry-run) pipes it into gnuplot (found on PATH) and checks that the
 * picture was written, is not empty and ends as a whole PNG or SVG does. The files go through
 * cli_outfile.h: never over one of o->inputs, a link or a device, and under their names only
 * when complete. Returns 0, 69 (gnuplot missing), 70 (gnuplot failed), 73 (script or picture
 * cannot be created) or 74 (a picture cut short, a failed write of the script), after one
 * line on stderr. */
int gp_draw(const char *cmd, gp_out *o, int (*writer)(const void *arg, FILE *f), const void *arg);

#endif
