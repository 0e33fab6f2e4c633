/* headplan batch: plan every row of a trace, in order, into CSV or JSON Lines, streaming:
 * memory does not grow with the number of rows. */
#define _POSIX_C_SOURCE 200809L
#include "cli/batch.h"
#include "cli/batch_output.h"
#include "cli/cli_output.h"
#include "cli/cli_scene.h"
#include "cli/cmd_solve_load.h"
#include "cli/commands.h"
#include "cli/sha256.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static const char *const CMD = "batch";

/* Rows planned per block and job: large enough that a fork per block costs little, small
 * enough that memory stays a few MB. */
#define BLOCK_PER_JOB 8192

static void help(void)
{
    printf("usage: headplan batch SCENE [TRACE|-] [-o OUT|-] [--format csv|jsonl]\n"
           "                      [--rows deviation|correction] [--backend NAME] [--level NAME]\n"
           "                      [--jobs N] [--strict] [--no-progress] [--no-times]\n"
           "       headplan batch --columns\n\n"
           "Plans every row of TRACE (default: the scene's trace; '-': standard input, read\n"
           "as a stream) with the scene's layout and writes one output row per input row, in\n"
           "order, after a metadata record: desired, achieved and error pose (mm, deg), the\n"
           "commanded directions, pose_error_mm and _deg, each bladder's pressure (Pa), radii\n"
           "(mm) and stretch, binding limits, iterations and solve_time_us (all of them:\n"
           "--columns). Rate limits carry\n"
           "from row to row. A bad row is reported on stderr with its line and gets status\n"
           "bad-row; the others go on.\n\n"
           "The kind of rows is never guessed: the trace's first line\n"
           "'# headplan-trace: rows=deviation' (or =correction; JSON Lines: a first record\n"
           "{\"headplan_trace\": 1, \"rows\": ...}), --rows, or the scene's trace.rows when the\n"
           "scene's own trace is used. Two that disagree, or none: an error. A deviation's\n"
           "correction is its exact inverse rigid motion about the pivot.\n\n"
           "-o OUT writes a temporary file beside OUT and renames it when complete; OUT may\n"
           "not be a symbolic link, a device or FIFO, or an input. -o - (or no -o) is\n"
           "standard output. The format is --format, else OUT's extension (.csv, .jsonl),\n"
           "else an error (standard output has no extension: give --format). --jobs N runs\n"
           "N processes and gives the same output as one job.\n"
           "--columns lists the output's columns (name, unit, format, shape, in the rows,\n"
           "Python key, measured) as tab-separated lines, for scripts.\n"
           "--no-times drops the measured columns (solve_time_us) so two runs' outputs are\n"
           "byte-identical. Rows stopped by the time budget (solver.max_time_s) depend on\n"
           "machine load: their output is not reproducible run to run; the summary on\n"
           "stderr counts them.\n\n"
           "exit: 0 finished (rows reached, closest or uncommanded), 1 some only closest\n"
           "with --strict, 2 some uncommanded with --strict, 64 usage, 65 bad rows, rows\n"
           "the planner refused (invalid-input, the reason on stderr), bad scene or rows\n"
           "kind, 66 no input, 70 solver failure or time/iteration limit, 73 OUT refused or\n"
           "cannot be created, 74 a write failed\n");
}

typedef struct {
    const char *scene, *trace, *out, *format, *backend, *level, *rows;
    long jobs;
    int progress, times, strict;
} batch_args;

static int parse(int argc, char **argv, batch_args *a)
{
    const char *jobs = NULL;
    int no_progress = 0, no_times = 0;
    const char *const names[] = {"-o", "--format", "--backend", "--level", "--rows", "--jobs"};
    const char **slots[] = {&a->out, &a->format, &a->backend, &a->level, &a->rows, &jobs};
    const char *const flags[] = {"--no-progress", "--no-times", "--strict"};
    int *const flag_slots[] = {&no_progress, &no_times, &a->strict};
    const cli_grammar g = {help,       names,  slots, 6,    flags,
                           flag_slots, 3,      NULL,  NULL, {&a->scene, &a->trace},
                           2,          "SCENE"};
    int rc = cli_parse(CMD, argc, argv, &g);
    if (rc >= 0) return rc;
    a->progress = !no_progress;
    a->times = !no_times;
    a->jobs = 1;
    if (jobs && (rc = cli_int(CMD, "--jobs", jobs, 1, 64, &a->jobs))) return rc;
    return -1;
}

/* ---- the summary: counts and a log-histogram of plan times (memory flat in rows) ---- */

#define TIME_BINS 1000 /* 100 per decade from 0.01 us to 1e8 us: quantiles to 2.3 % */

typedef struct {
    size_t rows, reached, closest, uncommanded, failed, time_limit, invalid, bad;
    double unc_max[6];                /* largest |uncommanded part| per axis, mm or deg */
    double worst_mm[2], worst_deg[2]; /* [0] reached rows, [1] closest rows */
    size_t time_bin[TIME_BINS], timed;
} summary;

static void tally(summary *S, const batch_in *in, const batch_out *out, size_t rows,
                  const char *trace, batch_engine *eng)
{
    for (size_t i = 0; i < rows; ++i) {
        const batch_out *o = &out[i];
        S->rows++;
        if (o->bad) {
            S->bad++;
            continue;
        }
        double us = o->r.solve_time * 1e6;
        double at = us > 0 ? floor((log10(us) + 2.0) * 100.0) : 0.0;
        int bin = at < 0 ? 0 : at >= TIME_BINS ? TIME_BINS - 1 : (int)at; /* clamp, then cast */
        S->time_bin[bin]++;
        S->timed++;
        int which = -1;
        switch (o->r.status) {
        case HP_STATUS_REACHED:
            S->reached++;
            which = 0;
            break;
        case HP_STATUS_CLOSEST:
            S->closest++;
            which = 1;
            break;
        case HP_STATUS_UNCOMMANDED:
            S->uncommanded++;
            which = 0;
            break;
        case HP_STATUS_INVALID_INPUT:
            S->invalid++;
            fprintf(stderr, "headplan batch: %s:%ld: %s\n", trace, in->row[i].line,
                    batch_engine_reason(eng, in, out, i));
            break;
        default:
            S->failed++;
            if (o->r.status == HP_STATUS_TIME_LIMIT) S->time_limit++;
            fprintf(stderr, "headplan batch: %s:%ld: %s\n", trace, in->row[i].line,
                    hp_status_name(o->r.status));
            break;
        }
        if (which < 0) continue;
        double want[6], got[6], unc[6];
        hp_pose_to_clinical(o->r.uncommanded, unc);
        for (int k = 0; k < 6; ++k)
            if (fabs(unc[k]) > S->unc_max[k]) S->unc_max[k] = fabs(unc[k]);
        hp_pose_to_clinical(in->row[i].correction, want);
        hp_pose_to_clinical(o->r.achieved, got);
        for (int k = 0; k < 6; ++k) {
            if (!o->r.commanded[k]) continue;
            double e = fabs(got[k] - (want[k] - unc[k])); /* against the commanded part */
            double *w = k < 3 ? &S->worst_mm[which] : &S->worst_deg[which];
            if (e > *w) *w = e;
        }
    }
}

static double time_quantile(const summary *S, double q)
{
    size_t want = (size_t)ceil(q * (double)S->timed), seen = 0;
    for (int b = 0; b < TIME_BINS; ++b) {
        seen += S->time_bin[b];
        if (seen >= want && seen > 0) return pow(10.0, (b + 1) / 100.0 - 2.0);
    }
    return 0.0;
}

/* Prints the summary and returns the exit status the rows call for. */
static int summarise(const summary *S, int jobs, size_t repaired, int strict)
{
    fprintf(stderr,
            "headplan batch: %zu rows: %zu reached, %zu closest, %zu uncommanded, %zu failed "
            "(%zu at the time budget), %zu invalid, %zu bad rows\n",
            S->rows, S->reached, S->closest, S->uncommanded, S->failed, S->time_limit, S->invalid,
            S->bad);
    if (S->uncommanded) {
        static const char *const axis[6] = {"x", "y", "z", "pitch", "roll", "yaw"};
        fprintf(stderr, "headplan batch: not commanded (the layout cannot observe it), largest:");
        for (int k = 0; k < 6; ++k)
            if (S->unc_max[k] > 0)
                fprintf(stderr, " %s %.3g %s", axis[k], S->unc_max[k], k < 3 ? "mm" : "deg");
        fputc('\n', stderr);
    }
    fprintf(stderr,
            "headplan batch: worst pose error %.3g mm, %.3g deg on reached rows; %.3g mm, "
            "%.3g deg on closest rows\n",
            S->worst_mm[0], S->worst_deg[0], S->worst_mm[1], S->worst_deg[1]);
    if (S->timed)
        fprintf(stderr,
                "headplan batch: time per plan: median %.3g us, p99 %.3g us (to 2.3%%); %d "
                "job%s, %zu row%s re-planned at shard joins\n",
                time_quantile(S, 0.5), time_quantile(S, 0.99), jobs, jobs == 1 ? "" : "s", repaired,
                repaired == 1 ? "" : "s");
    if (S->time_limit)
        fprintf(stderr,
                "headplan batch: %zu row%s stopped at the time budget: their output depends on "
                "machine load and is not reproducible run to run\n",
                S->time_limit, S->time_limit == 1 ? "" : "s");
    if (S->failed) return CLI_EXIT_SOFTWARE;
    if (S->bad || S->invalid) return CLI_EXIT_DATAERR;
    if (strict && S->uncommanded) return CLI_EXIT_UNCOMMANDED;
    return S->closest && strict ? CLI_EXIT_CLOSEST : CLI_EXIT_OK;
}

/* ---- inputs ---- */

typedef struct {
    FILE *f;
    const char *name; /* for messages */
    char sha[65];
    int hashed; /* a regular file, hashed before reading */
    struct stat st;
} trace_input;

/* Opens TRACE ("-": stdin) and hashes it when it is a regular file. */
static int open_trace(const char *path, trace_input *t)
{
    memset(t, 0, sizeof *t);
    if (strcmp(path, "-") == 0) {
        t->f = stdin;
        t->name = "<stdin>";
    } else {
        t->name = path;
        if (!(t->f = fopen(path, "rb")))
            return cli_fail(CLI_EXIT_NOINPUT, CMD, "%s: cannot open: %s", path, strerror(errno));
    }
    int rc = cli_stdout_not_input(CMD, "trace", t->name, fileno(t->f), NULL);
    if (rc) return rc;
    if (fstat(fileno(t->f), &t->st) != 0 || S_ISDIR(t->st.st_mode))
        return cli_fail(CLI_EXIT_NOINPUT, CMD, "%s: cannot read: %s", t->name,
                        strerror(S_ISDIR(t->st.st_mode) ? EISDIR : errno));
    if (S_ISREG(t->st.st_mode) && t->f != stdin) {
        if (sha256_file(path, t->sha) != 0)
            return cli_fail(CLI_EXIT_NOINPUT, CMD, "%s: cannot read: %s", path, strerror(errno));
        t->hashed = 1;
    }
    return 0;
}

static void close_trace(trace_input *t)
{
    if (t->f && t->f != stdin) fclose(t->f);
    t->f = NULL;
}

/* Settles where the kind of rows comes from and opens the reader. */
static int open_reader(const batch_args *a, const hp_scene *sc, const trace_input *t,
                       hp_trace_reader **r)
{
    hp_trace_rows opt = HP_TRACE_CORRECTION, scene_rows = sc->trace_rows;
    if (a->rows && hp_trace_rows_parse(a->rows, &opt) != HP_OK)
        return cli_fail(CLI_EXIT_USAGE, CMD, "--rows: '%s' is neither 'deviation' nor 'correction'",
                        a->rows);
    int scene_trace = !a->trace; /* the scene's trace.rows speaks only for its own trace */
    if (a->rows && scene_trace && opt != scene_rows)
        return cli_fail(CLI_EXIT_DATAERR, CMD,
                        "--rows says %s but the scene's trace.rows says %s: they must agree",
                        hp_trace_rows_name(opt), hp_trace_rows_name(scene_rows));
    const hp_trace_rows *given = a->rows ? &opt : scene_trace ? &scene_rows : NULL;
    const char *from = a->rows ? "--rows" : scene_trace ? "the scene's trace.rows" : "--rows";
    hp_diag d = {{0}};
    hp_error e = hp_trace_open_stream(t->f, t->name, given, from, r, &d);
    if (e != HP_OK)
        return cli_fail(e == HP_ERR_IO ? CLI_EXIT_NOINPUT : CLI_EXIT_DATAERR, CMD, "%s", d.text);
    return 0;
}

/* Reads up to cap rows into in; *end is set at the end of the trace. Bad rows are reported
 * at once, in order. Returns 0, or an exit status when reading cannot go on. */
static int read_block(hp_trace_reader *r, batch_in *in, size_t cap, size_t *n, int *end)
{
    *n = 0;
    while (*n < cap) {
        hp_trace_row row;
        hp_diag d = {{0}};
        hp_error e = hp_trace_next(r, &row, &d);
        if (e == HP_END) {
            *end = 1;
            return 0;
        }
        if (e == HP_ERR_IO) return cli_fail(CLI_EXIT_NOINPUT, CMD, "%s", d.text);
        if (e != HP_OK && e != HP_ERR_PARSE) return cli_fail(CLI_EXIT_DATAERR, CMD, "%s", d.text);
        size_t i = (*n)++;
        memset(&in->row[i], 0, sizeof in->row[i]);
        in->row[i].line = row.line;
        in->bad[i] = e != HP_OK;
        in->msg[i] = NULL;
        if (e == HP_OK) {
            in->row[i] = row;
        } else {
            in->msg[i] = strdup(d.text);
            cli_fail(0, CMD, "%s", d.text);
        }
    }
    return 0;
}

/* Plans the whole trace block by block into the sink. */
static int run_blocks(const batch_args *a, hp_trace_reader *r, const char *r_name,
                      batch_engine *eng, batch_sink *sink, summary *S)
{
    size_t cap = (size_t)BLOCK_PER_JOB * (size_t)a->jobs;
    batch_in block = {calloc(cap, sizeof *block.row), calloc(cap, sizeof *block.bad),
                      calloc(cap, sizeof *block.msg)},
             *in = &block;
    batch_out *out = calloc(cap, sizeof *out);
    int rc = in->row && in->bad && in->msg && out
                 ? 0
                 : cli_fail(CLI_EXIT_SOFTWARE, CMD, "out of memory");
    int end = 0, show = a->progress && isatty(2);
    while (rc == 0 && !end) {
        size_t n = 0;
        rc = read_block(r, in, cap, &n, &end);
        if (rc == 0 && n > 0 && batch_engine_run(eng, in, out, n) != 0)
            rc = cli_fail(CLI_EXIT_SOFTWARE, CMD, "the run failed; no output written");
        if (rc == 0) {
            tally(S, in, out, n, r_name, eng);
            if (batch_sink_rows(sink, in, out, n) != 0) rc = CLI_EXIT_IOERR;
        }
        for (size_t i = 0; i < n; ++i) free(in->msg[i]);
        if (show) fprintf(stderr, "\r%zu rows", S->rows);
    }
    if (show) fputc('\n', stderr);
    free(in->row);
    free(in->bad);
    free(in->msg);
    free(out);
    return rc;
}

int cmd_batch(int argc, char **argv)
{
    for (int i = 1; i < argc && strcmp(argv[i], "--") != 0; ++i)
        if (strcmp(argv[i], "--columns") == 0 && !cli_wants_help(argc, argv, 1)) {
            if (argc != 2)
                return cli_fail(CLI_EXIT_USAGE, CMD,
                                "--columns: lists the columns and takes no other argument");
            batch_columns_print(stdout);
            return 0;
        }
    batch_args a = {0};
    int rc = parse(argc, argv, &a);
    if (rc >= 0) return rc;
    hp_trace_format fmt = HP_TRACE_CSV;
    if ((rc = batch_output_format(a.format, a.out, &fmt))) return rc;

    hp_scene *sc = NULL;
    char scene_sha[65], *scene_text = NULL;
    size_t scene_len = 0;
    if ((rc = cli_load_scene_text(CMD, a.scene, NULL, &sc, &scene_text, &scene_len))) return rc;
    sha256_bytes(scene_text, scene_len, scene_sha);
    free(scene_text);
    hp_settings s;
    struct stat scene_st;
    if ((rc = cli_settings(CMD, sc, a.backend, a.level, &s))) {
        free(sc);
        return rc;
    }
    if ((strcmp(a.scene, "-") == 0 ? fstat(STDIN_FILENO, &scene_st) : stat(a.scene, &scene_st)) !=
        0) {
        free(sc);
        return cli_fail(CLI_EXIT_NOINPUT, CMD, "%s: cannot read: %s", a.scene, strerror(errno));
    }
    if (!a.trace && !sc->has_trace) {
        free(sc);
        return cli_fail(CLI_EXIT_USAGE, CMD, "missing TRACE (the scene %s names no trace)",
                        cli_name(a.scene));
    }
    const char *trace_path = a.trace ? a.trace : sc->trace_path;
    trace_input t = {0};
    hp_trace_reader *r = NULL;
    batch_sink sink = {0};
    batch_engine eng = {0};
    summary *S = calloc(1, sizeof *S);
    rc = S ? open_trace(trace_path, &t) : cli_fail(CLI_EXIT_SOFTWARE, CMD, "out of memory");
    if (rc == 0) rc = open_reader(&a, sc, &t, &r);
    if (rc == 0) {
        /* The trace by the identity of what was opened: standard input redirected from a
         * file protects that file too. */
        cli_input ids[3] = {{"scene", cli_name(a.scene), scene_st.st_dev, scene_st.st_ino,
                             S_ISREG(scene_st.st_mode)},
                            {"trace", t.name, t.st.st_dev, t.st.st_ino, 1}};
        /* The scene's own trace when another one is planned: the user's data all the same. */
        int nid = 2;
        if (sc->has_trace) cli_input_of(&ids[nid++], "scene's trace", sc->trace_path);
        rc = batch_sink_open(&sink, a.out, fmt, &sc->layout, a.times, ids, nid);
    }
    if (rc == 0 && batch_engine_init(&eng, &sc->layout, &s, (int)a.jobs) != 0)
        rc = CLI_EXIT_SOFTWARE;
    if (rc == 0) {
        const char *from = hp_trace_states_rows(r) ? "trace"
                           : a.rows                ? "--rows"
                                                   : "scene trace.rows";
        char level_why[HP_DIAG_MAX]; /* the planner's reason, whole */
        hp_planner_level_choice(eng.p, level_why, sizeof level_why); /* built: HP_OK */
        const batch_meta meta = {cli_name(a.scene),
                                 scene_sha,
                                 a.trace ? a.trace : trace_path,
                                 t.hashed ? t.sha : NULL,
                                 hp_trace_rows_name(hp_trace_rows_of(r)),
                                 from,
                                 hp_trace_form_name(hp_trace_form_of(r)),
                                 hp_level_name(hp_planner_level(eng.p)),
                                 level_why[0] ? level_why : NULL,
                                 &s};
        batch_sink_meta(&sink, &meta);
        rc = run_blocks(&a, r, t.name, &eng, &sink, S);
    }
    if (rc == 0) {
        int status = summarise(S, (int)a.jobs, eng.repaired, a.strict);
        rc = batch_sink_commit(&sink);
        if (rc == 0) rc = status;
    } else if (rc == CLI_EXIT_IOERR && sink.path) {
        /* A file failed: one line saying so (main reports a failed stdout). */
        if (cli_flush_output(sink.f, sink.path, CMD) == 0)
            cli_fail(0, CMD, "cannot write %s", sink.path);
        batch_sink_abandon(&sink);
    } else {
        batch_sink_abandon(&sink);
    }
    batch_engine_free(&eng);
    hp_trace_close(r);
    close_trace(&t);
    free(S);
    free(sc);
    return rc;
}
