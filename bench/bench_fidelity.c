/* headplan-bench, family "fidelity": each level's pose error against the finite-element
 * reference, on the catalogue's layout scenes.
 *
 * For every layout scene and its cases (the scene's own correction, then a seeded sweep
 * inside the clinical range: |t| <= 20 mm, every angle <= 15°), each level (linear, plane,
 * surface, load) plans with the scene's backend and settings. Its pressures go to the
 * reference: the head's rest under its weight (hp_load_rest, surface geometry) on a load
 * model that evaluates the contact law fitted to the CalculiX tables (fem/), from the pose
 * the plan claims. The level's error is that rest against the claimed pose (the desired pose
 * when the plan reached it): the translation's norm in mm and the rotation's angle in
 * degrees. The fitted law itself is uncertain by its worst error against the tables
 * (fem/tables/law_error.csv, read at run time); the band columns are the larger deviation of
 * the rests under a force scaled by 1 ± that error (a force scaled by s rests where the
 * weight over s does, so the band scales the mass). A scene with no load carries the
 * default head (hp_load_spec_default: the head's mass at its centre, supine gravity): the
 * row says so. A rest whose contact leaves the fitted law's domain is flagged with the
 * bladder and the group (an extrapolation, never silent). The load level's row names the law
 * its planner used: with the cap law it measures the cap law's error, with the fitted law
 * only the band is left; and, as the harness's own check, the rest of its pressures under
 * the planner's own load model from the pose it claims (that pose, when its stiffness there
 * is positive definite: own_stable). Writes DIR/fidelity.csv, the chart DIR/fidelity.gp ->
 * fidelity.png, fidelity.svg, and prints one line per scene and level. */
#define _DEFAULT_SOURCE
#include "bench/bench.h"
#include "bench/bench_report.h"
#include "bench/bench_util.h"
#include "cli/cli_args.h"
#include "cli/cli_fidelity.h"
#include "cli/cli_gptext.h"
#include "cli/exit_codes.h"
#include "headplan/headplan.h"
#include "kinematics/load_law_pick.h"
#include "planner/planner_internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_FID_SCENES 24
#define N_SWEEP_FULL 6
#define N_SWEEP_QUICK 2
#define MAX_CASES (1 + N_SWEEP_FULL)
#define N_LEVELS 4
#define SWEEP_T_MAX 0.020                    /* [m] */
#define SWEEP_ANGLE_MAX (15.0 * HP_PI / 180) /* [rad] */
#define LAW_ERROR_CSV HP_SOURCE_DIR "/fem/tables/law_error.csv"

static const hp_level LEVELS[N_LEVELS] = {HP_LEVEL_LINEAR, HP_LEVEL_PLANE, HP_LEVEL_SURFACE,
                                          HP_LEVEL_LOAD};

typedef struct fid_cell {
    char status[20];       /* the plan's status, "refused" (create) or "error" (hp_plan) */
    char law[8];           /* the load level's planning law ("cap", "fitted"); "-" elsewhere */
    hpi_fidelity_result m; /* the pressures against the reference (NaN: no plan) */
    double own_mm;         /* load level: its pressures' rest under its own model (law and
                        geometry) against the pose it claims, the harness's check (NaN
                        elsewhere; +inf: no rest) */
    int own_stable;        /* load level: 1 when its own model's stiffness is positive definite at
                        the pose it claims, 0 when not, -1 unknown or another level */
} fid_cell;

typedef struct fid_row {
    char scene[BENCH_STEM_MAX]; /* the file's stem, whole */
    char backend[16];
    int scene_mass; /* 1: the scene's load; 0: the default head's */
    double tolerance, level_tol_mm;
    int ncases;
    fid_cell c[MAX_CASES][N_LEVELS];
} fid_row;

/* The fitted law's worst relative error in force over its tables (the band's half-width). */
static double g_band = NAN;

/* Column index of name in a CSV header line (modified: split at commas), or -1. */
static int col_of(char *header, const char *name)
{
    char *save = NULL;
    int i = 0;
    for (char *tok = strtok_r(header, ",\n", &save); tok; tok = strtok_r(NULL, ",\n", &save), ++i)
        if (strcmp(tok, name) == 0) return i;
    return -1;
}

/* The fitted law's worst |law_error| over the rows of its table that lie in its domain
 * (rows outside it, such as the thick wall's, say how far it extrapolates, not how well it
 * fits): the dimensionless groups make a bladder with C1 = 1 and ro = 1. */
static int read_band(void)
{
    FILE *f = fopen(LAW_ERROR_CSV, "r");
    if (!f)
        return cli_fail(CLI_EXIT_NOINPUT, "bench",
                        "fidelity: cannot open %s (the fitted law's error table)", LAW_ERROR_CSV);
    static const char *const names[6] = {"delta_over_ro", "thickness_over_ro",   "P_over_C1",
                                         "C2_over_C1",    "ro_over_head_radius", "law_error"};
    char line[512];
    int col[6] = {-1, -1, -1, -1, -1, -1}, rows = 0;
    double worst = 0.0;
    while (fgets(line, sizeof line, f)) {
        if (line[0] == '#') continue;
        if (col[0] < 0) {
            for (int j = 0; j < 6; ++j) {
                char h[512];
                memcpy(h, line, sizeof h);
                col[j] = col_of(h, names[j]);
            }
            continue;
        }
        double v[6] = {0};
        int got = 0;
        char *save = NULL, *tok = strtok_r(line, ",\n", &save);
        for (int i = 0; tok; ++i, tok = strtok_r(NULL, ",\n", &save))
            for (int j = 0; j < 6; ++j)
                if (col[j] == i) {
                    char *end;
                    v[j] = strtod(tok, &end);
                    got += end != tok;
                }
        if (got != 6) continue;
        hp_claw_bladder b = {1.0, v[3], v[1], v[4]};
        if (hpi_claw_fem_domain(&b, v[2], 1.0, 1.0 - v[0]) != HP_CLAW_IN) continue;
        worst = fmax(worst, fabs(v[5]));
        ++rows;
    }
    fclose(f);
    if (rows == 0 || !(worst > 0 && worst < 0.5))
        return cli_fail(CLI_EXIT_DATAERR, "bench",
                        "fidelity: %s: no row in the law's domain with a law_error in (0, 0.5)",
                        LAW_ERROR_CSV);
    g_band = worst;
    return 0;
}

/* The cases: the scene's correction (when it has one), then the seeded sweep. */
static int cases_of(const bench_options *o, const hp_scene *sc, double (*t)[6])
{
    int n = 0;
    if (sc->has_correction) memcpy(t[n++], sc->correction, sizeof t[0]);
    uint64_t s = 0x9e3779b97f4a7c15ULL ^ (uint64_t)o->seed;
    int sweep = o->quick ? N_SWEEP_QUICK : N_SWEEP_FULL;
    for (int k = 0; k < sweep; ++k) {
        double u[6];
        bench_unit6(&s, u);
        double nt = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
        double nr = sqrt(u[3] * u[3] + u[4] * u[4] + u[5] * u[5]);
        double at = SWEEP_T_MAX * bench_urand(&s), ar = SWEEP_ANGLE_MAX * bench_urand(&s);
        for (int i = 0; i < 3; ++i) {
            t[n][i] = nt > 0 ? at * u[i] / nt : 0.0;
            t[n][3 + i] = nr > 0 ? ar * u[3 + i] / nr : 0.0;
        }
        ++n;
    }
    return n;
}

static int run_scene(const bench_options *o, const char *path, const char *stem, void *vrow)
{
    fid_row *row = vrow;
    static hp_scene sc;
    hp_diag d;
    if (hp_scene_file_kind(path) != HP_SCENE_LAYOUT) return 1;
    if (hp_scene_load(path, &sc, &d) != HP_OK) {
        fprintf(stderr, "bench fidelity: %s: refused, left out: %s\n", stem, d.text);
        return 1;
    }
    hp_settings base;
    if (hp_scene_settings(&sc, &base, &d) != HP_OK) {
        fprintf(stderr, "bench fidelity: %s: settings refused, left out: %s\n", stem, d.text);
        return 1;
    }
    memset(row, 0, sizeof *row);
    snprintf(row->scene, sizeof row->scene, "%s", stem); /* fits: bench_util.h */
    snprintf(row->backend, sizeof row->backend, "%s", hp_backend_name(base.backend));
    row->tolerance = base.tolerance;
    row->level_tol_mm = sc.level_tolerance * 1e3;
    hp_load_spec spec;
    row->scene_mass = cli_fidelity_spec(&sc, &spec);
    hpi_fidelity_ref ref;
    if (hpi_fidelity_open(&sc.layout, &spec, g_band, &ref) != HP_OK) {
        hpi_fidelity_close(&ref);
        fprintf(stderr, "bench fidelity: %s: no load model, left out\n", stem);
        return 1;
    }
    double t[MAX_CASES][6];
    row->ncases = cases_of(o, &sc, t);
    for (int li = 0; li < N_LEVELS; ++li) {
        hp_settings s;
        cli_fidelity_settings(&sc, &base, LEVELS[li], &spec, &s);
        hp_planner *p = NULL;
        hp_error ce = hp_planner_create(&sc.layout, &s, &p, &d);
        const char *law = "-";
        if (!ce && p->load)
            law = hpi_load_model_law(&p->load->M) == HP_CLAW_LAW_FEM ? "fitted" : "cap";
        for (int k = 0; k < row->ncases; ++k) {
            fid_cell *c = &row->c[k][li];
            snprintf(c->law, sizeof c->law, "%s", law);
            c->m.pose_mm = c->m.pose_deg = c->m.band_mm = c->m.band_deg = NAN;
            c->m.indent_max = c->m.carried = c->own_mm = NAN;
            c->own_stable = -1;
            snprintf(c->m.domain, sizeof c->m.domain, "-");
            if (ce) {
                snprintf(c->status, sizeof c->status, "refused");
                continue;
            }
            hp_result r;
            hp_planner_reset(p);
            if (hp_plan(p, t[k], &r) != HP_OK) {
                snprintf(c->status, sizeof c->status, "error");
                continue;
            }
            snprintf(c->status, sizeof c->status, "%s", hp_status_name(r.status));
            if (!hpi_fidelity_answered(r.status)) continue; /* no answer: not measured */
            double P[HP_MAX_BLADDERS];
            for (int b = 0; b < r.n; ++b) P[b] = r.bladders[b].pressure;
            hpi_fidelity_measure(&ref, P, r.achieved, &c->m);
            if (p->load) {
                double rest[6];
                hp_load_holding h;
                c->own_stable = hp_load_holding_at(&p->load->M, r.achieved, P, &h) == HP_OK
                                    ? h.stable
                                    : -1;
                c->own_mm = hp_load_rest(&p->load->M, P, r.achieved, rest, NULL) == HP_OK
                                ? hpi_pose_translation_mm(rest, r.achieved)
                                : INFINITY;
            }
        }
        hp_planner_destroy(p);
    }
    hpi_fidelity_close(&ref);
    fprintf(stderr, "bench fidelity: %s: %d cases\n", stem, row->ncases);
    return 0;
}

static void csv_row(const void *arg, int i, FILE *f)
{
    const fid_row *r = (const fid_row *)arg + i;
    for (int k = 0; k < r->ncases; ++k)
        for (int li = 0; li < N_LEVELS; ++li) {
            const fid_cell *c = &r->c[k][li];
            /* The scene's stem and the domain (a bladder's name) are the user's text. */
            cli_put_csv_text(f, r->scene);
            fprintf(f, ",%d,%s,%s,%s,%s,%s,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,", k,
                    hp_level_name(LEVELS[li]), r->backend, c->law, c->status,
                    r->scene_mass ? "scene" : "default", r->tolerance, r->level_tol_mm, g_band,
                    c->m.pose_mm, c->m.pose_deg, c->m.band_mm, c->m.band_deg, c->m.indent_max,
                    c->m.carried);
            cli_put_csv_text(f, c->m.domain);
            fprintf(f, ",%.6g,%d\n", c->own_mm, c->own_stable);
        }
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Median of the finite-or-infinite (not NaN) values of v[n] (sorted in place); NaN when
 * none. */
static double median_of(double *v, int n)
{
    int m = 0;
    for (int i = 0; i < n; ++i)
        if (!isnan(v[i])) v[m++] = v[i];
    if (m == 0) return NAN;
    qsort(v, (size_t)m, sizeof *v, cmp_double);
    return m % 2 ? v[m / 2] : 0.5 * (v[m / 2 - 1] + v[m / 2]);
}

/* Errors drawn at this height [mm] when unbounded (no rest), labelled so. */
#define ERROR_CEILING_MM 1e3
/* Errors below this [mm] drawn at it on the log scale; the CSV keeps the true value. */
#define ERROR_FLOOR_MM 1e-12

typedef struct chart_arg {
    const fid_row *rows;
    int n;
} chart_arg;

static double chart_mm(double v)
{
    return isfinite(v) ? fmax(v, ERROR_FLOOR_MM) : ERROR_CEILING_MM;
}

/* Two panels, data inline (the script redraws alone): per scene and level the median and
 * the worst (with the law's band) pose error against the reference, log scale, unbounded
 * at the ceiling, beside each scene's solver tolerance; and the median share of the weight
 * the bladders bear at the claimed pose. Scene names reach the script as quoted text
 * (cli_gptext.h), never inside the data block. */
static int chart_writer(const void *arg, FILE *f)
{
    const chart_arg *a = arg;
    fprintf(f,
            "# Generated by headplan-bench (fidelity family); data inline, from "
            "fidelity.csv.\n# Redraw: gnuplot fidelity.gp\nceiling = %g\n"
            "# scene, level, x, median mm, worst mm (band), tolerance mm, carried %%\n"
            "$d << EOD\n",
            ERROR_CEILING_MM);
    for (int i = 0; i < a->n; ++i) {
        const fid_row *r = &a->rows[i];
        for (int li = 0; li < N_LEVELS; ++li) {
            double mm[MAX_CASES], car[MAX_CASES], worst = NAN;
            for (int k = 0; k < r->ncases; ++k) {
                const fid_cell *c = &r->c[k][li];
                mm[k] = c->m.pose_mm;
                car[k] = c->m.carried;
                if (!isnan(c->m.band_mm))
                    worst = isnan(worst) ? c->m.band_mm : fmax(worst, c->m.band_mm);
            }
            double med = median_of(mm, r->ncases), cm = median_of(car, r->ncases);
            if (isnan(med)) continue; /* refused: nothing to draw */
            fprintf(f, "%d %d %.6g %.6g %.6g %.6g %.6g\n", i, li,
                    li + (i - 0.5 * (a->n - 1)) * 0.6 / (a->n > 1 ? a->n : 1), chart_mm(med),
                    chart_mm(worst), r->tolerance, 100.0 * cm);
        }
    }
    fprintf(f, "EOD\nn = %d\narray names[%d]\n", a->n, a->n > 0 ? a->n : 1);
    for (int i = 0; i < a->n; ++i) {
        fprintf(f, "names[%d] = ", i + 1);
        gp_label(f, a->rows[i].scene);
        fprintf(f, "\n");
    }
    fprintf(f, "\nif (strstrt(GPVAL_TERMINALS, \"pngcairo\") > 0) {\n"
               "  set terminal pngcairo size 1400,600 enhanced font \"Sans,10\"\n"
               "} else {\n  set terminal png size 1400,600\n}\n"
               "set output \"fidelity.png\"\n"
               "do for [term = 1:2] {\n"
               "if (term == 2) { set terminal svg size 1400,600 dynamic enhanced font "
               "\"Sans,10\"; set output \"fidelity.svg\" }\n"
               "set multiplot layout 1,2 title \"Each level against the finite-element reference: "
               "the plan's pressures rested under the head's weight with the fitted law\" "
               "font \",12\"\n"
               "set grid\nset xrange [-0.6:3.6]\n"
               "set xtics (\"linear\" 0, \"plane\" 1, \"surface\" 2, \"load\" 3)\n"
               "set key below horizontal box noenhanced\n"
               "set logscale y\nset format y \"10^{%%L}\"\nset yrange [1e-12:ceiling*30]\n"
               "set title \"pose error (mm): median (filled), worst with the law's band (open); "
               "solver tolerance (dashes)\\nno rest: drawn at the ceiling\"\n"
               "set ylabel \"translation error [mm]\"\n"
               "plot for [i = 0:n-1] $d using ($1 == i ? $3 : NaN):4 with points pt 7 ps 1.4 "
               "lc i + 1 title names[i + 1], \\\n"
               "  for [i = 0:n-1] $d using ($1 == i ? $3 : NaN):5 with points pt 6 ps 1.8 "
               "lc i + 1 notitle, \\\n"
               "  $d using ($3 - 0.08):6:(0.16):(0) with vectors nohead dt 2 lc rgb "
               "\"#404040\" notitle, \\\n"
               "  ceiling with lines dt 3 lc rgb \"#909090\" title \"no rest (unbounded)\"\n"
               "unset logscale y\nset format y \"%%g\"\nset yrange [-5:105]\n"
               "set title \"share of the weight the bladders bear at the claimed pose "
               "(median)\"\nset ylabel \"weight carried [%%]\"\nunset key\n"
               "plot for [i = 0:n-1] $d using ($1 == i ? $3 : NaN):7 with points pt 7 ps 1.4 "
               "lc i + 1 notitle, \\\n"
               "  100 with lines dt 2 lc rgb \"#909090\" notitle\n"
               "unset multiplot\n}\nunset output\n");
    return ferror(f) ? -1 : 0;
}

int bench_fidelity(const bench_options *o, const char *dir)
{
    int rc = read_band();
    if (rc) return rc;
    static fid_row rows[MAX_FID_SCENES];
    int nr = 0;
    if ((rc = bench_each_scene(o, run_scene, rows, sizeof *rows, MAX_FID_SCENES, &nr)) != 0)
        return rc;
    if ((rc = bench_save_csv(
             dir, "fidelity.csv",
             "scene,case,level,backend,law,status,mass,tolerance,level_tolerance_mm,"
             "law_band,pose_mm,pose_deg,band_mm,band_deg,indent_max,carried,domain,own_mm,"
             "own_stable",
             csv_row, rows, nr)) != 0)
        return rc;
    chart_arg ca = {rows, nr};
    static const char *const outs[] = {"fidelity.png", "fidelity.svg", NULL};
    if ((rc = bench_save(dir, "fidelity.gp", chart_writer, &ca)) != 0 ||
        (rc = bench_gnuplot_run(dir, "fidelity.gp", outs)) != 0)
        return rc;
    printf("%-18s %-8s %-7s %10s %10s %10s %10s %9s\n", "scene", "level", "law", "median_mm",
           "median_deg", "worst_mm", "worst_deg", "outside");
    for (int i = 0; i < nr; ++i)
        for (int li = 0; li < N_LEVELS; ++li) {
            double mm[MAX_CASES], dg[MAX_CASES], wmm = NAN, wdg = NAN;
            int out = 0;
            for (int k = 0; k < rows[i].ncases; ++k) {
                const fid_cell *c = &rows[i].c[k][li];
                mm[k] = c->m.pose_mm;
                dg[k] = c->m.pose_deg;
                if (!isnan(c->m.band_mm)) wmm = isnan(wmm) ? c->m.band_mm : fmax(wmm, c->m.band_mm);
                if (!isnan(c->m.band_deg))
                    wdg = isnan(wdg) ? c->m.band_deg : fmax(wdg, c->m.band_deg);
                out += strcmp(c->m.domain, "in") != 0 && strcmp(c->m.domain, "-") != 0;
            }
            printf("%-18s %-8s %-7s %10.4g %10.4g %10.4g %10.4g %5d/%-3d\n", rows[i].scene,
                   hp_level_name(LEVELS[li]), rows[i].c[0][li].law, median_of(mm, rows[i].ncases),
                   median_of(dg, rows[i].ncases), wmm, wdg, out, rows[i].ncases);
        }
    fprintf(
        stderr,
        "bench fidelity: wrote %s/fidelity.csv, fidelity.png, fidelity.svg (law band ±%.1f %%)\n",
        dir, 100 * g_band);
    return 0;
}
