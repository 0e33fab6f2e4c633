#define _DEFAULT_SOURCE
#include "cli/cli_args.h"
/* headplan-bench: shared helpers (see bench_util.h). */
#include "bench/bench_util.h"
#include "bench/bench_report.h"
#include "bench/loop_trace.h"
#include "cli/exit_codes.h"
#include "planner/problem_setup.h"

#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int bench_load_layout(const char *path, hp_scene *scene)
{
    hp_diag d;
    if (hp_scene_file_kind(path) != HP_SCENE_LAYOUT) {
        cli_fail(0, "bench", "%s: not a layout scene", path);
        return CLI_EXIT_DATAERR;
    }
    if (hp_scene_load(path, scene, &d) != HP_OK) {
        cli_fail(0, "bench", "%s", d.text);
        return CLI_EXIT_NOINPUT;
    }
    return 0;
}

int bench_planner_new(const hp_layout *L, const hp_settings *s, hp_planner **p)
{
    hp_diag d;
    if (hp_planner_create(L, s, p, &d) != HP_OK) {
        cli_fail(0, "bench", "planner (%s, %s, tolerance %g): %s", hp_backend_name(s->backend),
                 hp_level_name(s->level), s->tolerance, d.text);
        return CLI_EXIT_SOFTWARE;
    }
    return 0;
}

int bench_bounds_of(const hp_layout *L, bench_bounds *b)
{
    for (int k = 0; k < L->n; ++k) {
        hp_envelope e;
        if (hpi_bladder_envelope(&L->bladders[k], &e, NULL) != HP_OK) return -1;
        b->ri_lo[k] = e.ri_lo;
        b->ri_hi[k] = e.ri_hi;
        b->p_lo[k] = e.p_lo;
        b->p_hi[k] = e.p_hi;
    }
    return 0;
}

static hp_error outer_radii(const hp_layout *L, const hp_result *r, double *ro)
{
    for (int k = 0; k < L->n; ++k) {
        double ri;
        hp_error e = hp_iab_fk(&L->bladders[k].iab, r->bladders[k].pressure, &ri);
        if (e == HP_OK) e = hp_iab_ro(&L->bladders[k].iab, ri, &ro[k]);
        if (e != HP_OK) return e;
    }
    return HP_OK;
}

hp_error bench_round_trip(const hp_layout *L, hp_level level, const hp_result *r, double xi[6],
                          double *ro_out)
{
    double ro[HP_MAX_BLADDERS];
    hp_error e = outer_radii(L, r, ro);
    if (e != HP_OK) return e;
    if (ro_out)
        for (int k = 0; k < L->n; ++k) ro_out[k] = ro[k];
    return hp_contact_fk(L, level, ro, r->achieved, xi, NULL, NULL);
}

static double axis_diff(const double a[6], const double b[6], int i)
{
    return fabs(a[i] - b[i]) * (i < 3 ? 1e3 : 180.0 / BENCH_PI);
}

double bench_pose_diff(const double a[6], const double b[6], const int *commanded)
{
    double m = 0;
    for (int i = 0; i < 6; ++i) {
        if (commanded && !commanded[i]) continue;
        double d = axis_diff(a, b, i);
        if (!(d <= m)) m = d; /* NaN propagates */
    }
    return m;
}

double bench_pose_dist(const double a[6], const double b[6], const int *commanded)
{
    double s = 0;
    for (int i = 0; i < 6; ++i)
        if (!commanded || commanded[i]) s += axis_diff(a, b, i) * axis_diff(a, b, i);
    return sqrt(s);
}

double bench_limit_violation(const hp_layout *L, const hp_result *r)
{
    double v = 0;
    for (int k = 0; k < L->n; ++k) {
        const hp_bladder *b = &L->bladders[k];
        double P = r->bladders[k].pressure, s = r->bladders[k].stretch;
        double vp = fmax(fmax(P - b->p_max, b->p_min - P), 0) / (b->p_max - b->p_min);
        double vs = fmax(fmax(s - b->stretch_max, b->stretch_min - s), 0) /
                    (b->stretch_max - b->stretch_min);
        if (!(vp <= v)) v = vp;
        if (!(vs <= v)) v = vs;
    }
    return v;
}

double bench_contact_violation(const hp_layout *L, hp_level level, const hp_result *r)
{
    double ro[HP_MAX_BLADDERS], rho[HP_MAX_BLADDERS], v = 0;
    if (outer_radii(L, r, ro) != HP_OK ||
        hp_contact_eval(L, level, r->achieved, rho, NULL, NULL) != HP_OK)
        return NAN;
    for (int k = 0; k < L->n; ++k) {
        double d = fabs(ro[k] - rho[k]) * 1e3;
        if (!(d <= v)) v = d;
    }
    return v;
}

double bench_urand(uint64_t *s) { return sa_xorshift(s); }

void bench_unit6(uint64_t *s, double u[6])
{
    double n2 = 0;
    do {
        n2 = 0;
        for (int i = 0; i < 6; ++i) {
            double a = bench_urand(s), b = bench_urand(s);
            u[i] = sqrt(-2.0 * log(1.0 - a)) * cos(2.0 * BENCH_PI * b);
            n2 += u[i] * u[i];
        }
    } while (!(n2 > 1e-6));
    double n = sqrt(n2);
    for (int i = 0; i < 6; ++i) u[i] /= n;
}

void bench_to_si(const double mm_deg[6], double xi[6])
{
    for (int i = 0; i < 6; ++i) xi[i] = mm_deg[i] * (i < 3 ? 1e-3 : BENCH_PI / 180.0);
}

void bench_plan_batch(void *vctx, long first, long count)
{
    bench_plan_ctx *c = vctx;
    long pos = first % c->n;
    hp_result r;
    for (long j = 0; j < count; ++j) {
        if (!c->warm) hp_planner_reset(c->p);
        if (hp_plan(c->p, c->targets[c->perm ? c->perm[pos] : pos], &r) == HP_OK)
            c->sink += r.bladders[0].pressure;
        if (++pos == c->n) pos = 0;
    }
}

static int cmp_names(const void *a, const void *b)
{
    return strcmp(*(char *const *)a, *(char *const *)b);
}

#define BENCH_MAX_SCENE_FILES 64

/* The catalogue folder dir cannot be opened: one line, CLI_EXIT_NOINPUT. */
static int catalogue_refused(const char *dir)
{
    cli_fail(0, "bench", "--scenarios: cannot open folder '%s'", dir);
    return CLI_EXIT_NOINPUT;
}

int bench_catalogue_readable(const char *dir)
{
    DIR *dp = opendir(dir);
    if (!dp) return catalogue_refused(dir);
    closedir(dp);
    return 0;
}

int bench_each_scene(const bench_options *o, bench_scene_fn run, void *rows, size_t row_size,
                     int max_rows, int *nrows)
{
    *nrows = 0;
    DIR *dp = opendir(o->scenarios);
    if (!dp) return catalogue_refused(o->scenarios);
    char *names[BENCH_MAX_SCENE_FILES];
    int nn = 0, rc = 0;
    struct dirent *de;
    while ((de = readdir(dp)) && nn < BENCH_MAX_SCENE_FILES) {
        size_t len = strlen(de->d_name);
        if (len > 5 && strcmp(de->d_name + len - 5, ".yaml") == 0) {
            if (!(names[nn] = strdup(de->d_name))) {
                rc = CLI_EXIT_SOFTWARE;
                break;
            }
            ++nn;
        }
    }
    closedir(dp);
    qsort(names, (size_t)nn, sizeof *names, cmp_names);
    for (int i = 0; i < nn && rc == 0 && *nrows < max_rows; ++i) {
        char path[4096], stem[BENCH_STEM_MAX];
        if ((size_t)snprintf(path, sizeof path, "%s/%s", o->scenarios, names[i]) >= sizeof path ||
            (size_t)snprintf(stem, sizeof stem, "%.*s", (int)(strlen(names[i]) - 5), names[i]) >=
                sizeof stem) {
            cli_fail(0, "bench", "--scenarios: %s/%s: path or name too long", o->scenarios,
                     names[i]);
            rc = CLI_EXIT_USAGE;
            break;
        }
        int r = run(o, path, stem, (char *)rows + (size_t)*nrows * row_size);
        if (r == 0) ++*nrows;
        else if (r != 1) rc = r;
    }
    for (int i = 0; i < nn; ++i) free(names[i]);
    return rc;
}

typedef struct csv_job {
    const char *header;
    bench_csv_row_fn row;
    const void *arg;
    int n;
} csv_job;

static int csv_job_write(const void *arg, FILE *f)
{
    const csv_job *j = arg;
    fprintf(f, "%s\n", j->header);
    for (int i = 0; i < j->n; ++i) j->row(j->arg, i, f);
    return ferror(f) ? -1 : 0;
}

int bench_save_csv(const char *dir, const char *name, const char *header, bench_csv_row_fn row,
                   const void *arg, int n)
{
    csv_job j = {header, row, arg, n};
    return bench_save(dir, name, csv_job_write, &j);
}
