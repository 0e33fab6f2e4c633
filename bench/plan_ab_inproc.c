/* plan-ab-inproc: two builds of the library timed in one process, interleaved finely
 * (bench/plan_ab.sh, its third part). The virtual machine's speed drifts by ±10 % over
 * seconds; two programs run one after the other see different drifts, and even alternating
 * runs (plan_ab.sh's second part) resolve ~1 %. Here both libraries are loaded (dlopen,
 * each its own copy of the code and state) and every round times 80 cold plans of each,
 * in alternating order, so a drift hits both within a millisecond; the median of the
 * ROUNDS per-round ratios B/A is the figure. Public API only.
 *
 *   plan-ab-inproc LIB_A LIB_B SCENE LEVEL MM DEG ROUNDS
 *     LIB_*: paths of two different libheadplan.so files (copies, if the same file);
 *     the 40 targets of headplan-bench-count (seeded, uniform in ±MM mm, ±DEG deg). */
#define _GNU_SOURCE
#include <headplan/headplan.h>
#include <headplan/hp_planner.h>
#include <headplan/hp_scene.h>
#include "standalone.h"

#include <dlfcn.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#define N_TARGETS 40

typedef struct lib {
    hp_error (*load)(const char *, hp_scene *, hp_diag *);
    void (*defaults)(hp_settings *);
    hp_error (*create)(const hp_layout *, const hp_settings *, hp_planner **, hp_diag *);
    void (*reset)(hp_planner *);
    hp_error (*plan)(hp_planner *, const double *, hp_result *);
    hp_planner *p;
    hp_scene sc;
} lib;

static int open_lib(lib *L, const char *path, const char *scene, int level)
{
    void *h = dlopen(path, RTLD_NOW | RTLD_LOCAL);
    if (!h) {
        fprintf(stderr, "plan-ab-inproc: %s\n", dlerror());
        return 0;
    }
    /* POSIX: a function pointer from dlsym's void * (the conversion dlsym is made for) */
    *(void **)&L->load = dlsym(h, "hp_scene_load");
    *(void **)&L->defaults = dlsym(h, "hp_settings_default");
    *(void **)&L->create = dlsym(h, "hp_planner_create");
    *(void **)&L->reset = dlsym(h, "hp_planner_reset");
    *(void **)&L->plan = dlsym(h, "hp_plan");
    if (!L->load || !L->defaults || !L->create || !L->reset || !L->plan) {
        fprintf(stderr, "plan-ab-inproc: %s lacks the public API\n", path);
        return 0;
    }
    hp_diag d = {{0}};
    hp_settings s;
    if (L->load(scene, &L->sc, &d) != HP_OK) {
        fprintf(stderr, "plan-ab-inproc: %s\n", d.text);
        return 0;
    }
    L->defaults(&s);
    s.level = (hp_level)level;
    s.tolerance = 1e-9;
    s.warm_start = 0;
    s.max_iter = 3000;
    s.max_time = 5.0;
    if (L->create(&L->sc.layout, &s, &L->p, &d) != HP_OK) {
        fprintf(stderr, "plan-ab-inproc: %s\n", d.text);
        return 0;
    }
    return 1;
}

/* ns per plan over reps passes of the targets, each plan cold */
static double block(lib *L, double (*t)[6], int reps)
{
    double t0 = sa_now();
    for (int r = 0; r < reps; ++r)
        for (int k = 0; k < N_TARGETS; ++k) {
            hp_result res;
            L->reset(L->p);
            L->plan(L->p, t[k], &res);
        }
    return (sa_now() - t0) / (reps * N_TARGETS) * 1e9;
}

int main(int argc, char **argv)
{
    if (argc != 8) {
        fprintf(stderr, "usage: plan-ab-inproc LIB_A LIB_B SCENE LEVEL MM DEG ROUNDS\n");
        return 64;
    }
    int level = atoi(argv[4]), rounds = atoi(argv[7]);
    double mm = atof(argv[5]), deg = atof(argv[6]);
    if (level < 0 || level > 2 || rounds < 1 || rounds > 100000) return 64;
    static double t[N_TARGETS][6];
    sa_targets(mm, deg, N_TARGETS, t); /* headplan-bench-count's targets */
    static lib A, B;
    if (!open_lib(&A, argv[1], argv[3], level) || !open_lib(&B, argv[2], argv[3], level)) return 66;
    double *a = malloc(sizeof *a * (size_t)rounds), *b = malloc(sizeof *b * (size_t)rounds),
           *q = malloc(sizeof *q * (size_t)rounds);
    if (!a || !b || !q) return 71;
    block(&A, t, 5); /* warm the caches and the branch predictors of both */
    block(&B, t, 5);
    for (int r = 0; r < rounds; ++r) {
        if (r & 1) {
            b[r] = block(&B, t, 2);
            a[r] = block(&A, t, 2);
        } else {
            a[r] = block(&A, t, 2);
            b[r] = block(&B, t, 2);
        }
        q[r] = b[r] / a[r];
    }
    qsort(a, (size_t)rounds, sizeof *a, sa_by_value);
    qsort(b, (size_t)rounds, sizeof *b, sa_by_value);
    qsort(q, (size_t)rounds, sizeof *q, sa_by_value);
    printf("interleaved: A median %.0f ns, B median %.0f ns, median of round ratios B/A %.4f "
           "(quartiles %.4f, %.4f; %d rounds)\n",
           a[rounds / 2], b[rounds / 2], q[rounds / 2], q[rounds / 4], q[3 * rounds / 4], rounds);
    free(a);
    free(b);
    free(q);
    return 0;
}
