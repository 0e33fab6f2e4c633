/* headplan-bench, family "levels": model no more than a scene needs.
 *
 * For every layout scene of the catalogue (the .yaml files of o->scenarios, by name; bladder scenes are
 * skipped): its targets are its correction and up to N_TRACE rows of its trace (evenly
 * strided); their size is the largest translation norm (mm) and rotation-vector norm (deg).
 * `auto` = hp_contact_auto(layout, the scene's model tolerance, that size). For each level
 * (linear, plane, surface): hp_contact_error_bound at that size, the median time per plan
 * (the scene's backend and solver settings, cold plans, timing harness) and the pose error:
 * each answer's pressures through bladder FK, the volume law and the SURFACE contact FK,
 * against the same round trip of the surface-level answer (mm or deg, commanded axes). */
#define _DEFAULT_SOURCE
#include "cli/cli_args.h"
#include "bench/bench.h"
#include "bench/bench_report.h"
#include "bench/bench_timing.h"
#include "bench/bench_util.h"
#include "cli/exit_codes.h"
#include "headplan/hp_trace.h"

#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define N_TRACE_FULL 200
#define N_TRACE_QUICK 10
#define MAX_T (N_TRACE_FULL + 1)
#define MAX_SCENES 32
#define MAX_TRACE_READ 200000

typedef struct {
    char scene[64];
    char backend[16];
    int targets;
    double trans_mm, rot_deg, tol_mm;
    hp_level auto_level;
    struct {
        double bound_mm, median_ns, p99_ns, max_error;
        long failures;
    } lv[3];
} level_row;

typedef struct {
    hp_planner *p;
    const double (*targets)[6];
    long n;
    double sink;
} plan_ctx;

static void batch(void *vctx, long first, long count)
{
    plan_ctx *c = vctx;
    long pos = first % c->n;
    hp_result r;
    for (long j = 0; j < count; ++j) {
        hp_planner_reset(c->p);
        if (hp_plan(c->p, c->targets[pos], &r) == HP_OK) c->sink += r.bladders[0].pressure;
        if (++pos == c->n) pos = 0;
    }
}

/* The scene's targets (SI). Returns the count, or -1 after a message on stderr. */
static int scene_targets(const hp_scene *sc, int quick, double (*t)[6])
{
    int n = 0;
    if (sc->has_correction) memcpy(t[n++], sc->correction, sizeof t[0]);
    if (!sc->has_trace) return n;
    hp_trace_reader *r;
    hp_diag d;
    hp_trace_rows rows = sc->trace_rows;
    if (hp_trace_open(sc->trace_path, &rows, &r, &d) != HP_OK) {
        cli_fail(0, "bench", "levels: %s", d.text);
        return -1;
    }
    double(*all)[6] = malloc(MAX_TRACE_READ * sizeof *all);
    long m = 0;
    hp_trace_row row;
    hp_error e;
    while (all && m < MAX_TRACE_READ && (e = hp_trace_next(r, &row, &d)) != HP_END) {
        if (e != HP_OK) {
            cli_fail(0, "bench", "levels: %s", d.text);
            free(all);
            hp_trace_close(r);
            return -1;
        }
        memcpy(all[m++], row.correction, sizeof all[0]);
    }
    hp_trace_close(r);
    if (!all) return -1;
    long want = quick ? N_TRACE_QUICK : N_TRACE_FULL;
    long stride = m > want ? m / want : 1;
    for (long k = 0; k < m && n < want + 1; k += stride) memcpy(t[n++], all[k], sizeof t[0]);
    free(all);
    return n;
}

static const hp_level levels[3] = {HP_LEVEL_LINEAR, HP_LEVEL_PLANE, HP_LEVEL_SURFACE};

/* One scene: fills row. Returns 0, 1 when the scene is skipped, or an exit status. */
static int run_scene(const bench_options *o, const char *path, const char *stem, void *vrow)
{
    level_row *row = vrow;
    static hp_scene sc;
    hp_diag d;
    if (hp_scene_file_kind(path) != HP_SCENE_LAYOUT) return 1; /* a single-bladder study */
    if (hp_scene_load(path, &sc, &d) != HP_OK) {
        cli_fail(0, "bench", "levels: %s", d.text);
        return CLI_EXIT_DATAERR;
    }
    static double t[MAX_T][6], ref[MAX_T][6];
    int n = scene_targets(&sc, o->quick, t);
    if (n < 0) return CLI_EXIT_DATAERR;
    if (n == 0) return 1;
    const hp_layout *L = &sc.layout;
    memset(row, 0, sizeof *row);
    snprintf(row->scene, sizeof row->scene, "%s", stem);
    snprintf(row->backend, sizeof row->backend, "%s", hp_backend_name(sc.backend));
    row->targets = n;
    double tr = 0, rot = 0;
    for (int k = 0; k < n; ++k) {
        tr = fmax(tr, sqrt(t[k][0] * t[k][0] + t[k][1] * t[k][1] + t[k][2] * t[k][2]));
        rot = fmax(rot, sqrt(t[k][3] * t[k][3] + t[k][4] * t[k][4] + t[k][5] * t[k][5]));
    }
    row->trans_mm = tr * 1e3;
    row->rot_deg = rot * 180 / BENCH_PI;
    row->tol_mm = sc.level_tolerance * 1e3;
    if (hp_contact_auto(L, sc.level_tolerance, tr, rot, &row->auto_level) != HP_OK) {
        cli_fail(0, "bench", "levels: %s: auto could not choose a level", path);
        return CLI_EXIT_SOFTWARE;
    }
    hp_settings base;
    if (hp_scene_settings(&sc, &base, &d) != HP_OK) return CLI_EXIT_DATAERR;
    for (int li = 2; li >= 0; --li) { /* surface first: the reference */
        hp_settings s = base;
        s.level = levels[li];
        s.warm_start = 0;
        hp_planner *p;
        int rc = bench_planner_new(L, &s, &p);
        if (rc) return rc;
        double worst = 0;
        long fails = 0;
        for (int k = 0; k < n; ++k) {
            hp_result r;
            double xi[6];
            hp_planner_reset(p);
            if (hp_plan(p, t[k], &r) != HP_OK ||
                (r.status != HP_STATUS_REACHED && r.status != HP_STATUS_CLOSEST) ||
                bench_round_trip(L, HP_LEVEL_SURFACE, &r, xi, NULL) != HP_OK) {
                fails++;
                if (li == 2) memset(ref[k], 0, sizeof ref[k]);
                continue;
            }
            if (li == 2) memcpy(ref[k], xi, sizeof xi);
            double e = bench_pose_diff(xi, ref[k], r.commanded);
            if (!(e <= worst)) worst = e;
        }
        plan_ctx c = {p, (const double(*)[6])t, n, 0};
        bench_timing tm;
        rc = bench_time(o, batch, &c, &tm) != 0 ? CLI_EXIT_SOFTWARE : 0;
        hp_planner_destroy(p);
        if (rc) return rc;
        double bound;
        if (hp_contact_error_bound(L, levels[li], tr, rot, &bound) != HP_OK) bound = NAN;
        row->lv[li].bound_mm = bound * 1e3;
        row->lv[li].median_ns = tm.median_ns;
        row->lv[li].p99_ns = tm.p99_ns;
        row->lv[li].max_error = worst;
        row->lv[li].failures = fails;
    }
    fprintf(stderr, "bench levels: %-16s auto=%-7s (%.3g mm, %.3g deg, tolerance %g mm)\n", stem,
            hp_level_name(row->auto_level), row->trans_mm, row->rot_deg, row->tol_mm);
    return 0;
}

static void csv_row(const void *arg, int i, FILE *f)
{
    const level_row *r = (const level_row *)arg + i;
    double tauto = r->lv[r->auto_level].median_ns;
    for (int l = 0; l < 3; ++l)
        fprintf(f, "%s,%s,%d,%.6g,%.6g,%g,%s,%s,%d,%.6e,%d,%.1f,%.1f,%.6e,%ld,%.4g\n", r->scene,
                r->backend, r->targets, r->trans_mm, r->rot_deg, r->tol_mm,
                hp_level_name(r->auto_level), hp_level_name(levels[l]), levels[l] == r->auto_level,
                r->lv[l].bound_mm, r->lv[l].bound_mm <= r->tol_mm, r->lv[l].median_ns,
                r->lv[l].p99_ns, r->lv[l].max_error, r->lv[l].failures, r->lv[l].median_ns / tauto);
}

int bench_levels(const bench_options *o, const char *dir)
{
    static level_row rows[MAX_SCENES];
    int nr = 0;
    int rc = bench_each_scene(o, run_scene, rows, sizeof *rows, MAX_SCENES, &nr);
    if (rc) return rc;
    if ((rc = bench_save_csv(dir, "levels.csv",
                             "scene,backend,targets,trans_mm,rot_deg,tolerance_mm,auto_level,"
                             "level,is_auto,bound_mm,bound_meets_tolerance,median_ns,p99_ns,"
                             "max_error,failures,time_ratio_to_auto",
                             csv_row, rows, nr)) != 0)
        return rc;
    printf("%-16s %-8s %7s %8s %7s %-8s %-8s %10s %12s %12s %8s\n", "scene", "backend", "targets",
           "size_mm", "size_deg", "auto", "level", "bound_mm", "median_ns", "max_error",
           "failures");
    for (int i = 0; i < nr; ++i)
        for (int l = 0; l < 3; ++l) {
            const level_row *r = &rows[i];
            printf("%-16s %-8s %7d %8.3g %7.3g %-8s %-8s %10.3e %12.0f %12.3e %8ld%s\n", r->scene,
                   r->backend, r->targets, r->trans_mm, r->rot_deg, hp_level_name(r->auto_level),
                   hp_level_name(levels[l]), r->lv[l].bound_mm, r->lv[l].median_ns,
                   r->lv[l].max_error, r->lv[l].failures,
                   levels[l] == r->auto_level ? "  <- auto" : "");
        }
    fprintf(stderr, "bench levels: wrote %s/levels.csv\n", dir);
    return 0;
}
