/* Pictures drawn by gnuplot for headplan render and headplan plot: the output options they
 * share, the terminal preamble, and running gnuplot on the script. The program needs gnuplot
 * only for these two subcommands: without it they fail with exit 69 and one line. */
#ifndef HP_CLI_GNUPLOT_OUT_H
#define HP_CLI_GNUPLOT_OUT_H

#include <stdio.h>

/* EX_UNAVAILABLE: gnuplot is not installed (render and plot only). */
#define HP_EXIT_UNAVAILABLE 69

typedef struct hp_gp_out {
    const char *path;       /* -o FILE.png | FILE.svg */
    int svg;                /* 1 for .svg */
    long width, height;     /* --size WxH in pixels */
    const char *script_out; /* --script-out FILE: keep the gnuplot script (data inline) */
    int dry_run;            /* --dry-run: write the script (stdout unless --script-out) only */
} hp_gp_out;

/* Matches one of the shared options at argv[*i] (-o, --size, --script-out, --dry-run) and
 * stores it. Returns 1 when matched, 0 when not, or the exit status (64) after a message. */
int hp_gp_option(const char *cmd, int argc, char **argv, int *i, hp_gp_out *o);

/* Checks the options once parsed: -o given (unless --dry-run) with a .png or .svg name.
 * Returns -1 to go on, or 64 after a message. */
int hp_gp_check(const char *cmd, hp_gp_out *o);

/* Help text lines of the shared options, for a subcommand's --help. */
extern const char HP_GP_HELP[];

/* Writes "set terminal ...; set output '...'" for o (pngcairo when this gnuplot has it, else
 * png; svg). */
void hp_gp_terminal(FILE *f, const hp_gp_out *o);

/* Writes s as a gnuplot single-quoted string (a quote inside is doubled). */
void hp_gp_quote(FILE *f, const char *s);

/* Writes the script with writer(arg, f) to --script-out, to stdout (--dry-run alone) or to a
 * temporary file, then (unless --dry-run) runs gnuplot on it and checks that the picture was
 * written and is not empty. Returns 0, 69 (gnuplot missing), 70 (gnuplot failed) or 73
 * (script or picture cannot be written), after one line on stderr. */
int hp_gp_draw(const char *cmd, const hp_gp_out *o, int (*writer)(const void *arg, FILE *f),
               const void *arg);

#endif
