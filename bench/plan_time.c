/* headplan-plan-time: median wall time of one cold hp_plan on a fixed set of targets, for
 * comparing two builds of the library (bench/plan_ab.sh runs two copies of it, each against
 * one build's shared library, in alternation). A benchmark, not a test: it prints a time.
 *
 *   plan_time SCENE LEVEL MM DEG ROUNDS
 *       40 seeded targets uniform in ±MM mm and ±DEG deg per axis (the generator of
 *       bench/plan_count.c), planned cold (hp_planner_reset before each) 10 times over per
 *       round; prints the median over ROUNDS of a round's time per plan, in ns.
 * LEVEL: 0 linear, 1 plane, 2 surface. Realtime backend, tolerance 1e-9. Public API only. */
#define _POSIX_C_SOURCE 200809L
#include <headplan/headplan.h>
#include <headplan/hp_planner.h>
#include <headplan/hp_scene.h>

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#define N_TARGETS 40
#define PI 3.14159265358979323846

static uint64_t rng = 12345;
static double urand(void) /* the LCG of bench/plan_count.c */
{
    rng = rng * 6364136223846793005ULL + 1442695040888963407ULL;
    return (double)(rng >> 11) / 9007199254740992.0;
}

static double now_s(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static int by_value(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

int main(int argc, char **argv)
{
    if (argc != 6) {
        fprintf(stderr, "usage: plan_time SCENE LEVEL MM DEG ROUNDS\n");
        return 64;
    }
    int level = atoi(argv[2]), rounds = atoi(argv[5]);
    if (level < 0 || level > 2 || rounds < 1 || rounds > 100000) {
        fprintf(stderr, "plan_time: LEVEL must be 0..2 and ROUNDS 1..100000\n");
        return 64;
    }
    static hp_scene sc;
    hp_diag d = {{0}};
    if (hp_scene_load(argv[1], &sc, &d) != HP_OK) {
        fprintf(stderr, "plan_time: %s\n", d.text);
        return 66;
    }
    hp_settings st;
    hp_settings_default(&st);
    st.level = (hp_level)level;
    st.tolerance = 1e-9;
    st.warm_start = 0;
    st.max_iter = 3000;
    st.max_time = 5.0;
    hp_planner *p = NULL;
    if (hp_planner_create(&sc.layout, &st, &p, &d) != HP_OK) {
        fprintf(stderr, "plan_time: %s\n", d.text);
        return 65;
    }
    double mm = atof(argv[3]), deg = atof(argv[4]), t[N_TARGETS][6];
    for (int k = 0; k < N_TARGETS; ++k)
        for (int i = 0; i < 6; ++i) {
            double u = 2 * urand() - 1;
            t[k][i] = i < 3 ? u * mm * 1e-3 : u * deg * PI / 180;
        }
    double *per = malloc(sizeof *per * (size_t)rounds);
    if (!per) return 71;
    for (int r = 0; r < rounds; ++r) {
        double t0 = now_s();
        for (int rep = 0; rep < 10; ++rep)
            for (int k = 0; k < N_TARGETS; ++k) {
                hp_result res;
                hp_planner_reset(p);
                hp_plan(p, t[k], &res);
            }
        per[r] = (now_s() - t0) / (10.0 * N_TARGETS) * 1e9;
    }
    qsort(per, (size_t)rounds, sizeof *per, by_value);
    printf("%.1f\n", per[rounds / 2]);
    free(per);
    hp_planner_destroy(p);
    return 0;
}
