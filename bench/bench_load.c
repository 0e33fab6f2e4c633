/* headplan-bench, family "load": the load level against the kinematic levels on the
 * catalogue's load scenes (layout scenes with a `load` section that the load planner
 * accepts). For each: the median time per plan of the kinematic realtime planner (the
 * scene's level) and of the load planner on each backend (realtime, ipopt, nlopt-slsqp),
 * with the timing harness (cold plans: the planners are reset between batches' plans by
 * planning the same correction), and the sag error a kinematic plan makes: its pressures'
 * forward-statics rest (hp_load_rest from the desired pose) against the desired pose, in
 * mm (+inf when the kinematic pressures do not hold the head at all). Writes
 * DIR/load.csv and the chart DIR/load.gp -> load.png, load.svg (time per plan per level and
 * backend; the kinematic plan's sag). */
#define _DEFAULT_SOURCE
#include "bench/bench.h"
#include "bench/bench_report.h"
#include "bench/bench_timing.h"
#include "bench/bench_util.h"
#include "cli/cli_gptext.h"
#include "cli/exit_codes.h"
#include "headplan/headplan.h"

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

static const hp_backend BACKENDS[3] = {HP_BACKEND_REALTIME, HP_BACKEND_IPOPT,
                                       HP_BACKEND_NLOPT_SLSQP};

typedef struct ctx {
    hp_planner *kin;
    hp_planner *load; /* at the load level */
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
    for (long i = 0; i < count; ++i) (void)hp_plan(x->load, x->desired, &r);
}

/* 0 with the row filled, 1 when the scene is not a load scene, else an exit status. */
static int run_scene(const bench_options *o, const char *path, const char *stem, void *vrow)
{
    load_row *row = vrow;
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
    /* The kinematic plan: the scene's contact level (auto among the contact levels), the
     * head's weight left out. */
    hp_settings kin = s;
    kin.level = sc->level;
    memset(&kin.load, 0, sizeof kin.load);
    if (hp_planner_create(&sc->layout, &kin, &c.kin, &d) == HP_OK) {
        hp_result r;
        if (bench_time(o, kin_batch, &c, &t) == 0) row->kin_ns = t.median_ns;
        if (hp_plan(c.kin, sc->correction, &r) == HP_OK) {
            hp_load_model *M = NULL;
            double P[HP_MAX_BLADDERS], rest[6];
            for (int k = 0; k < r.n; ++k) P[k] = r.bladders[k].pressure;
            row->sag_mm = INFINITY;
            if (hp_load_model_create(&sc->layout, &sc->load, sc->load_geometry, &M, NULL) ==
                    HP_OK &&
                hp_load_rest(M, P, sc->correction, rest, NULL) == HP_OK) {
                double e = 0.0;
                for (int i = 0; i < 3; ++i)
                    e += (rest[i] - sc->correction[i]) * (rest[i] - sc->correction[i]);
                row->sag_mm = sqrt(e) * 1e3;
            }
            hp_load_model_destroy(M);
        }
        hp_planner_destroy(c.kin);
    }
    for (int b = 0; b < 3; ++b) {
        s.backend = BACKENDS[b];
        s.level = HP_LEVEL_LOAD;
        row->load_ns[b] = NAN;
        snprintf(row->status[b], sizeof row->status[b], "refused");
        if (hp_planner_create(&sc->layout, &s, &c.load, &d) != HP_OK) continue;
        hp_result r;
        if (hp_plan(c.load, sc->correction, &r) == HP_OK)
            snprintf(row->status[b], sizeof row->status[b], "%s", hp_status_name(r.status));
        if (bench_time(o, load_batch, &c, &t) == 0) row->load_ns[b] = t.median_ns;
        hp_planner_destroy(c.load);
        c.load = NULL;
    }
    rc = 0;
    free(sc);
    return rc;
}

static void csv_row(const void *arg, int i, FILE *f)
{
    const load_row *r = (const load_row *)arg + i;
    for (int b = 0; b < 3; ++b)
        fprintf(f, "%s,%.1f,%.6g,%s,%s,%.1f\n", r->scene, r->kin_ns, r->sag_mm,
                hp_backend_name(BACKENDS[b]), r->status[b], r->load_ns[b]);
}

/* Sags drawn at this height [mm] when unbounded (the kinematic pressures do not hold the
 * head at all) or missing, labelled so. */
#define SAG_CEILING_MM 1e3

typedef struct chart_arg {
    const load_row *rows;
    int n;
} chart_arg;

/* Two panels, data inline (the script redraws alone): the median time per plan of each
 * scene at the kinematic level (realtime) and at the load level on each backend (log
 * scale), and the sag a kinematic plan leaves through the forward statics (log scale;
 * unbounded drawn at the ceiling). */
static int chart_writer(const void *arg, FILE *f)
{
    const chart_arg *a = arg;
    fprintf(f,
            "# Generated by headplan-bench (load family); data inline, from load.csv.\n"
            "# Redraw: gnuplot load.gp\nceiling = %g\n"
            "# index, kinematic us, load us (realtime, ipopt, nlopt-slsqp), sag mm, "
            "unbounded\n$d << EOD\n",
            SAG_CEILING_MM);
    for (int i = 0; i < a->n; ++i) {
        const load_row *r = &a->rows[i];
        double sag = isfinite(r->sag_mm) ? fmax(r->sag_mm, 1e-9) : SAG_CEILING_MM;
        fprintf(f, "%d %.6g %.6g %.6g %.6g %.6g %d\n", i, r->kin_ns * 1e-3, r->load_ns[0] * 1e-3,
                r->load_ns[1] * 1e-3, r->load_ns[2] * 1e-3, sag, !isfinite(r->sag_mm));
    }
    /* The scenes are named by their files: the names reach the script as quoted text
     * (cli_gptext.h), never inside the data block or a comment. */
    fprintf(f, "EOD\nset xtics (");
    for (int i = 0; i < a->n; ++i) {
        fprintf(f, "%s", i ? ", " : "");
        gp_label(f, a->rows[i].scene);
        fprintf(f, " %d", i);
    }
    fprintf(f,
            ")\n\n"
            "if (strstrt(GPVAL_TERMINALS, \"pngcairo\") > 0) {\n"
            "  set terminal pngcairo size 1400,560 enhanced font \"Sans,10\"\n"
            "} else {\n  set terminal png size 1400,560\n}\n"
            "set output \"load.png\"\n"
            "do for [term = 1:2] {\n"
            "if (term == 2) { set terminal svg size 1400,560 dynamic enhanced font "
            "\"Sans,10\"; set output \"load.svg\" }\n"
            "set multiplot layout 1,2 title \"The load level: time per plan and the sag "
            "a kinematic plan leaves (catalogue load scenes)\" font \",12\"\n"
            "set grid\nset xrange [-0.5:%d.5]\nset xtics noenhanced\n"
            "set logscale y\nset format y \"10^{%%L}\"\n"
            "set title \"median time per plan (cold)\"\nset ylabel \"time per plan "
            "[us]\"\nset key below horizontal box noenhanced\n"
            "plot $d using 1:2 with points pt 7 ps 1.6 lc rgb \"#1b9e77\" "
            "title \"kinematic level, realtime\", \\\n"
            "  $d using 1:3 with points pt 5 ps 1.6 lc rgb \"#d95f02\" "
            "title \"load level, realtime\", \\\n"
            "  $d using 1:4 with points pt 9 ps 1.6 lc rgb \"#7570b3\" "
            "title \"load level, ipopt\", \\\n"
            "  $d using 1:5 with points pt 13 ps 1.6 lc rgb \"#e7298a\" "
            "title \"load level, nlopt-slsqp\"\n"
            "set title \"sag of the kinematic plan: its pressures' forward-statics rest vs "
            "the desired pose\\n(unbounded: nothing holds the head, it falls)\"\n"
            "set ylabel \"sag [mm]\"\n"
            "set yrange [1e-3:ceiling*10]\nunset key\n"
            "set boxwidth 0.5\nset style fill solid 0.6\n"
            "plot $d using 1:6 with boxes lc rgb \"#d95f02\" notitle, \\\n"
            "  $d using 1:($7 > 0 ? $6 * 1.6 : NaN):(\"unbounded\") with labels notitle, \\\n"
            "  ceiling with lines dt 2 lc rgb \"#909090\" notitle\n"
            "unset multiplot\n}\nunset output\n",
            a->n > 0 ? a->n - 1 : 0);
    return ferror(f) ? -1 : 0;
}

int bench_load(const bench_options *o, const char *dir)
{
    static load_row rows[MAX_LOAD_SCENES];
    int nr = 0;
    int rc = bench_each_scene(o, run_scene, rows, sizeof *rows, MAX_LOAD_SCENES, &nr);
    if (rc) return rc;
    if ((rc = bench_save_csv(dir, "load.csv",
                             "scene,kinematic_median_ns,kinematic_sag_mm,backend,load_status,"
                             "load_median_ns",
                             csv_row, rows, nr)) != 0)
        return rc;
    chart_arg ca = {rows, nr};
    static const char *const outs[] = {"load.png", "load.svg", NULL};
    if ((rc = bench_save(dir, "load.gp", chart_writer, &ca)) != 0 ||
        (rc = bench_gnuplot_run(dir, "load.gp", outs)) != 0)
        return rc;
    printf("%-14s %14s %12s  %-12s %-16s %14s\n", "scene", "kinematic_ns", "sag_mm", "backend",
           "load_status", "load_ns");
    for (int i = 0; i < nr; ++i)
        for (int b = 0; b < 3; ++b)
            printf("%-14s %14.0f %12.4g  %-12s %-16s %14.0f\n", rows[i].scene, rows[i].kin_ns,
                   rows[i].sag_mm, hp_backend_name(BACKENDS[b]), rows[i].status[b],
                   rows[i].load_ns[b]);
    fprintf(stderr, "bench load: wrote %s/load.csv, load.png, load.svg\n", dir);
    return 0;
}
