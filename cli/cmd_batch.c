/* headplan batch: plan every row of a trace, in order, into CSV or JSON Lines. */
#define _POSIX_C_SOURCE 200809L
#include "cli/batch.h"
#include "cli/batch_output.h"
#include "cli/cli_scene.h"
#include "cli/commands.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static const char *const CMD = "batch";

static void help(void)
{
    printf("usage: headplan batch SCENE [TRACE] [-o OUT] [--format csv|jsonl]\n"
           "                      [--backend NAME] [--level NAME] [--rows deviation|correction]\n"
           "                      [--jobs N] [--no-progress] [--no-times]\n\n"
           "Plans every row of TRACE (default: the scene's trace) with the scene's layout and\n"
           "writes one output row per input row, in order: line, t_s, status, achieved pose\n"
           "(mm, deg), pose_error, each bladder's pressure (Pa), binding limits, iterations\n"
           "and solve_time_us. Rate limits carry from row to row (each plan starts from the\n"
           "previous row's pressures). A bad row is reported on stderr with its line and\n"
           "gets status bad-row; the others go on. -o writes OUT.partial-PID and renames it\n"
           "to OUT only when complete. --jobs N runs N processes and gives the same output\n"
           "as one job. --no-times drops the solve_time_us column (a measurement), so two\n"
           "runs' outputs are byte-identical. A summary goes to stderr.\n\n"
           "exit: 0 all reached, 1 some only closest, 65 bad rows or scene, 66 no input,\n"
           "70 solver failure, 73 cannot write OUT\n");
}

typedef struct {
    const char *scene, *trace, *out, *format, *backend, *level, *rows;
    long jobs;
    int progress, times;
} batch_args;

static int parse(int argc, char **argv, batch_args *a)
{
    a->jobs = 1;
    a->progress = 1;
    a->times = 1;
    int npos = 0, jobs_given = 0;
    for (int i = 1; i < argc; ++i) {
        const char *v = NULL;
        int m;
        if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0) {
            help();
            return HP_EXIT_OK;
        }
        if (strcmp(argv[i], "--no-progress") == 0) { a->progress = 0; continue; }
        if (strcmp(argv[i], "--no-times") == 0) { a->times = 0; continue; }
#define OPT(name, field)                                                                      \
    if ((m = hp_cli_opt(CMD, argc, argv, &i, name, &v)) != 0) {                               \
        if (m < 0) return HP_EXIT_USAGE;                                                      \
        if (a->field)                                                                         \
            return hp_cli_fail(HP_EXIT_USAGE, CMD, "%s: given more than once", name);         \
        a->field = v;                                                                         \
        continue;                                                                             \
    }
        OPT("-o", out)
        OPT("--format", format)
        OPT("--backend", backend)
        OPT("--level", level)
        OPT("--rows", rows)
#undef OPT
        if ((m = hp_cli_opt(CMD, argc, argv, &i, "--jobs", &v)) != 0) {
            if (m < 0) return HP_EXIT_USAGE;
            if (jobs_given++)
                return hp_cli_fail(HP_EXIT_USAGE, CMD, "--jobs: given more than once");
            int rc = hp_cli_int(CMD, "--jobs", v, 1, 64, &a->jobs);
            if (rc) return rc;
            continue;
        }
        if (argv[i][0] == '-' && argv[i][1] != '\0')
            return hp_cli_fail(HP_EXIT_USAGE, CMD, "unknown option '%s' (see --help)", argv[i]);
        if (npos == 0) a->scene = argv[i];
        else if (npos == 1) a->trace = argv[i];
        else return hp_cli_fail(HP_EXIT_USAGE, CMD, "unexpected argument '%s'", argv[i]);
        ++npos;
    }
    if (!a->scene) return hp_cli_fail(HP_EXIT_USAGE, CMD, "missing SCENE (see --help)");
    return -1;
}

/* Reads every row first: shards need random access, and bad rows are reported in order. */
static int read_rows(const char *path, const hp_trace_rows *rows_override, batch_in **out,
                     size_t *count, size_t *bad)
{
    hp_trace_reader *r = NULL;
    hp_diag d = {{0}};
    hp_error e = hp_trace_open(path, rows_override, &r, &d);
    if (e != HP_OK)
        return hp_cli_fail(e == HP_ERR_IO ? HP_EXIT_NOINPUT : HP_EXIT_DATAERR, CMD, "%s", d.text);
    size_t n = 0, cap = 1024;
    batch_in *rows = malloc(cap * sizeof *rows);
    *bad = 0;
    for (;;) {
        if (!rows) {
            hp_trace_close(r);
            return hp_cli_fail(HP_EXIT_SOFTWARE, CMD, "out of memory");
        }
        hp_trace_row row;
        e = hp_trace_next(r, &row, &d);
        if (e == HP_END) break;
        if (e == HP_ERR_IO) {
            hp_trace_close(r);
            free(rows);
            return hp_cli_fail(HP_EXIT_NOINPUT, CMD, "%s", d.text);
        }
        if (n == cap) {
            cap *= 2;
            batch_in *grown = realloc(rows, cap * sizeof *rows);
            if (!grown) free(rows);
            rows = grown;
            if (!rows) continue;
        }
        batch_in *b = &rows[n++];
        memset(b, 0, sizeof *b);
        if (e == HP_OK) {
            b->line = row.line;
            b->t = row.t;
            memcpy(b->correction, row.correction, sizeof b->correction);
        } else {
            /* The message starts "FILE:LINE:"; keep the line for the output row. */
            const char *colon = strchr(d.text, ':');
            b->line = colon ? strtol(colon + 1, NULL, 10) : 0;
            b->bad = 1;
            b->msg = strdup(d.text);
            ++*bad;
        }
    }
    hp_trace_close(r);
    *out = rows;
    *count = n;
    return 0;
}

static void draw_progress(size_t done, size_t total)
{
    int width = 40, fill = total ? (int)((double)width * (double)done / (double)total) : width;
    fprintf(stderr, "\r[");
    for (int i = 0; i < width; ++i) fputc(i < fill ? '#' : '.', stderr);
    fprintf(stderr, "] %3d%% %zu/%zu", total ? (int)(100.0 * (double)done / (double)total) : 100,
            done, total);
    fflush(stderr);
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Prints the summary and returns the exit status the rows call for. */
static int summarise(const batch_in *in, const batch_out *out, size_t rows, int jobs,
                     size_t repaired)
{
    size_t reached = 0, closest = 0, failed = 0, bad = 0, invalid = 0;
    double worst_closest = 0.0, worst_reached = 0.0;
    double *times = malloc((rows + 1) * sizeof *times);
    size_t nt = 0;
    for (size_t i = 0; i < rows; ++i) {
        const batch_out *o = &out[i];
        if (o->bad) {
            fprintf(stderr, "headplan batch: %s\n", in[i].msg ? in[i].msg : "bad row");
            ++bad;
            continue;
        }
        if (times) times[nt++] = o->solve_time;
        switch (o->status) {
        case HP_STATUS_REACHED:
            ++reached;
            if (o->pose_error > worst_reached) worst_reached = o->pose_error;
            break;
        case HP_STATUS_CLOSEST:
            ++closest;
            if (o->pose_error > worst_closest) worst_closest = o->pose_error;
            break;
        case HP_STATUS_INVALID_INPUT:
            ++invalid;
            fprintf(stderr, "headplan batch: line %ld: invalid correction\n", in[i].line);
            break;
        default:
            ++failed;
            fprintf(stderr, "headplan batch: line %ld: %s\n", in[i].line,
                    hp_status_name(o->status));
            break;
        }
    }
    fprintf(stderr,
            "headplan batch: %zu rows: %zu reached, %zu closest, %zu failed, %zu invalid, "
            "%zu bad rows\n",
            rows, reached, closest, failed, invalid, bad);
    fprintf(stderr,
            "headplan batch: worst pose error %.3g (mm or deg) on reached rows, %.3g on "
            "closest rows\n",
            worst_reached, worst_closest);
    if (times && nt) {
        qsort(times, nt, sizeof *times, cmp_double);
        size_t p99 = (size_t)ceil(0.99 * (double)nt) - 1;
        fprintf(stderr,
                "headplan batch: time per plan: median %.1f us, p99 %.1f us; %d job%s, %zu "
                "row%s re-planned at shard joins\n",
                times[nt / 2] * 1e6, times[p99] * 1e6, jobs, jobs == 1 ? "" : "s", repaired,
                repaired == 1 ? "" : "s");
    }
    free(times);
    if (failed) return HP_EXIT_SOFTWARE;
    if (bad || invalid) return HP_EXIT_DATAERR;
    return closest ? HP_EXIT_CLOSEST : HP_EXIT_OK;
}

int hp_cmd_batch(int argc, char **argv)
{
    batch_args a = {0};
    int rc = parse(argc, argv, &a);
    if (rc >= 0) return rc;
    hp_trace_format fmt = HP_TRACE_CSV;
    if (a.format && hp_trace_format_parse(a.format, &fmt) != HP_OK)
        return hp_cli_fail(HP_EXIT_USAGE, CMD, "--format: unknown format '%s' (csv, jsonl)",
                           a.format);
    hp_trace_rows rows_kind;
    if (a.rows && hp_trace_rows_parse(a.rows, &rows_kind) != HP_OK)
        return hp_cli_fail(HP_EXIT_USAGE, CMD,
                           "--rows: '%s' is neither 'deviation' nor 'correction'", a.rows);

    hp_scene *sc = NULL;
    if ((rc = hp_cli_load_scene(CMD, a.scene, 1, &sc))) return rc;
    hp_settings s;
    if ((rc = hp_cli_settings(CMD, sc, a.backend, a.level, &s))) {
        free(sc);
        return rc;
    }
    const char *trace = a.trace;
    hp_trace_rows scene_rows = sc->trace_rows;
    const hp_trace_rows *override = a.rows ? &rows_kind : NULL;
    if (!trace) {
        if (!sc->has_trace) {
            free(sc);
            return hp_cli_fail(HP_EXIT_USAGE, CMD,
                               "missing TRACE (the scene %s names no trace)", a.scene);
        }
        trace = sc->trace_path;
        if (!override) override = &scene_rows;
    }
    batch_in *in = NULL;
    size_t n = 0, nbad = 0;
    if ((rc = read_rows(trace, override, &in, &n, &nbad))) {
        free(sc);
        return rc;
    }
    batch_out *out = calloc(n + 1, sizeof *out);
    size_t repaired = 0;
    int show = a.progress && isatty(2);
    /* Create the output before planning: an unwritable -o must not cost a whole run. */
    FILE *dest = out ? batch_open(a.out) : NULL;
    if (!out) {
        rc = hp_cli_fail(HP_EXIT_SOFTWARE, CMD, "out of memory");
    } else if (!dest) {
        rc = HP_EXIT_CANTCREAT;
    } else if (batch_run(&sc->layout, &s, in, out, n, (int)a.jobs, show ? draw_progress : NULL,
                         &repaired) != 0) {
        batch_abandon(dest, a.out);
        rc = hp_cli_fail(HP_EXIT_SOFTWARE, CMD, "%s: the run failed; no output written", trace);
    } else {
        if (show) fputc('\n', stderr);
        /* The planner prepares its own copy of the layout; the names are the scene's. */
        rc = batch_write(dest, a.out, fmt, &sc->layout, in, out, n, a.times);
        int status = summarise(in, out, n, (int)a.jobs, repaired);
        if (rc == 0) rc = status;
    }
    for (size_t i = 0; i < n; ++i) free(in[i].msg);
    free(in);
    free(out);
    free(sc);
    return rc;
}
