/* Strict command-line value parsing and output helpers shared by every subcommand. Every
 * parse failure prints one line on stderr naming the option and returns non-zero. */
#ifndef CLI_ARGS_H
#define CLI_ARGS_H

#include <stdio.h>

/* Parses text as a finite double: the whole string must be a number ("1.5abc", "", "nan",
 * "inf" and overflow are refused). On failure prints "headplan CMD: OPTION: why" to stderr
 * and returns CLI_EXIT_USAGE (64). Returns 0 on success. */
int cli_double(const char *cmd, const char *option, const char *text, double *out);

/* Parses a comma-separated list of exactly n finite doubles ("1,2,3"). Same contract. */
int cli_doubles(const char *cmd, const char *option, const char *text, int n, double *out);

/* Parses a positive integer in [lo, hi]. Same contract. */
int cli_int(const char *cmd, const char *option, const char *text, long lo, long hi, long *out);

/* Option walker: matches argv[*i] against "--name" (value in the next argument) or
 * "--name=value". Returns 1 and sets *value (advancing *i past a separate value) when it
 * matches, 0 when it does not, and -1 (after printing "missing value") when the value is
 * missing. */
int cli_opt(const char *cmd, int argc, char **argv, int *i, const char *name, const char **value);

/* Parses the command line of a subcommand of the form `SCENE [--NAME VALUE]... [--json]`:
 * --help or -h anywhere prints help() and returns 0; each of the nopts value options
 * names[o] fills *slots[o] (a second one is refused); --json sets *json; one positional
 * argument is the scene. Returns -1 to go on, or the exit status after one line on stderr
 * (64: unknown option, missing value, repeated option, no or two scenes). */
/* Matches argv[*i] against the named options (each takes a value, "--name V" or
 * "--name=V") and stores the value in the option's slot. Returns 1 when matched (*i moved
 * past the value), 0 when argv[*i] is none of them, -1 after printing why (missing value,
 * an option given twice): the caller exits 64. */
int cli_named_opt(const char *cmd, int argc, char **argv, int *i, const char *const *names,
                  const char **const *slots, int nopts);

int cli_scene_args(const char *cmd, int argc, char **argv, void (*help)(void),
                   const char *const *names, const char **const *slots, int nopts, int *json,
                   const char **scene);

/* The grammar of a subcommand's command line: value options (names[o] fills *slots[o]),
 * flags (flags[f] sets *flag_slots[f] to 1), options with their own syntax (extra, tried
 * first: it returns 1 matched, 0 not, or an exit status), and up to two positional
 * arguments (pos[k]; the first, named first_name, is required). */
typedef struct cli_grammar {
    void (*help)(void);
    const char *const *names;
    const char **const *slots;
    int nopts;
    const char *const *flags;
    int *const *flag_slots;
    int nflags;
    int (*extra)(const char *cmd, int argc, char **argv, int *i, void *ctx);
    void *extra_ctx;
    const char **pos[2];
    int npos;
    const char *first_name; /* "SCENE", "RESULT" */
} cli_grammar;

/* End of options (POSIX): every subcommand reads each argument after the first "--" as a
 * file or value, never as an option ("headplan solve -- -x.yaml"). cli_wants_help says
 * whether argv[from..argc) holds --help or -h before any "--". */
int cli_wants_help(int argc, char **argv, int from);

/* Parses argv by g: --help or -h anywhere (before "--") prints help() and returns 0. An
 * argument after "--" is positional. Returns -1 to go on,
 * or 64 after one line: "unknown option 'X' (see --help)", "unexpected argument 'X'",
 * "missing FIRST (see --help)", a missing value or an option given twice. */
int cli_parse(const char *cmd, int argc, char **argv, const cli_grammar *g);

/* The backends' names (hp_backend_name over the backend table, in its order) joined as
 * "a, b, c", the last separator `last` (" or "), into buf (len bytes). Returns buf: the
 * list --help gives, so a backend added to the table is listed without touching it. */
const char *cli_backend_names(const char *last, char *buf, size_t len);

/* The name of an input file in messages: "<stdin>" for "-" (standard input, as every
 * subcommand reads it), else path itself. */
const char *cli_name(const char *path);

/* Writes s to f with control characters (and DEL) as \xNN, and every byte that is not
 * part of well-formed UTF-8 as \xNN: echoed text cannot break a message's one line. */
void cli_put_escaped(FILE *f, const char *s);

/* s escaped as by cli_put_escaped, in a new string the caller frees; NULL when out of
 * memory. */
char *cli_escaped_copy(const char *s);

/* Writes s to f as one CSV field: escaped as by cli_put_escaped, then quoted by RFC 4180
 * (inside double quotes, a quote doubled) when it holds a comma, a quote or a backslash (the
 * escapes' own), else as it is. Every text field of the program's CSV files goes through it. */
void cli_put_csv_text(FILE *f, const char *s);

/* Prints "headplan CMD: message" and a newline to stderr, the message escaped as by
 * cli_put_escaped; returns status. */
int cli_fail(int status, const char *cmd, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

/* Size of a buffer for cli_fmt. */
#define CLI_FMT_MAX 32
/* Formats v with the fewest significant digits (15 to 17) that read back to the same double
 * ("%.Ng"); returns buf. The number format of every CSV and table output. Any of buf's
 * CLI_FMT_MAX bytes may be written (scratch beyond the string's end). */
const char *cli_fmt(char buf[CLI_FMT_MAX], double v);
/* The same, returning the string's length: for writers that format numbers straight into a
 * larger buffer (with CLI_FMT_MAX bytes free at buf). */
size_t cli_fmt_len(char buf[CLI_FMT_MAX], double v);

/* cli_fmt's integer path alone: writes the same string as cli_fmt and returns 1 for every
 * finite |v| in [1e-6, 1e16), else returns 0 and leaves buf untouched. */
int cli_fmt_exact(char buf[CLI_FMT_MAX], double v);

/* The same by printf and strtod alone (cli_fmt's path outside its integer range; the
 * reference its test compares against). */
const char *cli_fmt_printf(char buf[CLI_FMT_MAX], double v);

/* Number format used in every JSON and table output: shortest round-trip ("%.17g"
 * trimmed by jansson's precision 17), so results are reproducible bit for bit. */
#define CLI_JSON_REAL_PRECISION 17

#endif
