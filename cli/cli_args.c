/* Strict parsing of command-line values (see cli_args.h). */
#define _POSIX_C_SOURCE 200809L /* open_memstream */
#include "cli/cli_args.h"
#include "cli/exit_codes.h"
#include "headplan/hp_planner.h"
#include "scene/text_check.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

void cli_put_escaped(FILE *f, const char *s)
{
    size_t len = strlen(s);
    for (size_t i = 0; i < len;) {
        int nul = 0;
        long bad = hpi_text_bad_byte(s + i, len - i, &nul);
        size_t clean = bad < 0 ? len - i : (size_t)bad;
        for (size_t k = 0; k < clean; ++k) {
            unsigned char c = (unsigned char)s[i + k];
            if (c < 0x20 || c == 0x7f) fprintf(f, "\\x%02x", c);
            else fputc(c, f);
        }
        i += clean;
        if (i < len) fprintf(f, "\\x%02x", (unsigned char)s[i++]);
    }
}

char *cli_escaped_copy(const char *s)
{
    char *clean = NULL;
    size_t size = 0;
    FILE *m = open_memstream(&clean, &size);
    if (!m) return NULL;
    cli_put_escaped(m, s);
    if (fclose(m) != 0) {
        free(clean);
        return NULL;
    }
    return clean;
}

void cli_put_csv_text(FILE *f, const char *s)
{
    const char *c = s;
    while (*c >= 0x20 && *c < 0x7f && *c != ',' && *c != '"' && *c != '\\') ++c;
    if (*c == '\0') {
        fputs(s, f); /* printable ASCII with nothing to quote or escape */
        return;
    }
    char *clean = cli_escaped_copy(s);
    if (!clean) return;
    if (strpbrk(clean, ",\"\\") == NULL) {
        fputs(clean, f);
        free(clean);
        return;
    }
    fputc('"', f);
    for (const char *p = clean; *p; ++p) {
        if (*p == '"') fputc('"', f);
        fputc(*p, f);
    }
    fputc('"', f);
    free(clean);
}

int cli_fail(int status, const char *cmd, const char *fmt, ...)
{
    /* Echoed text (a path, an option, a key from a file) may hold control characters or
     * broken UTF-8: the message stays one line of clean text. */
    char buf[2048];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(buf, sizeof buf, fmt, ap);
    va_end(ap);
    fprintf(stderr, "headplan %s: ", cmd);
    cli_put_escaped(stderr, buf);
    fputc('\n', stderr);
    return status;
}

/* strtod accepts "nan", "inf", hex floats and leading spaces; a user's number is none of
 * those, so the characters are checked before strtod sees them. */
static int plain_number_chars(const char *s)
{
    if (*s == '\0') return 0;
    for (const char *p = s; *p; ++p)
        if (!strchr("0123456789+-.eE", *p)) return 0;
    return 1;
}

int cli_double(const char *cmd, const char *option, const char *text, double *out)
{
    if (!text || !plain_number_chars(text))
        return cli_fail(CLI_EXIT_USAGE, cmd, "%s: '%s' is not a number", option, text ? text : "");
    char *end = NULL;
    errno = 0;
    double v = strtod(text, &end);
    if (end == text || *end != '\0')
        return cli_fail(CLI_EXIT_USAGE, cmd, "%s: '%s' is not a number", option, text);
    if (errno == ERANGE && fabs(v) > 1.0)
        return cli_fail(CLI_EXIT_USAGE, cmd, "%s: '%s' overflows a double", option, text);
    if (!isfinite(v)) return cli_fail(CLI_EXIT_USAGE, cmd, "%s: '%s' is not finite", option, text);
    *out = v;
    return 0;
}

int cli_doubles(const char *cmd, const char *option, const char *text, int n, double *out)
{
    char buf[512];
    if (!text || strlen(text) >= sizeof buf)
        return cli_fail(CLI_EXIT_USAGE, cmd, "%s: expected %d comma-separated numbers", option, n);
    strcpy(buf, text);
    int count = 0;
    char *p = buf;
    for (;;) {
        char *comma = strchr(p, ',');
        if (comma) *comma = '\0';
        if (count >= n)
            return cli_fail(CLI_EXIT_USAGE, cmd, "%s: more than %d numbers in '%s'", option, n,
                            text);
        int rc = cli_double(cmd, option, p, &out[count]);
        if (rc) return rc;
        ++count;
        if (!comma) break;
        p = comma + 1;
    }
    if (count != n)
        return cli_fail(CLI_EXIT_USAGE, cmd, "%s: %d numbers in '%s', expected %d", option, count,
                        text, n);
    return 0;
}

int cli_int(const char *cmd, const char *option, const char *text, long lo, long hi, long *out)
{
    if (!text || *text == '\0' || strspn(text, "0123456789") != strlen(text))
        return cli_fail(CLI_EXIT_USAGE, cmd, "%s: '%s' is not a whole number", option,
                        text ? text : "");
    errno = 0;
    long v = strtol(text, NULL, 10);
    if (errno == ERANGE || v < lo || v > hi)
        return cli_fail(CLI_EXIT_USAGE, cmd, "%s: '%s' is outside [%ld, %ld]", option, text, lo,
                        hi);
    *out = v;
    return 0;
}

int cli_opt(const char *cmd, int argc, char **argv, int *i, const char *name, const char **value)
{
    const char *a = argv[*i];
    size_t n = strlen(name);
    if (strncmp(a, name, n) != 0) return 0;
    if (a[n] == '=') {
        *value = a + n + 1;
        return 1;
    }
    if (a[n] != '\0') return 0;
    if (*i + 1 >= argc) {
        cli_fail(CLI_EXIT_USAGE, cmd, "%s: missing value", name);
        return -1;
    }
    *i += 1;
    *value = argv[*i];
    return 1;
}

int cli_named_opt(const char *cmd, int argc, char **argv, int *i, const char *const *names,
                  const char **const *slots, int nopts)
{
    for (int o = 0; o < nopts; ++o) {
        const char *v = NULL;
        int m = cli_opt(cmd, argc, argv, i, names[o], &v);
        if (m < 0) return -1;
        if (m == 0) continue;
        if (*slots[o]) {
            cli_fail(CLI_EXIT_USAGE, cmd, "%s: given more than once", names[o]);
            return -1;
        }
        *slots[o] = v;
        return 1;
    }
    return 0;
}

const char *cli_name(const char *path) { return path && strcmp(path, "-") == 0 ? "<stdin>" : path; }

int cli_wants_help(int argc, char **argv, int from)
{
    for (int i = from; i < argc && strcmp(argv[i], "--") != 0; ++i)
        if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0) return 1;
    return 0;
}

/* argv[*i] as one of g's options: 1 matched (*i past its value), 0 not an option (a
 * positional argument), else the exit status after one line. */
static int grammar_option(const char *cmd, int argc, char **argv, int *i, const cli_grammar *g)
{
    if (g->extra) {
        int m = g->extra(cmd, argc, argv, i, g->extra_ctx);
        if (m != 0) return m;
    }
    for (int f = 0; f < g->nflags; ++f)
        if (strcmp(argv[*i], g->flags[f]) == 0) return *g->flag_slots[f] = 1;
    int matched = cli_named_opt(cmd, argc, argv, i, g->names, g->slots, g->nopts);
    if (matched != 0) return matched < 0 ? CLI_EXIT_USAGE : 1;
    if (argv[*i][0] == '-' && argv[*i][1] != '\0')
        return cli_fail(CLI_EXIT_USAGE, cmd, "unknown option '%s' (see --help)", argv[*i]);
    return 0;
}

int cli_parse(const char *cmd, int argc, char **argv, const cli_grammar *g)
{
    if (cli_wants_help(argc, argv, 1)) {
        g->help();
        return CLI_EXIT_OK;
    }
    int npos = 0;
    for (int i = 1, operands = 0; i < argc; ++i) {
        if (!operands && strcmp(argv[i], "--") == 0) {
            operands = 1;
            continue;
        }
        if (!operands) {
            int m = grammar_option(cmd, argc, argv, &i, g);
            if (m == 1) continue;
            if (m != 0) return m;
        }
        if (npos >= g->npos)
            return cli_fail(CLI_EXIT_USAGE, cmd, "unexpected argument '%s'", argv[i]);
        *g->pos[npos++] = argv[i];
    }
    if (npos == 0) return cli_fail(CLI_EXIT_USAGE, cmd, "missing %s (see --help)", g->first_name);
    /* SCENE - and TRACE -: the second would read what the first left (nothing). */
    if (npos == 2 && strcmp(*g->pos[0], "-") == 0 && strcmp(*g->pos[1], "-") == 0)
        return cli_fail(CLI_EXIT_USAGE, cmd,
                        "'-' given twice: standard input can be read only once");
    return -1;
}

int cli_scene_args(const char *cmd, int argc, char **argv, void (*help)(void),
                   const char *const *names, const char **const *slots, int nopts, int *json,
                   const char **scene)
{
    if (cli_wants_help(argc, argv, 1)) {
        help();
        return CLI_EXIT_OK;
    }
    for (int i = 1, operands = 0; i < argc; ++i) {
        if (!operands && strcmp(argv[i], "--") == 0) {
            operands = 1;
            continue;
        }
        if (!operands && strcmp(argv[i], "--json") == 0) {
            *json = 1;
            continue;
        }
        int matched = operands ? 0 : cli_named_opt(cmd, argc, argv, &i, names, slots, nopts);
        if (matched < 0) return CLI_EXIT_USAGE;
        if (matched) continue;
        if (!operands && argv[i][0] == '-' && argv[i][1] != '\0')
            return cli_fail(CLI_EXIT_USAGE, cmd, "unknown option '%s' (see headplan %s --help)",
                            argv[i], cmd);
        if (*scene)
            return cli_fail(CLI_EXIT_USAGE, cmd, "'%s': only one scene file may be given", argv[i]);
        *scene = argv[i];
    }
    if (!*scene)
        return cli_fail(CLI_EXIT_USAGE, cmd, "SCENE: missing (see headplan %s --help)", cmd);
    return -1;
}

const char *cli_backend_names(const char *last, char *buf, size_t len)
{
    size_t at = 0;
    if (len) buf[0] = '\0';
    for (int b = 0; b < HP_BACKEND_COUNT_ && at < len; ++b) {
        const char *sep = b == 0 ? "" : b == HP_BACKEND_COUNT_ - 1 ? last : ", ";
        int w = snprintf(buf + at, len - at, "%s%s", sep, hp_backend_name((hp_backend)b));
        if (w < 0) break;
        at += (size_t)w;
    }
    return buf;
}
