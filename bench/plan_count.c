/* headplan-bench-count: a fixed workload of hp_plan calls for counting instructions
 * (bench/plan_instructions.sh runs it under valgrind's callgrind; counts, unlike times, do
 * not depend on how busy the machine is). Public API only, so the same file also builds
 * against an older commit's library to compare before and after (docs/benchmarks.md,
 * section 6).
 *
 *   headplan-bench-count SCENE cold LEVEL MM DEG REPS
 *       40 seeded targets uniform in ±MM mm and ±DEG deg per axis, each planned cold
 *       (hp_planner_reset before it), REPS times over; realtime, tolerance 1e-9.
 *   headplan-bench-count SCENE trace LEVEL AMP_MM ROWS
 *       a drift x(t) = AMP·(1 + sin(t/400))·(1, 0.6, −0.75 mm; 0.25, 0.1, −0.15 deg)
 *       planned in order, warm start on, no reset.
 * LEVEL: 0 linear, 1 plane, 2 surface. Prints the statuses and the mean active-set steps
 * (hp_result.iterations) of one pass on stdout. */
#include <headplan/headplan.h>
#include <headplan/hp_planner.h>
#include <headplan/hp_scene.h>

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define N_TARGETS 40
#define PI 3.14159265358979323846

static uint64_t rng = 12345;
static double urand(void) /* 64-bit LCG: seeded, the same on every machine */
{
    rng = rng * 6364136223846793005ULL + 1442695040888963407ULL;
    return (double)(rng >> 11) / 9007199254740992.0;
}

static int usage(void)
{
    fprintf(stderr, "usage: headplan-bench-count SCENE cold LEVEL MM DEG REPS\n"
                    "       headplan-bench-count SCENE trace LEVEL AMP_MM ROWS\n");
    return 64;
}

int main(int argc, char **argv)
{
    if (argc != 7 && argc != 6) return usage();
    int cold = strcmp(argv[2], "cold") == 0;
    if ((cold && argc != 7) || (!cold && (strcmp(argv[2], "trace") != 0 || argc != 6)))
        return usage();
    int level = atoi(argv[3]);
    if (level < 0 || level > 2) return usage();
    static hp_scene sc;
    hp_diag d = {{0}};
    if (hp_scene_load(argv[1], &sc, &d) != HP_OK) {
        fprintf(stderr, "headplan-bench-count: %s\n", d.text);
        return 66;
    }
    hp_settings st;
    hp_settings_default(&st);
    st.level = (hp_level)level;
    st.tolerance = 1e-9;
    st.warm_start = !cold;
    st.max_iter = 3000;
    st.max_time = 5.0;
    hp_planner *p = NULL;
    if (hp_planner_create(&sc.layout, &st, &p, &d) != HP_OK) {
        fprintf(stderr, "headplan-bench-count: %s\n", d.text);
        return 65;
    }
    int count[HP_STATUS_COUNT_] = {0};
    long steps = 0, plans = 0;
    if (cold) {
        double mm = atof(argv[4]), deg = atof(argv[5]), t[N_TARGETS][6];
        long reps = atol(argv[6]);
        for (int k = 0; k < N_TARGETS; ++k)
            for (int i = 0; i < 6; ++i) {
                double u = 2 * urand() - 1;
                t[k][i] = i < 3 ? u * mm * 1e-3 : u * deg * PI / 180;
            }
        for (long r = 0; r < reps; ++r)
            for (int k = 0; k < N_TARGETS; ++k) {
                hp_result res;
                hp_planner_reset(p);
                hp_plan(p, t[k], &res);
                if (r == 0) {
                    count[res.status]++;
                    steps += res.iterations;
                    ++plans;
                }
            }
    } else {
        static const double dir[6] = {1, 0.6, -0.75, 0.25, 0.1, -0.15};
        double amp = atof(argv[4]);
        long rows = atol(argv[5]);
        for (long k = 0; k < rows; ++k) {
            double t[6], s = amp * (1 + sin((double)k / 400.0));
            for (int i = 0; i < 6; ++i) t[i] = i < 3 ? s * dir[i] * 1e-3 : s * dir[i] * PI / 180;
            hp_result res;
            hp_plan(p, t, &res);
            count[res.status]++;
            steps += res.iterations;
            ++plans;
        }
    }
    printf("plans %ld; mean active-set steps %.2f;", plans, (double)steps / (double)plans);
    for (int i = 0; i < HP_STATUS_COUNT_; ++i)
        if (count[i]) printf(" %s %d", hp_status_name((hp_status)i), count[i]);
    printf("\n");
    hp_planner_destroy(p);
    return 0;
}
