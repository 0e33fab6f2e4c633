/* Benchmark of the horizon planners (docs/horizon.md), a standalone program built as
 * build/headplan-bench-horizon:
 *   headplan-bench-horizon rh SCENE TRACE      time per receding-horizon call against N
 *   headplan-bench-horizon windows SCENE TRACE WINDOW OVERLAP
 *                                             whole offline solve against overlapping windows
 * Prints CSV on stdout. Per-call times are the calling thread's CPU time
 * (CLOCK_THREAD_CPUTIME_ID: a loaded machine inflates wall time, not this), the offline
 * solves' wall time (CLOCK_MONOTONIC). */
#define _POSIX_C_SOURCE 200809L
#include "headplan/headplan.h"
#include "standalone.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static double cpu_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int load(const char *scene, const char *trace, hp_scene *sc, hp_settings *s,
                hp_trace_row **rows, size_t *T)
{
    hp_diag d = {{0}};
    if (hp_scene_load(scene, sc, &d) != HP_OK || hp_scene_settings(sc, s, &d) != HP_OK) {
        fprintf(stderr, "%s\n", d.text);
        return 1;
    }
    hp_trace_rows dev = HP_TRACE_DEVIATION;
    hp_trace_reader *r = NULL;
    if (hp_trace_open(trace, &dev, &r, &d) != HP_OK) {
        fprintf(stderr, "%s\n", d.text);
        return 1;
    }
    size_t cap = 1024;
    *rows = malloc(cap * sizeof **rows);
    *T = 0;
    for (;;) {
        if (*T == cap) *rows = realloc(*rows, (cap *= 2) * sizeof **rows);
        if (!*rows) return 1;
        hp_error e = hp_trace_next(r, &(*rows)[*T], &d);
        if (e == HP_ERR_STATE) break;
        if (e != HP_OK) {
            fprintf(stderr, "%s\n", d.text);
            return 1;
        }
        ++*T;
    }
    hp_trace_close(r);
    return 0;
}

static int bench_rh(const hp_scene *sc, const hp_settings *s, const hp_trace_row *rows, size_t T)
{
    static const int Ns[] = {1, 2, 5, 10, 20, 40, 64};
    double *times = malloc(T * sizeof *times);
    printf("N,prediction,calls,median_us,p99_us,max_us\n");
    for (int p = 0; p < 2; ++p)
        for (size_t a = 0; a < sizeof Ns / sizeof Ns[0]; ++a) {
            hp_horizon_settings hs;
            hp_horizon_settings_default(&hs);
            hs.horizon = Ns[a];
            hs.prediction = p ? HP_PREDICT_VELOCITY : HP_PREDICT_HOLD;
            hp_horizon_rh *rh = NULL;
            hp_diag d = {{0}};
            if (hp_horizon_rh_create(&sc->layout, s, &hs, NULL, &rh, &d) != HP_OK) {
                fprintf(stderr, "%s\n", d.text);
                return 1;
            }
            for (size_t t = 0; t < T; ++t) {
                hp_result r;
                double t0 = cpu_s();
                hp_horizon_rh_step(rh, rows[t].t, rows[t].correction, &r);
                times[t] = cpu_s() - t0;
            }
            hp_horizon_rh_destroy(rh);
            qsort(times, T, sizeof *times, sa_by_value);
            printf("%d,%s,%zu,%.1f,%.1f,%.1f\n", Ns[a], hp_prediction_name(hs.prediction), T,
                   1e6 * times[T / 2], 1e6 * times[(T * 99) / 100], 1e6 * times[T - 1]);
            fflush(stdout);
        }
    free(times);
    return 0;
}

static int bench_windows(const hp_scene *sc, const hp_settings *s, const hp_trace_row *rows,
                         size_t T, int window, int overlap)
{
    hp_horizon_settings hs;
    hp_horizon_settings_default(&hs);
    hs.start_interval_s = hp_horizon_start_interval(rows, T, hs.start_interval_s);
    hp_horizon_row *whole = malloc(T * sizeof *whole), *win = malloc(T * sizeof *win);
    hp_horizon_info iw, iv;
    hp_diag d = {{0}};
    hs.window = (int)T; /* the whole trace at once, however long */
    double t0 = sa_now();
    if (hp_horizon_offline(&sc->layout, s, &hs, rows, T, NULL, whole, &iw, &d) != HP_OK) {
        fprintf(stderr, "whole: %s\n", d.text);
        return 1;
    }
    double tw = sa_now() - t0;
    hs.window = window;
    hs.overlap = overlap;
    t0 = sa_now();
    if (hp_horizon_offline(&sc->layout, s, &hs, rows, T, NULL, win, &iv, &d) != HP_OK) {
        fprintf(stderr, "windows: %s\n", d.text);
        return 1;
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
    free(whole);
    free(win);
    return 0;
}

int main(int argc, char **argv)
{
    if (argc < 4 || (strcmp(argv[1], "rh") != 0 && strcmp(argv[1], "windows") != 0) ||
        (strcmp(argv[1], "windows") == 0 && argc != 6)) {
        fprintf(stderr, "usage: headplan-bench-horizon rh SCENE TRACE\n"
                        "       headplan-bench-horizon windows SCENE TRACE WINDOW OVERLAP\n");
        return 64;
    }
    hp_scene *sc = calloc(1, sizeof *sc);
    hp_settings s;
    hp_trace_row *rows = NULL;
    size_t T = 0;
    if (!sc || load(argv[2], argv[3], sc, &s, &rows, &T) || T < 2) return 65;
    int rc = strcmp(argv[1], "rh") == 0
                 ? bench_rh(sc, &s, rows, T)
                 : bench_windows(sc, &s, rows, T, atoi(argv[4]), atoi(argv[5]));
    free(rows);
    free(sc);
    return rc;
}
