/* headplan plot: a batch result (CSV of headplan batch) drawn over time by gnuplot — the
 * pose error of every axis against the clinical tolerance band (0.5 mm / 0.5 degree), the
 * bladders' pressures with their limits, and the rows that did not reach their correction.
 * The result holds the achieved pose; the desired one comes from the trace (--trace, or the
 * scene's), matched by line. Units: mm, degrees, kPa on the picture. */
#define _POSIX_C_SOURCE 200809L
#include "cli/cli_args.h"
#include "cli/cli_scene.h"
#include "cli/commands.h"
#include "cli/exit_codes.h"
#include "cli/gnuplot_out.h"
#include "cli/sha256.h"
#include "headplan/hp_scene.h"
#include "headplan/hp_trace.h"
#include "headplan/hp_trace_columns.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

static const char *const CMD = "plot";

/* The clinical tolerance the band shows: 0.5 mm in translation, 0.5 degree in rotation. */
#define TOLERANCE_BAND 0.5

static void help(void)
{
    printf("usage: headplan plot RESULT [--scene SCENE] [--trace TRACE]\n"
           "                     [--rows deviation|correction] -o FILE.png|FILE.svg\n"
           "                     [--size WxH] [--script-out FILE.gp] [--dry-run]\n\n"
           "Draws a headplan batch result (CSV) over time with gnuplot. Top: the pose error\n"
           "of every axis (achieved - desired; mm for x, y, z and degrees for pitch, roll,\n"
           "yaw) inside the clinical tolerance band of +-0.5 mm / +-0.5 deg (green). Bottom:\n"
           "every bladder's pressure in kPa with its limits (dashed). Rows that only reached\n"
           "the closest correction are marked by orange triangles along the top of both\n"
           "panels, failed rows by red crosses (uncommanded rows with the closest ones). The\n"
           "errors are the result's error_* columns; a trace (--trace, else the scene's), when\n"
           "given, is matched to the result by line and must be the one it was planned from.\n"
           "The limits come from --scene. --scene and --trace must be the files whose\n"
           "SHA-256 the result's metadata states (the scene's own trace is left out when it\n"
           "is not the result's).\n\n"
           "  --scene SCENE  the scene the result was planned with (limits, trace)\n"
           "  --trace TRACE  the trace it was planned from (default: the scene's)\n"
           "  --rows KIND    deviation or correction (default: the trace's or the scene's)\n"
           "%s"
           "  --help         this text\n\n"
           "exit status: 0 picture written, 64 bad command line, 65 bad result, scene or\n"
           "trace, 66 an input cannot be read, 69 gnuplot not installed, 70 gnuplot failed,\n"
           "73 picture or script cannot be written\n",
           GP_HELP);
}

typedef struct plot_args {
    const char *result, *scene, *trace, *rows;
    gp_out out;
} plot_args;

static int parse(int argc, char **argv, plot_args *a)
{
    a->out.width = 1400;
    a->out.height = 900;
    const char *const names[] = {"--scene", "--trace", "--rows"};
    const char **slots[] = {&a->scene, &a->trace, &a->rows};
    const cli_grammar g = {help, names,   slots,        3,       NULL,
                           NULL, 0,       gp_option_of, &a->out, {&a->result, NULL},
                           1,    "RESULT"};
    int rc = cli_parse(CMD, argc, argv, &g);
    return rc >= 0 ? rc : gp_check(CMD, &a->out);
}

/* One row of the result. */
typedef struct row {
    long line;
    double t;
    int status; /* 0 reached, 1 closest, 2 anything else (bad row included) */
    int bad;    /* no numbers (bad-row) */
    double achieved[6], pose_error, err[6];
    int has_desired;
    double p[HP_MAX_BLADDERS]; /* kPa */
} row;

typedef struct result {
    size_t n, cap;
    row *rows;
    int nb; /* bladders (the *_pa columns) */
    char names[HP_MAX_BLADDERS][HP_NAME_MAX];
    int have_limits;
    double pmin[HP_MAX_BLADDERS], pmax[HP_MAX_BLADDERS]; /* kPa */
    int have_desired;
    int have_err_cols;                 /* the error_* columns are in the result */
    char scene_sha[65], trace_sha[65]; /* from its metadata; "" when not stated */
} result;

/* Splits a CSV line in place (no quoting in batch output). Returns the field count. */
static int split(char *s, char **f, int max)
{
    int n = 0;
    s[strcspn(s, "\r\n")] = '\0';
    for (;;) {
        if (n == max) return -1;
        f[n++] = s;
        char *c = strchr(s, ',');
        if (!c) return n;
        *c = '\0';
        s = c + 1;
    }
}

/* Numbers beyond this magnitude are refused: the axis ranges (a span, plus 12 % margins)
 * of numbers near DBL_MAX overflow to inf, which a script cannot hold ("inf" is no number
 * to gnuplot). 1e300 leaves a factor 1e8 of room. */
#define DRAWABLE_MAX 1e300

/* 0 for a number, 1 for a malformed one, 2 for one beyond DRAWABLE_MAX (flags: a row's
 * results are or-ed together). */
static int number(const char *text, double *v)
{
    char *end;
    errno = 0;
    *v = strtod(text, &end);
    if (end == text || *end != '\0' || errno != 0 || !isfinite(*v)) return 1;
    return fabs(*v) > DRAWABLE_MAX ? 2 : 0;
}

enum { MAXF = 256 }; /* columns: 8 bladders give about 80 */

/* The index of column c's value k (axis; NULL layout: not a bladders column) in the
 * header f, or -1. The names come from the one column table (hp_trace_columns.h). */
static int find_column(const char *pattern, int k, char **f, int nf, char *name, size_t size)
{
    const hp_column *c = hp_column_find(pattern);
    if (!c || hp_column_name(c, k, NULL, name, size) != HP_OK) return -1;
    for (int i = 0; i < nf; ++i)
        if (strcmp(f[i], name) == 0) return i;
    return -1;
}

/* Column indices from the header. Returns -1 to go on, or the exit status. */
static int header(const char *path, char **f, int nf, int *col, result *res)
{
    /* line, t_s, status, the achieved pose (6), pose_error_mm */
    static const char *const need[] = {"line", "t_s", "status", "achieved_{axis}_{unit}",
                                       "pose_error_mm"};
    char name[HP_COLUMN_NAME_MAX];
    for (int k = 0, j = 0; j < 5; ++j) {
        int w = hp_column_width(hp_column_find(need[j]), 0);
        for (int v = 0; v < w; ++v, ++k) {
            col[k] = find_column(need[j], v, f, nf, name, sizeof name);
            if (col[k] < 0)
                return cli_fail(CLI_EXIT_DATAERR, CMD,
                                "%s:1: not a headplan batch CSV: no column '%s'", path, name);
        }
    }
    /* The pressures: every column named by the pressure pattern, "{bladder}" any name. */
    res->nb = 0;
    const char *suffix = strstr(hp_column_find("{bladder}_pressure_pa")->name, "}") + 1;
    const size_t sl = strlen(suffix);
    for (int i = 0; i < nf; ++i) {
        size_t len = strlen(f[i]);
        if (len > sl && strcmp(f[i] + len - sl, suffix) == 0 && res->nb < HP_MAX_BLADDERS &&
            len - sl < HP_NAME_MAX) {
            col[10 + HP_MAX_BLADDERS + res->nb] = i;
            memcpy(res->names[res->nb], f[i], len - sl);
            res->names[res->nb][len - sl] = '\0';
            res->nb++;
        }
    }
    if (res->nb == 0)
        return cli_fail(CLI_EXIT_DATAERR, CMD, "%s:1: no pressure columns (NAME%s)", path, suffix);
    /* The per-axis errors (achieved − desired) are in the result itself. */
    res->have_err_cols = 1;
    for (int k = 0; k < 6; ++k) {
        col[10 + k] = find_column("error_{axis}_{unit}", k, f, nf, name, sizeof name);
        if (col[10 + k] < 0) res->have_err_cols = 0;
    }
    return -1;
}

/* Copies the 64 hex digits after key into sha when line is that metadata line (a stream's
 * "none (not a regular file)" is no hash: sha stays ""). */
static void meta_sha(const char *line, const char *key, char sha[65])
{
    size_t k = strlen(key);
    if (strncmp(line, key, k) != 0) return;
    line += k;
    if (strspn(line, "0123456789abcdef") != 64 ||
        (line[64] != '\n' && line[64] != '\r' && line[64] != '\0'))
        return;
    memcpy(sha, line, 64);
    sha[64] = '\0';
}

/* 1 when the file at path is not the one whose hash the result states (0 when the result
 * states none: a stream cannot be checked, the line match still is). */
static int not_the_one(const char *stated, const char *path)
{
    char sha[65];
    return stated[0] && (sha256_file(path, sha) != 0 || strcmp(sha, stated) != 0);
}

/* A trace is hashed (against the result's trace_sha256) and then read: only a regular file
 * is sure to end (/dev/zero, a FIFO nobody writes would be read forever). stat follows a
 * link, so a link to a file is a file. Returns -1 to go on (a name that cannot be opened is
 * reported where it is opened), or 66 after one line naming what. */
static int regular_trace(const char *what, const char *path)
{
    struct stat st;
    if (stat(path, &st) != 0 || S_ISREG(st.st_mode)) return -1;
    return cli_fail(CLI_EXIT_NOINPUT, CMD,
                    "%s %s: not a regular file (a FIFO, device or folder); a trace is hashed, "
                    "then read",
                    what, path);
}

static int read_result(const char *path, result *res)
{
    const int std = strcmp(path, "-") == 0; /* `headplan batch ... | headplan plot -` */
    path = cli_name(path);
    FILE *in = std ? stdin : fopen(path, "r");
    if (!in) return cli_fail(CLI_EXIT_NOINPUT, CMD, "%s: cannot open: %s", path, strerror(errno));
    int bad_out = cli_stdout_not_input(CMD, "result", path, fileno(in), NULL);
    if (bad_out) {
        if (!std) fclose(in);
        return bad_out;
    }
    char buf[8192];
    char *f[MAXF];
    int col[10 + 6 + 2 * HP_MAX_BLADDERS], nf = 0, rc = -1;
    long lineno = 0;
    int have_header = 0;
    while (rc < 0 && fgets(buf, sizeof buf, in)) {
        ++lineno;
        /* A result cut short (a killed `headplan batch > r.csv`, a partial copy) must not be
         * drawn with its last number cut ("-38.09" read as "-3"), nor a line longer than buf
         * read as two: refused as the trace reader refuses them. */
        size_t len = strlen(buf);
        if (len == 0 || buf[len - 1] != '\n') {
            rc = cli_fail(CLI_EXIT_DATAERR, CMD,
                          feof(in) && len > 0
                              ? "%s:%ld: truncated: the last line has no end of line"
                          : len == sizeof buf - 1 ? "%s:%ld: line longer than 8190 bytes"
                                                  : "%s:%ld: NUL byte",
                          path, lineno);
            break;
        }
        /* A UTF-8 byte-order mark is skipped, as the scene and trace readers skip it. */
        if (lineno == 1 && memcmp(buf, "\xEF\xBB\xBF", 3) == 0) memmove(buf, buf + 3, len - 2);
        if (!have_header) { /* batch's metadata: which scene and trace made the result */
            meta_sha(buf, "# scene_sha256: ", res->scene_sha);
            meta_sha(buf, "# trace_sha256: ", res->trace_sha);
        }
        if (buf[0] == '#' || buf[0] == '\n') continue;
        /* batch --format jsonl: refused by name, not as a CSV without a column 'line'. */
        if (!have_header && buf[0] == '{') {
            rc = cli_fail(CLI_EXIT_DATAERR, CMD,
                          "%s:%ld:1: a JSON Lines result; plot reads the CSV result (headplan "
                          "batch --format csv)",
                          path, lineno);
            break;
        }
        nf = split(buf, f, MAXF);
        if (nf < 0) {
            rc = cli_fail(CLI_EXIT_DATAERR, CMD, "%s:%ld: more than %d columns", path, lineno,
                          MAXF);
            break;
        }
        if (!have_header) {
            rc = header(path, f, nf, col, res);
            have_header = 1;
            continue;
        }
        if (res->n == res->cap) {
            size_t cap = res->cap ? res->cap * 2 : 1024;
            row *g = realloc(res->rows, cap * sizeof *g);
            if (!g) {
                rc = cli_fail(CLI_EXIT_SOFTWARE, CMD, "out of memory");
                break;
            }
            res->rows = g;
            res->cap = cap;
        }
        row *r = &res->rows[res->n];
        memset(r, 0, sizeof *r);
        double v;
        int maxcol = 0;
        for (int k = 0; k < 10; ++k) maxcol = col[k] > maxcol ? col[k] : maxcol;
        for (int k = 0; k < res->nb; ++k)
            maxcol = col[10 + HP_MAX_BLADDERS + k] > maxcol ? col[10 + HP_MAX_BLADDERS + k]
                                                            : maxcol;
        for (int k = 0; res->have_err_cols && k < 6; ++k)
            maxcol = col[10 + k] > maxcol ? col[10 + k] : maxcol;
        /* A line number is a whole number a long holds ((long) of 1e20 is undefined). */
        if (nf <= maxcol || number(f[col[0]], &v) || !(fabs(v) < 1e15)) {
            rc = cli_fail(CLI_EXIT_DATAERR, CMD, "%s:%ld: malformed row", path, lineno);
            break;
        }
        r->line = (long)v;
        const char *st = f[col[2]];
        r->bad = strcmp(st, "bad-row") == 0;
        /* uncommanded is an answer, marked with the closest ones: neither met the request */
        r->status = strcmp(st, "reached") == 0                                     ? 0
                    : strcmp(st, "closest") == 0 || strcmp(st, "uncommanded") == 0 ? 1
                                                                                   : 2;
        if (!r->bad) {
            int bad = number(f[col[1]], &r->t) | number(f[col[9]], &r->pose_error);
            for (int i = 0; i < 6; ++i) bad |= number(f[col[3 + i]], &r->achieved[i]);
            for (int k = 0; k < res->nb; ++k) {
                bad |= number(f[col[10 + HP_MAX_BLADDERS + k]], &r->p[k]);
                r->p[k] *= 1e-3;
            }
            for (int k = 0; res->have_err_cols && k < 6; ++k)
                bad |= number(f[col[10 + k]], &r->err[k]);
            r->has_desired = res->have_err_cols;
            if (bad) {
                rc = cli_fail(CLI_EXIT_DATAERR, CMD,
                              bad & 1 ? "%s:%ld: a number is malformed"
                                      : "%s:%ld: a number beyond 1e300 in magnitude (too large "
                                        "to draw)",
                              path, lineno);
                break;
            }
        }
        res->n++;
    }
    /* A read that failed (a directory, an I/O error) is not an empty result. */
    if (rc < 0 && ferror(in))
        rc = cli_fail(CLI_EXIT_NOINPUT, CMD, "%s: cannot read: %s", path, strerror(errno));
    if (rc < 0 && !have_header) rc = cli_fail(CLI_EXIT_DATAERR, CMD, "%s: empty (no header)", path);
    if (!std) fclose(in);
    return rc;
}

/* Desired poses from the trace, matched to the result's rows by line (both in file order). */
static int read_desired(const char *path, const hp_trace_rows *rows, const char *from, result *res)
{
    hp_trace_reader *r = NULL;
    hp_diag d = {{0}};
    FILE *tf = fopen(path, "rb");
    if (!tf) return cli_fail(CLI_EXIT_NOINPUT, CMD, "%s: cannot open: %s", path, strerror(errno));
    int bad_out = cli_stdout_not_input(CMD, "trace", path, fileno(tf), NULL);
    if (bad_out) {
        fclose(tf);
        return bad_out;
    }
    hp_error e = hp_trace_open_stream(tf, path, rows, from, &r, &d);
    if (e != HP_OK) {
        fclose(tf);
        return cli_fail(e == HP_ERR_IO ? CLI_EXIT_NOINPUT : CLI_EXIT_DATAERR, CMD, "%s", d.text);
    }
    size_t i = 0;
    for (size_t k = 0; k < res->n; ++k) res->rows[k].has_desired = 0; /* matched anew */
    for (;;) {
        hp_trace_row tr;
        e = hp_trace_next(r, &tr, &d);
        if (e == HP_END) break;
        if (e == HP_ERR_IO) {
            hp_trace_close(r);
            fclose(tf);
            return cli_fail(CLI_EXIT_NOINPUT, CMD, "%s", d.text);
        }
        if (e != HP_OK) continue; /* a bad trace row is a bad-row in the result */
        while (i < res->n && res->rows[i].line < tr.line) ++i;
        if (i < res->n && res->rows[i].line == tr.line && !res->rows[i].bad) {
            double c[6];
            hp_pose_to_clinical(tr.correction, c);
            for (int k = 0; k < 6; ++k) res->rows[i].err[k] = res->rows[i].achieved[k] - c[k];
            res->rows[i].has_desired = 1;
        }
    }
    hp_trace_close(r);
    fclose(tf);
    size_t matched = 0;
    for (size_t k = 0; k < res->n; ++k) matched += res->rows[k].has_desired;
    size_t good = 0;
    for (size_t k = 0; k < res->n; ++k) good += !res->rows[k].bad;
    if (matched != good)
        return cli_fail(CLI_EXIT_DATAERR, CMD,
                        "%s: %zu of the result's %zu rows have no row of the same line in "
                        "the trace (is it the trace the result was planned from?)",
                        path, good - matched, good);
    res->have_desired = 1;
    return -1;
}

static int write_script(const void *arg, FILE *f)
{
    const void *const *pa = arg;
    const result *res = pa[0];
    const gp_out *out = pa[1];
    const char *title = pa[2];
    /* Names (the result's, its scene's, its columns') appear only as quoted titles
     * (cli_gptext.h), never in a comment. */
    fprintf(f, "# headplan plot: a batch result over time. Units: s, mm and degrees, kPa.\n"
               "# Redraw: gnuplot THIS_FILE\n");
    if (gp_terminal(f, out) != 0) return -1;
    /* $rows: t, six axis errors (or pose_error), pressures in kPa. */
    double emin = -TOLERANCE_BAND, emax = TOLERANCE_BAND, pmin = INFINITY, pmax = -INFINITY;
    fprintf(f, "$rows << EOD\n# t_s");
    if (res->have_desired)
        for (int i = 0; i < 6; ++i) fprintf(f, " err_%s", hp_pose_key(i));
    else fprintf(f, " pose_error");
    fprintf(f, ", then the pressure in kPa of each bladder in the key's order\n");
    double tmin = INFINITY, tmax = -INFINITY;
    for (size_t i = 0; i < res->n; ++i) {
        const row *r = &res->rows[i];
        if (r->bad) continue;
        tmin = fmin(tmin, r->t);
        tmax = fmax(tmax, r->t);
        fprintf(f, "%.10g", r->t);
        int ne = res->have_desired ? 6 : 1;
        for (int k = 0; k < ne; ++k) {
            double e = res->have_desired ? r->err[k] : r->pose_error;
            emin = fmin(emin, e);
            emax = fmax(emax, e);
            fprintf(f, " %.10g", e);
        }
        for (int k = 0; k < res->nb; ++k) {
            pmin = fmin(pmin, r->p[k]);
            pmax = fmax(pmax, r->p[k]);
            fprintf(f, " %.10g", r->p[k]);
        }
        fprintf(f, "\n");
    }
    fprintf(f, "EOD\n");
    if (res->have_limits)
        for (int k = 0; k < res->nb; ++k) {
            pmin = fmin(pmin, res->pmin[k]);
            pmax = fmax(pmax, res->pmax[k]);
        }
    if (!(pmax > pmin)) {
        pmin -= 1;
        pmax += 1;
    }
    if (!(tmax > tmin)) {
        tmin -= 0.5;
        tmax += 0.5;
    }
    double epad = 0.12 * (emax - emin), ppad = 0.12 * (pmax - pmin);
    double etop = emax + 0.6 * epad, ptop = pmax + 0.6 * ppad;
    /* Rows that did not reach: closest, and failed (other statuses). */
    for (int s = 1; s <= 2; ++s) {
        fprintf(f, "$status%d << EOD\n", s);
        for (size_t i = 0; i < res->n; ++i)
            if (res->rows[i].status == s && !res->rows[i].bad)
                fprintf(f, "%.10g\n", res->rows[i].t);
        fprintf(f, "EOD\n");
    }
    size_t closest = 0, failed = 0, bad = 0;
    for (size_t i = 0; i < res->n; ++i) {
        closest += res->rows[i].status == 1;
        failed += res->rows[i].status == 2 && !res->rows[i].bad;
        bad += res->rows[i].bad;
    }
    fprintf(f, "set multiplot layout 2,1 title ");
    gp_label(f, title);
    fprintf(f, " noenhanced font ',14'\n");
    fprintf(f, "set key outside right top noenhanced\nset grid\nset xrange [%.10g:%.10g]\n", tmin,
            tmax);
    fprintf(f, "set lmargin 12\nset rmargin 30\n");
    fprintf(f, "set yrange [%.10g:%.10g]\n", emin - epad, emax + epad);
    fprintf(f, "set ylabel '%s'\n",
            res->have_desired ? "pose error [mm or deg]" : "largest axis error [mm or deg]");
    fprintf(f, "set title '%zu rows: %zu closest (orange), %zu failed (red), %zu bad rows'\n",
            res->n, closest, failed, bad);
    fprintf(f,
            "set object 1 rect from graph 0, first %g to graph 1, first %g behind "
            "fc rgb '#d9f0d3' fs solid 1.0 noborder\n",
            -TOLERANCE_BAND, TOLERANCE_BAND);
    fprintf(f, "plot ");
    if (res->have_desired)
        for (int i = 0; i < 6; ++i)
            fprintf(f, "$rows using 1:%d with lines lw 1.5 title '%s', ", 2 + i, hp_pose_key(i));
    else fprintf(f, "$rows using 1:2 with lines lw 1.5 title 'pose\\_error', ");
    fprintf(f, "NaN with filledcurves fc rgb '#d9f0d3' title 'tolerance +-0.5'");
    /* Empty marker blocks are left out (gnuplot warns about a plot with no points). */
    if (closest)
        fprintf(f,
                ", $status1 using 1:(%.10g) with points pt 9 ps 1 lc rgb '#f08000' title "
                "'closest'",
                etop);
    if (failed)
        fprintf(f,
                ", $status2 using 1:(%.10g) with points pt 2 ps 1.2 lc rgb '#d00000' "
                "title 'failed'",
                etop);
    fprintf(f, "\n");
    int ecol = res->have_desired ? 8 : 3;
    fprintf(f,
            "unset object 1\nset title 'pressures%s'\nset ylabel 'pressure [kPa]'\n"
            "set xlabel 'time [s]'\nset yrange [%.10g:%.10g]\nset key outside right top "
            "noenhanced\n",
            res->have_limits ? " and their limits (dashed)" : " (no --scene: limits unknown)",
            pmin - ppad, pmax + ppad);
    fprintf(f, "plot ");
    for (int k = 0; k < res->nb; ++k) {
        fprintf(f, "$rows using 1:%d with lines lw 1.2 lc %d title ", ecol + k, k + 1);
        gp_label(f, res->names[k]);
        fprintf(f, ", ");
    }
    if (res->have_limits) {
        /* One dashed pair for limits shared by every bladder, else one pair per bladder. */
        int same = 1;
        for (int k = 1; k < res->nb; ++k)
            same &= res->pmin[k] == res->pmin[0] && res->pmax[k] == res->pmax[0];
        for (int k = 0; k < (same ? 1 : res->nb); ++k) {
            char lc[32];
            snprintf(lc, sizeof lc, same ? "rgb '#000000'" : "%d", k + 1);
            fprintf(f,
                    "%.10g with lines dt 2 lw 1.5 lc %s title '%s', %.10g with lines dt 2 "
                    "lw 1.5 lc %s notitle, ",
                    res->pmin[k], lc, same ? "limits" : "", res->pmax[k], lc);
        }
    }
    if (closest)
        fprintf(f, "$status1 using 1:(%.10g) with points pt 9 ps 1 lc rgb '#f08000' notitle, ",
                ptop);
    if (failed)
        fprintf(f, "$status2 using 1:(%.10g) with points pt 2 ps 1.2 lc rgb '#d00000' notitle, ",
                ptop);
    fprintf(f, "NaN notitle\nunset multiplot\n");
    return ferror(f) ? -1 : 0;
}

int cmd_plot(int argc, char **argv)
{
    plot_args a = {0};
    int rc = parse(argc, argv, &a);
    if (rc >= 0) return rc;
    hp_trace_rows kind;
    if (a.rows && hp_trace_rows_parse(a.rows, &kind) != HP_OK)
        return cli_fail(CLI_EXIT_USAGE, CMD, "--rows: '%s' is neither 'deviation' nor 'correction'",
                        a.rows);
    /* One standard input: for the result or the scene. The trace is read twice (its hash
     * against the result's, then its rows), so it must be a file. */
    if (a.scene && strcmp(a.scene, "-") == 0 && strcmp(a.result, "-") == 0)
        return cli_fail(CLI_EXIT_USAGE, CMD,
                        "'-' given twice: standard input can be read only once");
    if (a.trace && strcmp(a.trace, "-") == 0)
        return cli_fail(CLI_EXIT_USAGE, CMD,
                        "--trace -: the trace must be a file (it is checked against the "
                        "result's trace_sha256, then read)");
    if (a.trace && (rc = regular_trace("--trace", a.trace)) >= 0) return rc;
    result res = {0};
    if ((rc = read_result(a.result, &res)) >= 0) {
        free(res.rows);
        return rc;
    }
    hp_scene *sc = NULL;
    const char *trace = a.trace;
    const hp_trace_rows *override = a.rows ? &kind : NULL;
    hp_trace_rows scene_rows;
    const char *from = "--rows";
    if (a.scene) {
        char *text = NULL, sha[65];
        size_t len = 0;
        int lrc = cli_load_scene_text(CMD, a.scene, NULL, &sc, &text, &len);
        if (!lrc) sha256_bytes(text, len, sha);
        free(text);
        if (!lrc && res.scene_sha[0] && strcmp(sha, res.scene_sha) != 0)
            lrc = cli_fail(CLI_EXIT_DATAERR, CMD,
                           "--scene %s: not the scene %s was planned with (its scene_sha256 "
                           "is another file's)",
                           cli_name(a.scene), cli_name(a.result));
        if (lrc) {
            free(sc);
            free(res.rows);
            return lrc;
        }
        /* Limits by name: the result's columns are the scene's bladders. */
        res.have_limits = 1;
        for (int k = 0; k < res.nb; ++k) {
            int found = 0;
            for (int j = 0; j < sc->layout.n && !found; ++j)
                if (strcmp(sc->layout.bladders[j].name, res.names[k]) == 0) {
                    res.pmin[k] = sc->layout.bladders[j].p_min * 1e-3;
                    res.pmax[k] = sc->layout.bladders[j].p_max * 1e-3;
                    found = 1;
                }
            if (!found) {
                rc = cli_fail(CLI_EXIT_DATAERR, CMD, "%s: the scene %s has no bladder '%s'",
                              cli_name(a.result), cli_name(a.scene), res.names[k]);
                break;
            }
        }
        /* The scene's own trace only when it is provably the one the result was planned
         * from: a result carries its own errors, and one of another trace, or of a stream
         * (no hash), must not get that trace's. */
        if (rc < 0 && !trace && sc->has_trace && !(res.have_err_cols && !res.trace_sha[0]))
            rc = regular_trace("the scene's trace", sc->trace_path);
        if (rc < 0 && !trace && sc->has_trace &&
            !(res.have_err_cols &&
              (!res.trace_sha[0] || not_the_one(res.trace_sha, sc->trace_path)))) {
            trace = sc->trace_path;
            scene_rows = sc->trace_rows;
            if (!override) {
                override = &scene_rows;
                from = "the scene's trace.rows";
            }
        }
    }
    if (rc < 0 && a.trace && not_the_one(res.trace_sha, a.trace))
        rc = cli_fail(CLI_EXIT_DATAERR, CMD,
                      "--trace %s: not the trace %s was planned from (its trace_sha256 is "
                      "another file's)",
                      a.trace, cli_name(a.result));
    /* The result carries its own per-axis errors; a trace, when given, is checked against it
     * (same lines) and supplies the same numbers. */
    if (rc < 0 && res.have_err_cols) res.have_desired = 1;
    if (rc < 0 && trace) rc = read_desired(trace, override, from, &res);
    if (rc < 0) {
        const char *slash = strrchr(a.result, '/');
        char title[HP_SCENE_TEXT_MAX + 512];
        snprintf(title, sizeof title, "%s%s%s", slash ? slash + 1 : cli_name(a.result),
                 sc ? ": " : "", sc ? sc->name : "");
        cli_input_of(&a.out.inputs[0], "result", a.result);
        cli_input_of(&a.out.inputs[1], "scene", a.scene);
        cli_input_of(&a.out.inputs[2], "trace", trace);
        a.out.ninputs = 3;
        const void *args[3] = {&res, &a.out, title};
        rc = gp_draw(CMD, &a.out, write_script, args);
    }
    free(sc);
    free(res.rows);
    return rc;
}
