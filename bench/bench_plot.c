/* headplan-bench: the output folder, atomic file writes and the gnuplot chart. gnuplot runs
 * as a child process (fork + execvp, no shell, so no quoting of the folder name) in the
 * output folder, which makes the generated script re-runnable there by hand. */
#define _POSIX_C_SOURCE 200809L
#include "cli/cli_args.h"
#include "cli/cli_gptext.h"
#include "cli/cli_output.h"
#include "bench/bench_report.h"
#include "cli/exit_codes.h"
#include "common/unconst.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#define PATH_CAP 4096

int bench_mkdirs(const char *dir)
{
    char p[PATH_CAP];
    if (!dir || !*dir || strlen(dir) >= sizeof p) {
        cli_fail(0, "bench", "--out: folder name empty or too long");
        return CLI_EXIT_CANTCREAT;
    }
    strcpy(p, dir);
    for (char *s = p + 1;; ++s) {
        int end = *s == '\0';
        if (*s == '/' || end) {
            *s = '\0';
            if (mkdir(p, 0777) != 0 && errno != EEXIST) {
                cli_fail(0, "bench", "--out: cannot create folder '%s': %s", p, strerror(errno));
                return CLI_EXIT_CANTCREAT;
            }
            if (end) break;
            *s = '/';
        }
    }
    struct stat st;
    if (stat(dir, &st) != 0 || !S_ISDIR(st.st_mode)) {
        cli_fail(0, "bench", "--out: '%s' is not a folder", dir);
        return CLI_EXIT_CANTCREAT;
    }
    return 0;
}

static int join(char *out, size_t cap, const char *dir, const char *name, const char *suffix)
{
    int n = snprintf(out, cap, "%s/%s%s", dir, name, suffix);
    return n < 0 || (size_t)n >= cap ? -1 : 0;
}

int bench_save(const char *dir, const char *name, int (*writer)(const void *arg, FILE *f),
               const void *arg)
{
    char final[PATH_CAP], tmp[PATH_CAP];
    if (join(final, sizeof final, dir, name, "") || join(tmp, sizeof tmp, dir, name, ".tmp")) {
        cli_fail(0, "bench", "%s/%s: path too long", dir, name);
        return CLI_EXIT_CANTCREAT;
    }
    FILE *f = fopen(tmp, "w");
    if (!f) {
        cli_fail(0, "bench", "cannot create '%s': %s", tmp, strerror(errno));
        return CLI_EXIT_CANTCREAT;
    }
    int bad = writer(arg, f) != 0;
    int rc = cli_close_output(f, tmp, "bench");
    if (rc == 0 && bad) rc = cli_fail(CLI_EXIT_IOERR, "bench", "cannot write %s", tmp);
    if (rc == 0 && rename(tmp, final) != 0)
        rc = cli_fail(CLI_EXIT_IOERR, "bench", "cannot rename %s to %s: %s", tmp, final,
                      strerror(errno));
    if (rc) remove(tmp);
    return rc;
}

int bench_run_child(char *const argv[], const char *cwd, int quiet)
{
    fflush(stdout);
    fflush(stderr);
    pid_t pid = fork();
    if (pid < 0) return -1;
    if (pid == 0) {
        if (quiet) {
            int fd = open("/dev/null", O_WRONLY);
            if (fd >= 0) {
                dup2(fd, 1);
                dup2(fd, 2);
            }
        } else {
            dup2(2, 1);
        }
        if (cwd && chdir(cwd) != 0) _exit(126);
        execvp(argv[0], argv);
        _exit(127);
    }
    int st;
    while (waitpid(pid, &st, 0) < 0)
        if (errno != EINTR) return -1;
    return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

int bench_gnuplot_available(void)
{
    char *const argv[] = {"gnuplot", "--version", NULL};
    return bench_run_child(argv, NULL, 1) == 0 ? 0 : -1;
}

typedef struct {
    const bench_table *t;
    const bench_chart *c;
} plot_args;

static double floored(double e) { return e > BENCH_ERROR_FLOOR ? e : BENCH_ERROR_FLOOR; }

static int cmp_time_error(const void *a, const void *b)
{
    const bench_row *x = *(const bench_row *const *)a, *y = *(const bench_row *const *)b;
    if (x->median_ns != y->median_ns)
        return (x->median_ns > y->median_ns) - (x->median_ns < y->median_ns);
    return (x->max_error > y->max_error) - (x->max_error < y->max_error);
}

/* Writes the Pareto front of the rows of one variant (NULL: of every row) as the inline data
 * block $name: sorted by time, each point more accurate than every faster one. The last
 * error is repeated at x_end so the step line spans the chart: all that lies above and to
 * the right of it is dominated. Comma-separated, as the script's data separator says. */
static int write_front(FILE *f, const bench_table *t, const char *variant, const char *input_set,
                       const char *name, double x_end)
{
    const bench_row **rows = malloc((t->n ? t->n : 1) * sizeof *rows);
    if (!rows) return -1;
    size_t m = 0;
    for (size_t i = 0; i < t->n; ++i) {
        const bench_row *r = &t->rows[i];
        if ((!variant || strcmp(r->variant, variant) == 0) &&
            (!input_set || strcmp(r->input_set, input_set) == 0) && r->failures == 0 &&
            isfinite(r->median_ns) && isfinite(r->max_error))
            rows[m++] = r;
    }
    qsort(rows, m, sizeof *rows, cmp_time_error);
    fprintf(f, "$%s << EOD\n", name);
    double best = INFINITY;
    for (size_t i = 0; i < m; ++i) {
        double e = floored(rows[i]->max_error);
        if (!(e < best)) continue;
        best = e;
        fprintf(f, "%.6g,%.6e,%s\n", rows[i]->median_ns, e, rows[i]->method);
    }
    if (m) fprintf(f, "%.6g,%.6e,end\n", x_end, best);
    fprintf(f, "EOD\n\n");
    free(rows);
    return 0;
}

/* The distinct variants in first-appearance order; returns how many (at most cap). */
static int variants(const bench_table *t, const char **out, int cap)
{
    int nv = 0;
    for (size_t i = 0; i < t->n; ++i) {
        int seen = 0;
        for (int j = 0; j < nv && !seen; ++j) seen = strcmp(out[j], t->rows[i].variant) == 0;
        if (!seen && nv < cap) out[nv++] = t->rows[i].variant;
    }
    return nv;
}

#define MAX_VARIANTS 16

/* 1-based index of a column of the CSV header (gnuplot numbers columns from 1). */
static int column(const char *name)
{
    const char *h = bench_csv_header;
    size_t n = strlen(name);
    for (int i = 1;; ++i) {
        if (strncmp(h, name, n) == 0 && (h[n] == ',' || h[n] == '\0')) return i;
        h = strchr(h, ',');
        if (!h) return 0;
        ++h;
    }
}

static int write_script(const void *arg, FILE *f)
{
    const plot_args *a = arg;
    const bench_chart *c = a->c;
    const bench_table *t = a->t;
    static const int pts[] = {7, 5, 9, 11, 13, 15, 4, 6, 8, 10};
    const char *v[MAX_VARIANTS];
    int nv = variants(t, v, MAX_VARIANTS);
    int c_name = column("method"), c_var = column("variant"), c_time = column("median_ns"),
        c_err = column("max_error");
    double x_max = 0, y_max = BENCH_ERROR_FLOOR;
    const char *base_set = NULL;
    for (size_t i = 0; i < t->n; ++i) {
        if (t->rows[i].median_ns > x_max) x_max = t->rows[i].median_ns;
        if (t->rows[i].max_error > y_max) y_max = t->rows[i].max_error;
        if (t->baseline && strcmp(t->rows[i].method, t->baseline) == 0)
            base_set = t->rows[i].input_set;
    }
    fprintf(f,
            "# Generated by headplan-bench from %s.csv (columns: %s).\n"
            "# Redraw: cd into this folder and run: gnuplot %s_pareto.gp\n"
            "set datafile separator comma\n"
            "floor = %g\n"
            "fl(e) = (e > floor) ? e : floor\n"
            "set logscale xy\n"
            "set format x \"10^{%%L}\"\n"
            "set format y \"10^{%%L}\"\n"
            "set xlabel \"%s\"\n"
            "set ylabel \"%s\"\n"
            "set title \"%s\\n{/*0.8 Errors below %g (exact zeros included) are drawn at "
            "%g.}\\n{/*0.8 Thick dashed: Pareto front among the methods run on the baseline's "
            "inputs; thin dotted: front of each series.}\"\n"
            "set grid xtics ytics mxtics mytics lc rgb \"#e0e0e0\"\n"
            "set key outside right top box opaque noenhanced\n"
            "set yrange [floor / 4 : %.3g]\n"
            "set xrange [* : %.6g]\n\n",
            c->family, bench_csv_header, c->family, BENCH_ERROR_FLOOR, c->xlabel, c->ylabel,
            c->title, BENCH_ERROR_FLOOR, BENCH_ERROR_FLOOR, 100 * y_max, 3 * x_max);
    if (write_front(f, t, NULL, base_set, "front", 3 * x_max) != 0) return -1;
    for (int k = 0; k < nv; ++k) {
        char name[32];
        snprintf(name, sizeof name, "front%d", k + 1);
        if (write_front(f, t, v[k], NULL, name, 3 * x_max) != 0) return -1;
    }
    fprintf(f, "if (strstrt(GPVAL_TERMINALS, \"pngcairo\") > 0) {\n"
               "  set terminal pngcairo size 1400,900 enhanced font \"Sans,11\"\n"
               "} else {\n"
               "  set terminal png size 1400,900\n"
               "}\n"
               "set output ");
    /* The file names and the series (variants) reach the script through cli_gptext.h: the
     * CSV's name as a quoted string, a variant as quoted text compared with the CSV's
     * column and shown in the key. */
    char csv[64], png[64], svg[64];
    snprintf(csv, sizeof csv, "%s.csv", c->family);
    snprintf(png, sizeof png, "%s_pareto.png", c->family);
    snprintf(svg, sizeof svg, "%s_pareto.svg", c->family);
    if (gp_path(f, png) != 0) return -1;
    fprintf(f, "\nplot \\\n");
    for (int k = 0; k < nv; ++k) {
        fprintf(f, "  ");
        if (gp_path(f, csv) != 0) return -1;
        fprintf(f, " skip 1 using %d:(strcol(%d) eq ", c_time, c_var);
        gp_label(f, v[k]);
        fprintf(f, " ? fl($%d) : NaN) with points pt %d ps 1.5 lc %d title ", c_err, pts[k % 10],
                k + 1);
        gp_label(f, v[k]);
        fprintf(f, ", \\\n  $front%d using 1:2 with steps dt 3 lw 1 lc %d notitle, \\\n", k + 1,
                k + 1);
    }
    fprintf(
        f,
        "  $front using 1:2 with steps dt 2 lw 2.5 lc rgb \"#303030\" title \"Pareto front\", \\\n"
        "  floor with lines dt 4 lc rgb \"#909090\" title sprintf(\"floor %%g\", floor), \\\n"
        "  ");
    if (gp_path(f, csv) != 0) return -1;
    fprintf(f,
            " skip 1 using %d:(fl($%d)):%d with labels noenhanced font \",7\" left rotate by 25 "
            "offset char 0.7, char 0.3 tc rgb \"#202020\" notitle\n"
            "set terminal svg size 1400,900 dynamic enhanced font \"Sans,11\"\n"
            "set output ",
            c_time, c_err, c_name);
    if (gp_path(f, svg) != 0) return -1;
    fprintf(f, "\nreplot\nunset output\n");
    return ferror(f) ? -1 : 0;
}

static int nonempty(const char *dir, const char *family, const char *suffix)
{
    char p[PATH_CAP];
    struct stat st;
    if (snprintf(p, sizeof p, "%s/%s%s", dir, family, suffix) >= (int)sizeof p) return 0;
    return stat(p, &st) == 0 && st.st_size > 0;
}

int bench_gnuplot_run(const char *dir, const char *script, const char *const *outputs)
{
    char *const argv[] = {"gnuplot", hpi_unconst(script), NULL};
    int st = bench_run_child(argv, dir, 0);
    if (st != 0) {
        cli_fail(0, "bench", "gnuplot failed on '%s/%s' (%s %d)", dir, script,
                 st < 0 ? "could not run, status" : "exit status", st);
        return CLI_EXIT_SOFTWARE;
    }
    for (; outputs && *outputs; ++outputs)
        if (!nonempty(dir, *outputs, "")) {
            cli_fail(0, "bench", "gnuplot left '%s/%s' missing or empty", dir, *outputs);
            return CLI_EXIT_SOFTWARE;
        }
    return 0;
}

int bench_plot(const bench_table *t, const bench_chart *c, const char *dir)
{
    char script[256];
    snprintf(script, sizeof script, "%s_pareto.gp", c->family);
    plot_args a = {t, c};
    int rc = bench_save(dir, script, write_script, &a);
    if (rc) return rc;
    char *const argv[] = {"gnuplot", script, NULL};
    int st = bench_run_child(argv, dir, 0);
    if (st != 0) {
        cli_fail(0, "bench", "gnuplot failed on '%s/%s' (%s %d)", dir, script,
                 st < 0 ? "could not run, status" : "exit status", st);
        return CLI_EXIT_SOFTWARE;
    }
    if (!nonempty(dir, c->family, "_pareto.png") || !nonempty(dir, c->family, "_pareto.svg")) {
        cli_fail(0, "bench", "gnuplot left '%s/%s_pareto.png' or .svg missing or empty", dir,
                 c->family);
        return CLI_EXIT_SOFTWARE;
    }
    return 0;
}
