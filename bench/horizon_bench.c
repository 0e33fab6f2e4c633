/* Benchmark of the horizon planners (docs/horizon.md), a standalone program built as
 * build/headplan-bench-horizon:
 *   headplan-bench-horizon rh SCENE TRACE [N] [--max-time-us US] [--repeat R]
 *                                             time per receding-horizon call against N
 *                                             (the table's N, or only the N given), its
 *                                             interior-point iterations (counted: the same
 *                                             on any machine without a time budget), the
 *                                             calls the budget stopped and the plan's cost;
 *                                             --max-time-us replaces the scene's
 *                                             solver.max_time_s (a control loop's deadline),
 *                                             --repeat takes each call's median of R runs
 *   headplan-bench-horizon windows SCENE TRACE WINDOW OVERLAP
 *                                             whole offline solve against overlapping windows
 * Prints CSV on stdout. Per-call times are the calling thread's CPU time
 * (CLOCK_THREAD_CPUTIME_ID: a loaded machine inflates wall time, not this), the offline
 * solves' wall time (CLOCK_MONOTONIC). */
#define _POSIX_C_SOURCE 200809L
#include "headplan/headplan.h"
#include "horizon/horizon_internal.h"
#include "standalone.h"

#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

/* The most runs of a trace --repeat takes (each call's times sorted on the stack). */
#define RH_MAX_REPEAT 99

static double cpu_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Exit statuses (sysexits, as headplan's): a bad command line, bad data, an input that cannot
 * be opened, an internal failure. Every refusal prints one line on stderr first. */
enum { EX_USAGE_ = 64, EX_DATA_ = 65, EX_NOINPUT_ = 66, EX_SOFTWARE_ = 70 };

/* The exit status of a failed load: a file that cannot be read is 66, anything else 65. */
static int load_status(hp_error e)
{
    return e == HP_ERR_IO ? EX_NOINPUT_ : e == HP_ERR_NOMEM ? EX_SOFTWARE_ : EX_DATA_;
}

/* A refused or failed horizon call: one line, and 65 for values the library refuses (a window
 * the trace cannot hold), 70 for anything else. */
static int call_failed(const char *what, hp_error e, const hp_diag *d)
{
    fprintf(stderr, "headplan-bench-horizon: %s: %s\n", what, d->text);
    return e == HP_ERR_INVALID ? EX_DATA_ : EX_SOFTWARE_;
}

/* Out of memory for what: one line, 70. */
static int no_memory(const char *what)
{
    fprintf(stderr, "headplan-bench-horizon: out of memory for %s\n", what);
    return EX_SOFTWARE_;
}

/* Loads the scene and every row of the trace (rows stated by the caller: deviations).
 * Returns 0, or an exit status after printing why on one line. */
static int load(const char *scene, const char *trace, hp_scene *sc, hp_settings *s,
                hp_trace_row **rows, size_t *T)
{
    hp_diag d = {{0}};
    hp_error e = hp_scene_load(scene, sc, &d);
    if (e == HP_OK) e = hp_scene_settings(sc, s, &d);
    if (e != HP_OK) {
        fprintf(stderr, "headplan-bench-horizon: %s\n", d.text);
        return load_status(e);
    }
    hp_trace_rows dev = HP_TRACE_DEVIATION;
    hp_trace_reader *r = NULL;
    if ((e = hp_trace_open(trace, &dev, &r, &d)) != HP_OK) {
        fprintf(stderr, "headplan-bench-horizon: %s\n", d.text);
        return load_status(e);
    }
    size_t cap = 1024;
    *rows = malloc(cap * sizeof **rows);
    *T = 0;
    int rc = 0;
    for (;;) {
        if (*rows && *T == cap) {
            hp_trace_row *more = realloc(*rows, (cap *= 2) * sizeof **rows);
            if (!more) free(*rows);
            *rows = more;
        }
        if (!*rows) {
            fprintf(stderr, "headplan-bench-horizon: %s: out of memory at row %zu\n", trace,
                    *T + 1);
            rc = EX_SOFTWARE_;
            break;
        }
        e = hp_trace_next(r, &(*rows)[*T], &d);
        if (e == HP_END) break; /* the end of the trace, not a failure */
        if (e != HP_OK) {
            fprintf(stderr, "headplan-bench-horizon: %s\n", d.text);
            rc = load_status(e);
            break;
        }
        ++*T;
    }
    hp_trace_close(r);
    if (rc == 0 && *T < 2) {
        /* One row has no interval for a rate limit and no horizon to plan over. */
        fprintf(stderr, "headplan-bench-horizon: %s: %zu row%s; the benchmark needs at least 2\n",
                trace, *T, *T == 1 ? "" : "s");
        rc = EX_DATA_;
    }
    return rc;
}

/* Every N (or only), every prediction: one line of times, iterations, the calls the time
 * budget stopped (status time-limit) and the plan's cost, measured as headplan horizon
 * measures its receding plan (the same start pressures, start interval and tolerances), so
 * that a budget's effect on tracking shows beside its effect on time. With repeat R > 1 the
 * trace is planned R times (new planners each time) and each call's time is its median over
 * the R runs: a call is the same work in every run while no budget stops it, and a stall of
 * the host lands in one run's time of it, not in the median. The other columns are the first
 * run's. */
static int bench_rh(const hp_scene *sc, const hp_settings *s, const hp_trace_row *rows, size_t T,
                    int only, int repeat)
{
    static const int table[] = {1, 2, 5, 10, 20, 40, 64};
    const int *Ns = only ? &only : table;
    const size_t nN = only ? 1 : sizeof table / sizeof table[0], R = (size_t)repeat;
    double p0[HP_MAX_BLADDERS];
    hp_diag d0 = {{0}};
    hp_error e0 = hp_horizon_nominal_pressures(&sc->layout, p0, &d0);
    if (e0 != HP_OK) return call_failed("start pressures", e0, &d0);
    double *runs = malloc(R * T * sizeof *runs), *times = malloc(T * sizeof *times);
    hp_horizon_row *plan = malloc(T * sizeof *plan);
    if (!runs || !times || !plan) {
        free(runs);
        free(times);
        free(plan);
        return no_memory("the times");
    }
    printf("N,prediction,calls,median_us,p99_us,max_us,mean_iterations,max_iterations,"
           "calls_6_or_more,time_limited,cost\n");
    static const hp_prediction preds[] = {HP_PREDICT_HOLD, HP_PREDICT_VELOCITY,
                                          HP_PREDICT_PERIODIC};
    int rc = 0;
    for (size_t p = 0; p < sizeof preds / sizeof preds[0] && !rc; ++p)
        for (size_t a = 0; a < nN && !rc; ++a) {
            hp_horizon_settings hs;
            hp_horizon_settings_default(&hs);
            hs.horizon = Ns[a];
            hs.prediction = preds[p];
            hs.start_interval_s = hp_horizon_start_interval(rows, T, hs.start_interval_s);
            long first = 0, most = 0, slow = 0; /* the first run's iterations */
            size_t stopped = 0;
            hp_error e = HP_OK;
            hp_diag d = {{0}};
            for (size_t k = 0; k < R && e == HP_OK; ++k) {
                hp_horizon_rh *rh = NULL;
                if ((e = hp_horizon_rh_create(&sc->layout, s, &hs, p0, &rh, &d)) != HP_OK) break;
                long before = 0;
                for (size_t t = 0; t < T && e == HP_OK; ++t) {
                    hp_result r;
                    double t0 = cpu_s();
                    e = hp_horizon_rh_step(rh, rows[t].t, rows[t].correction, &r);
                    runs[k * T + t] = cpu_s() - t0;
                    if (e != HP_OK) { /* the rows were checked: not expected */
                        hp_diag_set(&d, e, "line %ld: %s", rows[t].line, hp_error_message(e));
                        break;
                    }
                    if (k) continue;
                    long now = hpi_horizon_rh_iterations(rh), it = now - before;
                    before = now;
                    most = it > most ? it : most;
                    slow += it >= 6;
                    stopped += r.status == HP_STATUS_TIME_LIMIT;
                    hpi_horizon_row_from_result(rows + t, &r, sc->layout.n, plan + t);
                }
                if (!k) first = before;
                hp_horizon_rh_destroy(rh);
            }
            hp_horizon_metrics m;
            if (e == HP_OK &&
                (e = hp_horizon_measure(plan, T, sc->layout.n, p0, s, &hs, 0.5, 0.5, &m)) != HP_OK)
                hp_diag_set(&d, e, "metrics: %s", hp_error_message(e));
            if (e != HP_OK) {
                rc = call_failed("receding horizon", e, &d);
                break;
            }
            double col[RH_MAX_REPEAT];
            for (size_t t = 0; t < T; ++t) {
                for (size_t k = 0; k < R; ++k) col[k] = runs[k * T + t];
                times[t] = sa_median(col, R);
            }
            qsort(times, T, sizeof *times, sa_by_value);
            printf("%d,%s,%zu,%.1f,%.1f,%.1f,%.3f,%ld,%ld,%zu,%.17g\n", Ns[a],
                   hp_prediction_name(hs.prediction), T, 1e6 * times[T / 2],
                   1e6 * times[(T * 99) / 100], 1e6 * times[T - 1], (double)first / (double)T, most,
                   slow, stopped, m.cost);
            fflush(stdout);
        }
    free(runs);
    free(times);
    free(plan);
    return rc;
}

static int bench_windows(const hp_scene *sc, const hp_settings *s, const hp_trace_row *rows,
                         size_t T, int window, int overlap)
{
    hp_horizon_settings hs;
    hp_horizon_settings_default(&hs);
    hs.start_interval_s = hp_horizon_start_interval(rows, T, hs.start_interval_s);
    hp_horizon_row *whole = malloc(T * sizeof *whole), *win = malloc(T * sizeof *win);
    int rc = 0;
    if (!whole || !win) {
        rc = no_memory("the plans");
        goto done;
    }
    hp_horizon_info iw, iv;
    hp_diag d = {{0}};
    hs.window = (int)T; /* the whole trace at once, however long */
    double t0 = sa_now();
    hp_error e = hp_horizon_offline(&sc->layout, s, &hs, rows, T, NULL, whole, &iw, &d);
    if (e != HP_OK) {
        rc = call_failed("whole trace", e, &d);
        goto done;
    }
    double tw = sa_now() - t0;
    hs.window = window;
    hs.overlap = overlap;
    t0 = sa_now();
    if ((e = hp_horizon_offline(&sc->layout, s, &hs, rows, T, NULL, win, &iv, &d)) != HP_OK) {
        rc = call_failed("windows", e, &d);
        goto done;
    }
    double tv = sa_now() - t0;
    double worst = 0;
    for (size_t t = 0; t < T; ++t)
        for (int i = 0; i < 6; ++i)
            worst = fmax(worst, fabs(win[t].achieved[i] - whole[t].achieved[i]) *
                                    (i < 3 ? 1e3 : 57.295779513082320877));
    printf("rows,solve,window,overlap,windows,iterations,seconds,cost,largest_pose_difference\n");
    printf("%zu,whole,%zu,0,%d,%d,%.2f,%.10g,0\n", T, T, iw.windows, iw.iterations, tw, iw.cost);
    printf("%zu,windows,%d,%d,%d,%d,%.2f,%.10g,%.3g\n", T, window, overlap, iv.windows,
           iv.iterations, tv, iv.cost, worst);
done:
    free(whole);
    free(win);
    return rc;
}

/* A whole number >= min from a command-line argument, or -1 after printing why. */
static int count_arg(const char *name, const char *arg, int min)
{
    char *end = NULL;
    long v = strtol(arg, &end, 10);
    if (end == arg || *end != '\0' || isspace((unsigned char)arg[0]) || v < min ||
        v > 1000000000L) {
        fprintf(stderr, "headplan-bench-horizon: %s '%s': want a whole number >= %d\n", name, arg,
                min);
        return -1;
    }
    return (int)v;
}

/* Refuses, before anything is printed, a trace the horizon planners refuse: a desired pose
 * hp_plan would refuse, or time stamps that are not finite and increasing. 0, or the exit
 * status after one line on stderr. */
static int check_trace(const char *trace, const hp_scene *sc, const hp_trace_row *rows, size_t T)
{
    hp_diag d = {{0}};
    hp_horizon_settings hs;
    hp_horizon_settings_default(&hs);
    hp_error e = hpi_horizon_check_rows_at(&sc->layout, rows, T, &d);
    for (size_t t = 0; t < T && e == HP_OK; ++t) {
        double dt = NAN; /* written on HP_OK; read by nothing here */
        e = hpi_horizon_row_dt(&hs, rows, t, &dt, &d);
    }
    if (e == HP_OK) return 0;
    fprintf(stderr, "headplan-bench-horizon: %s: %s\n", trace, d.text);
    return EX_DATA_;
}

/* A number > 0 and finite from a command-line argument, or -1 after printing why. */
static double positive_arg(const char *name, const char *arg)
{
    char *end = NULL;
    double v = strtod(arg, &end);
    if (end == arg || *end != '\0' || isspace((unsigned char)arg[0]) || !(v > 0) || !isfinite(v)) {
        fprintf(stderr, "headplan-bench-horizon: %s '%s': want a finite number > 0\n", name, arg);
        return -1;
    }
    return v;
}

int main(int argc, char **argv)
{
    static const char usage[] =
        "usage: headplan-bench-horizon rh SCENE TRACE [N] [--max-time-us US] "
        "[--repeat R] | headplan-bench-horizon windows SCENE TRACE WINDOW "
        "OVERLAP\n";
    if (argc < 2) {
        fputs(usage, stderr);
        return EX_USAGE_;
    }
    int rh = strcmp(argv[1], "rh") == 0;
    if (!rh && strcmp(argv[1], "windows") != 0) {
        fprintf(stderr, "headplan-bench-horizon: unknown mode '%s' (rh or windows); %s", argv[1],
                usage);
        return EX_USAGE_;
    }
    /* rh: the positional arguments end at the first option (N is never negative) */
    int npos = argc;
    for (int i = 2; i < argc && rh; ++i)
        if (argv[i][0] == '-') {
            npos = i;
            break;
        }
    if (rh ? npos < 4 || npos > 5 : argc != 6) {
        fputs(usage, stderr);
        return EX_USAGE_;
    }
    int window = 0, overlap = 0, only = 0, repeat = 1;
    double max_time_us = 0; /* 0: the scene's solver.max_time_s */
    int seen[2] = {0, 0};   /* --repeat, --max-time-us */
    const char *time_text = "";
    if (rh && npos == 5 && (only = count_arg("N", argv[4], 1)) < 0) return EX_USAGE_;
    for (int i = npos; i < argc; i += 2) {
        const int is_time = strcmp(argv[i], "--max-time-us") == 0;
        if (!is_time && strcmp(argv[i], "--repeat") != 0) {
            fprintf(stderr, "headplan-bench-horizon: unknown option '%s'; %s", argv[i], usage);
            return EX_USAGE_;
        }
        if (i + 1 == argc) {
            fprintf(stderr, "headplan-bench-horizon: %s: missing value\n", argv[i]);
            return EX_USAGE_;
        }
        if (seen[is_time]++) {
            fprintf(stderr, "headplan-bench-horizon: %s: given more than once\n", argv[i]);
            return EX_USAGE_;
        }
        if (is_time) time_text = argv[i + 1];
        if (is_time ? (max_time_us = positive_arg(argv[i], argv[i + 1])) < 0
                    : (repeat = count_arg(argv[i], argv[i + 1], 1)) < 0)
            return EX_USAGE_;
        if (repeat > RH_MAX_REPEAT) {
            fprintf(stderr, "headplan-bench-horizon: --repeat '%s': at most %d\n", argv[i + 1],
                    RH_MAX_REPEAT);
            return EX_USAGE_;
        }
    }
    if (!rh && ((window = count_arg("WINDOW", argv[4], 1)) < 0 ||
                (overlap = count_arg("OVERLAP", argv[5], 0)) < 0))
        return EX_USAGE_;
    hp_scene *sc = calloc(1, sizeof *sc);
    if (!sc) {
        fprintf(stderr, "headplan-bench-horizon: out of memory for the scene\n");
        return EX_SOFTWARE_;
    }
    hp_settings s;
    hp_trace_row *rows = NULL;
    size_t T = 0;
    int rc = load(argv[2], argv[3], sc, &s, &rows, &T);
    if (rc == 0) rc = check_trace(argv[3], sc, rows, T);
    if (rc == 0 && max_time_us > 0) {
        hp_diag d = {{0}};
        s.max_time = 1e-6 * max_time_us;
        if (hp_settings_validate(&s, &d) != HP_OK) {
            fprintf(stderr, "headplan-bench-horizon: --max-time-us '%s': %s\n", time_text, d.text);
            rc = EX_USAGE_;
        }
    }
    if (rc == 0)
        rc = rh ? bench_rh(sc, &s, rows, T, only, repeat)
                : bench_windows(sc, &s, rows, T, window, overlap);
    free(rows);
    free(sc);
    return rc;
}
