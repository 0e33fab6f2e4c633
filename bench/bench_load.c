/* headplan-bench, family "load": the load level against the kinematic levels on the
 * catalogue's load scenes (layout scenes with a `load` section that the load planner
 * accepts). For each: the median time per plan of the kinematic realtime planner (the
 * scene's level) and of the load planner on each backend (realtime, ipopt, nlopt-slsqp),
 * with the timing harness (cold plans: the planners are reset between batches' plans by
 * planning the same correction), and the sag error a kinematic plan makes: its pressures'
 * forward-statics rest (hp_load_rest from the desired pose) against the desired pose, in
 * mm (+inf when the kinematic pressures do not hold the head at all). Writes
 * DIR/load.csv. */
#define _DEFAULT_SOURCE
#include "bench/bench.h"
#include "bench/bench_report.h"
#include "bench/bench_timing.h"
#include "cli/exit_codes.h"
#include "headplan/headplan.h"
#include "headplan/hp_load_planner.h"

#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_LOAD_SCENES 16

typedef struct load_row {
    char scene[64];
    double kin_ns, sag_mm;
    double load_ns[3];
    char status[3][20];
} load_row;

typedef struct load_table {
    const load_row *rows;
    int n;
} load_table;

static const hp_backend BACKENDS[3] = {HP_BACKEND_REALTIME, HP_BACKEND_IPOPT,
                                       HP_BACKEND_NLOPT_SLSQP};

typedef struct ctx {
    hp_planner *kin;
    hp_load_planner *load;
    const double *desired;
} ctx;

static void kin_batch(void *c, long first, long count)
{
    ctx *x = c;
    (void)first;
    hp_result r;
    for (long i = 0; i < count; ++i) (void)hp_plan(x->kin, x->desired, &r);
}

static void load_batch(void *c, long first, long count)
{
    ctx *x = c;
    (void)first;
    hp_result r;
    for (long i = 0; i < count; ++i) (void)hp_load_plan(x->load, x->desired, &r, NULL);
}

/* 0 with the row filled, 1 when the scene is not a load scene, else an exit status. */
static int run_scene(const bench_options *o, const char *path, const char *stem,
                     load_row *row)
{
    hp_scene *sc = malloc(sizeof *sc);
    if (!sc) return CLI_EXIT_SOFTWARE;
    hp_diag d;
    int rc = 1;
    if (hp_scene_load(path, sc, &d) != HP_OK || !sc->has_load || !sc->has_correction) {
        free(sc);
        return 1;
    }
    memset(row, 0, sizeof *row);
    snprintf(row->scene, sizeof row->scene, "%s", stem);
    hp_settings s;
    (void)hp_scene_settings(sc, &s, NULL);
    s.use_rate_limits = 0;
    ctx c = {NULL, NULL, sc->correction};
    bench_timing t;
    row->kin_ns = row->sag_mm = NAN;
    if (hp_planner_create(&sc->layout, &s, &c.kin, &d) == HP_OK) {
        hp_result r;
        if (bench_time(o, kin_batch, &c, &t) == 0) row->kin_ns = t.median_ns;
        if (hp_plan(c.kin, sc->correction, &r) == HP_OK) {
            hp_load_model *M = malloc(sizeof *M);
            double P[HP_MAX_BLADDERS], rest[6];
            for (int k = 0; k < r.n; ++k) P[k] = r.bladders[k].pressure;
            row->sag_mm = INFINITY;
            if (M && hp_load_model_init(M, &sc->layout, &sc->load, sc->load_geometry, NULL) ==
                         HP_OK &&
                hp_load_rest(M, P, sc->correction, rest, NULL) == HP_OK) {
                double e = 0.0;
                for (int i = 0; i < 3; ++i) e += (rest[i] - sc->correction[i]) *
                                                 (rest[i] - sc->correction[i]);
                row->sag_mm = sqrt(e) * 1e3;
            }
            free(M);
        }
        hp_planner_destroy(c.kin);
    }
    for (int b = 0; b < 3; ++b) {
        s.backend = BACKENDS[b];
        s.level = sc->load_geometry;
        row->load_ns[b] = NAN;
        snprintf(row->status[b], sizeof row->status[b], "refused");
        if (hp_load_planner_create(&sc->layout, &sc->load, &s,
                                   (hp_load_tiebreak)sc->load_tiebreak, &c.load, &d) != HP_OK)
            continue;
        hp_result r;
        if (hp_load_plan(c.load, sc->correction, &r, NULL) == HP_OK)
            snprintf(row->status[b], sizeof row->status[b], "%s", hp_status_name(r.status));
        if (bench_time(o, load_batch, &c, &t) == 0) row->load_ns[b] = t.median_ns;
        hp_load_planner_destroy(c.load);
        c.load = NULL;
    }
    rc = 0;
    free(sc);
    return rc;
}

static int cmp_str(const void *a, const void *b)
{
    return strcmp(*(char *const *)a, *(char *const *)b);
}

static int csv_writer(const void *arg, FILE *f)
{
    const load_table *lt = arg;
    fprintf(f, "scene,kinematic_median_ns,kinematic_sag_mm,backend,load_status,load_median_ns\n");
    for (int i = 0; i < lt->n; ++i)
        for (int b = 0; b < 3; ++b)
            fprintf(f, "%s,%.1f,%.6g,%s,%s,%.1f\n", lt->rows[i].scene, lt->rows[i].kin_ns,
                    lt->rows[i].sag_mm, hp_backend_name(BACKENDS[b]), lt->rows[i].status[b],
                    lt->rows[i].load_ns[b]);
    return ferror(f) ? -1 : 0;
}

int bench_load(const bench_options *o, const char *dir)
{
    DIR *dp = opendir(o->scenarios);
    if (!dp) {
        fprintf(stderr, "headplan-bench: --scenarios: cannot open folder '%s'\n", o->scenarios);
        return CLI_EXIT_NOINPUT;
    }
    char *names[64];
    int nn = 0;
    struct dirent *de;
    while ((de = readdir(dp)) && nn < 64) {
        size_t len = strlen(de->d_name);
        if (len > 5 && strcmp(de->d_name + len - 5, ".yaml") == 0 &&
            (names[nn] = strdup(de->d_name)) != NULL)
            ++nn;
    }
    closedir(dp);
    qsort(names, (size_t)nn, sizeof *names, cmp_str);
    static load_row rows[MAX_LOAD_SCENES];
    int nr = 0, rc = 0;
    for (int i = 0; i < nn && rc == 0 && nr < MAX_LOAD_SCENES; ++i) {
        char path[4096], stem[64];
        snprintf(path, sizeof path, "%s/%s", o->scenarios, names[i]);
        snprintf(stem, sizeof stem, "%.*s", (int)(strlen(names[i]) - 5), names[i]);
        int r = run_scene(o, path, stem, &rows[nr]);
        if (r == 0) ++nr;
        else if (r != 1) rc = r;
    }
    for (int i = 0; i < nn; ++i) free(names[i]);
    if (rc) return rc;
    load_table lt = {rows, nr};
    if ((rc = bench_save(dir, "load.csv", csv_writer, &lt)) != 0) return rc;
    printf("%-14s %14s %12s  %-12s %-16s %14s\n", "scene", "kinematic_ns", "sag_mm",
           "backend", "load_status", "load_ns");
    for (int i = 0; i < nr; ++i)
        for (int b = 0; b < 3; ++b)
            printf("%-14s %14.0f %12.4g  %-12s %-16s %14.0f\n", rows[i].scene, rows[i].kin_ns,
                   rows[i].sag_mm, hp_backend_name(BACKENDS[b]), rows[i].status[b],
                   rows[i].load_ns[b]);
    fprintf(stderr, "bench load: wrote %s/load.csv\n", dir);
    return 0;
}
