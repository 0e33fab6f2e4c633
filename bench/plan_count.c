/* headplan-bench-count: fixed workloads of hp_plan calls, for counting instructions
 * (bench/plan_instructions.sh runs it under valgrind's callgrind; counts, unlike times, do
 * not depend on how busy the machine is), for timing and for comparing two builds
 * (bench/plan_ab.sh runs it against two shared libraries). Public API only, so the same
 * file also builds against an older commit's library (CHANGELOG.md, realtime backend speed work).
 *
 *   headplan-bench-count SCENE cold LEVEL MM DEG REPS
 *       40 seeded targets uniform in ±MM mm and ±DEG deg per axis, each planned cold
 *       (hp_planner_reset before it), REPS times over; realtime, tolerance 1e-9.
 *   headplan-bench-count SCENE trace LEVEL AMP_MM ROWS
 *       a drift x(t) = AMP·(1 + sin(t/400))·(1, 0.6, −0.75 mm; 0.25, 0.1, −0.15 deg)
 *       planned in order, warm start on, no reset.
 *   headplan-bench-count SCENE time LEVEL MM DEG ROUNDS
 *       the cold targets 10 times over per round; prints the median over ROUNDS of a
 *       round's time per plan (ns, CLOCK_MONOTONIC) instead of the statuses.
 *   headplan-bench-count SCENE answers LEVEL MM DEG WARM
 *       400 seeded targets of the same generator, cold (WARM 0) or in order with the warm
 *       start (WARM 1); prints per plan the status, the active-set steps and the achieved
 *       pose (%a, exact) instead of the statuses.
 *   headplan-bench-count SCENE loop LEVEL BACKEND CYCLES
 *       the control loop of the loop benchmark's measured mode on a step trace: a new
 *       seeded target within ±3 mm, ±2 deg every 300 cycles, held between; every bladder's
 *       rate_max 500 Pa a plan; after each plan its pressures read back with ±3 Pa of
 *       seeded noise through hp_planner_set_measured; default settings otherwise, BACKEND
 *       by name (bench/loop_profile.sh profiles it by phase).
 *   headplan-bench-count SCENE tail LEVEL TRACE FEED CYCLES
 *       the loop benchmark's trace TRACE (smooth, noisy or step: sa_loop_trace, seeded as
 *       there) on two realtime planners in turn, rate-free first, then rate-limited
 *       (every bladder's rate_max 500 Pa), default settings otherwise; FEED 1 reads the
 *       rate-limited planner's pressures back with ±3 Pa of seeded noise through
 *       hp_planner_set_measured (the loop benchmark's measured mode), FEED 0 lets it plan
 *       from its own answers (the rate mode). Prints a line a plan: cycle, planner (0 free,
 *       1 rate-limited), status, 1 if a rate limit binds (else 0). bench/loop_tail.sh counts
 *       each plan's instructions.
 *   headplan-bench-count SCENE bits CYCLES
 *       the tail mode's replay for every level (0..2), trace and feed (18 replays, 2·CYCLES
 *       plans each), printing every answer whole: level, trace, feed, cycle, planner,
 *       status, the achieved pose and pose error, and every bladder's pressure, radii and
 *       binding flags, the numbers in %a (exact). Two builds that print the same text gave
 *       the same answers bit for bit (bench/plan_bits.sh compares two).
 *   headplan-bench-count clocks ROUNDS
 *       the cost of one read of the precise and of the coarse monotonic clock (the realtime
 *       backend's time budget reads the coarse one when max_time spans 100 of its ticks):
 *       the median over ROUNDS of 100 000 reads' mean, ns, and each clock's tick.
 * LEVEL: 0 linear, 1 plane, 2 surface. cold and trace print the statuses and the mean
 * active-set steps (hp_result.iterations) of one pass on stdout. */
#define _POSIX_C_SOURCE 200809L
#include <headplan/headplan.h>
#include <headplan/hp_planner.h>
#include <headplan/hp_scene.h>
#include "loop_trace.h"
#include "standalone.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define N_TARGETS 40
#define PI 3.14159265358979323846

static int usage(void)
{
    fprintf(stderr, "usage: headplan-bench-count SCENE cold LEVEL MM DEG REPS\n"
                    "       headplan-bench-count SCENE trace LEVEL AMP_MM ROWS\n"
                    "       headplan-bench-count SCENE time LEVEL MM DEG ROUNDS\n"
                    "       headplan-bench-count SCENE answers LEVEL MM DEG WARM\n"
                    "       headplan-bench-count SCENE loop LEVEL BACKEND CYCLES\n"
                    "       headplan-bench-count SCENE tail LEVEL TRACE FEED CYCLES\n"
                    "       headplan-bench-count SCENE bits CYCLES\n"
                    "       headplan-bench-count clocks ROUNDS\n");
    return 64;
}

/* The time mode: median over rounds of a round's time per cold plan (ns). */
static int time_plans(hp_planner *p, double mm, double deg, long rounds)
{
    static double t[N_TARGETS][6], per[10000];
    if (rounds < 1 || rounds > 10000) return usage();
    sa_targets(mm, deg, N_TARGETS, t);
    for (long r = 0; r < rounds; ++r) {
        double t0 = sa_now();
        for (int rep = 0; rep < 10; ++rep)
            for (int k = 0; k < N_TARGETS; ++k) {
                hp_result res;
                hp_planner_reset(p);
                hp_plan(p, t[k], &res);
            }
        per[r] = (sa_now() - t0) / (10.0 * N_TARGETS) * 1e9;
    }
    qsort(per, (size_t)rounds, sizeof *per, sa_by_value);
    printf("%.1f\n", per[rounds / 2]);
    return 0;
}

/* The answers mode: status, steps and achieved pose of 400 plans, exactly. */
static int print_answers(hp_planner *p, double mm, double deg, int warm)
{
    static double t[400][6];
    sa_targets(mm, deg, 400, t);
    for (int k = 0; k < 400; ++k) {
        hp_result res;
        if (!warm) hp_planner_reset(p);
        hp_plan(p, t[k], &res);
        printf("%s %d", hp_status_name(res.status), res.iterations);
        for (int i = 0; i < 6; ++i) printf(" %a", res.achieved[i]);
        printf("\n");
    }
    return 0;
}

/* The clocks mode: ns per read of each monotonic clock, and its tick. */
static int time_clocks(long rounds)
{
    static double per[1000];
    if (rounds < 1 || rounds > 1000) return usage();
#ifdef CLOCK_MONOTONIC_COARSE
    const clockid_t id[2] = {CLOCK_MONOTONIC, CLOCK_MONOTONIC_COARSE};
#else
    const clockid_t id[2] = {CLOCK_MONOTONIC, CLOCK_MONOTONIC};
#endif
    const char *name[2] = {"precise (CLOCK_MONOTONIC)", "coarse (CLOCK_MONOTONIC_COARSE)"};
    for (int c = 0; c < 2; ++c) {
        volatile long sink = 0; /* the reads are kept */
        for (long r = 0; r < rounds; ++r) {
            struct timespec ts;
            double t0 = sa_now();
            for (int i = 0; i < 100000; ++i) {
                clock_gettime(id[c], &ts);
                sink += ts.tv_nsec;
            }
            per[r] = (sa_now() - t0) / 100000 * 1e9;
        }
        qsort(per, (size_t)rounds, sizeof *per, sa_by_value);
        struct timespec res = {0, 0};
        clock_getres(id[c], &res);
        printf("%s: %.1f ns a read, tick %.9f s\n", name[c], per[rounds / 2],
               (double)res.tv_sec + 1e-9 * (double)res.tv_nsec);
    }
    return 0;
}

/* The loop mode (see the top). */
static int run_loop(const hp_layout *L0, int level, const char *backend, long cycles)
{
    hp_settings st;
    hp_settings_default(&st);
    st.level = (hp_level)level;
    st.use_rate_limits = 1;
    /* One start for every backend, as realtime solves: the profile compares one solve's
     * work (SLSQP's restarts, on by default, repeat it on plans that bind). */
    st.restarts = 0;
    if (hp_backend_parse(backend, &st.backend) != HP_OK || cycles < 1) return usage();
    hp_layout L;
    sa_loop_layout(L0, &L);
    hp_planner *p = NULL;
    hp_diag d = {{0}};
    if (hp_planner_create(&L, &st, &p, &d) != HP_OK) {
        fprintf(stderr, "headplan-bench-count: %s\n", d.text);
        return 65;
    }
    int count[HP_STATUS_COUNT_] = {0};
    double tgt[6] = {0};
    for (long j = 0; j < cycles; ++j) {
        if (j % 300 == 0)
            for (int i = 0; i < 6; ++i)
                tgt[i] = (2.0 * sa_urand() - 1.0) * (i < 3 ? 3e-3 : 2.0 * PI / 180);
        hp_result res;
        if (hp_plan(p, tgt, &res) != HP_OK) break;
        count[res.status]++;
        double P[HP_MAX_BLADDERS];
        for (int k = 0; k < res.n; ++k)
            P[k] = res.bladders[k].pressure + 3.0 * (2.0 * sa_urand() - 1.0);
        if (hp_planner_set_measured(p, P, NULL) != HP_OK) break;
    }
    printf("cycles %ld;", cycles);
    for (int i = 0; i < HP_STATUS_COUNT_; ++i)
        if (count[i]) printf(" %s %d", hp_status_name((hp_status)i), count[i]);
    printf("\n");
    hp_planner_destroy(p);
    return 0;
}

/* One answer whole, exactly (the bits mode). */
static void print_bits(int level, int trace, int feed, long j, int m, const hp_result *r)
{
    printf("L%d T%d F%d %ld %d %s", level, trace, feed, j, m, hp_status_name(r->status));
    for (int i = 0; i < 6; ++i) printf(" %a", r->achieved[i]);
    printf(" %a", r->pose_error);
    for (int k = 0; k < r->n; ++k)
        printf(" %a %a %a %u", r->bladders[k].pressure, r->bladders[k].ri, r->bladders[k].ro,
               r->bladders[k].binding);
    printf("\n");
}

/* The tail mode (see the top); bits: the bits mode's line a plan instead. */
static int run_tail(const hp_layout *L0, int level, int trace, int feed, long cycles, int bits)
{
    hp_planner *p[2];
    int rc = sa_loop_planners(L0, level, 2, "headplan-bench-count", p);
    sa_loop_walk w;
    sa_loop_walk_start(&w, trace);
    for (long j = 0; j < cycles && rc == 0; ++j) {
        double xi[6];
        sa_loop_walk_at(&w, j, xi);
        for (int m = 0; m < 2 && rc == 0; ++m) {
            hp_result res;
            if (hp_plan(p[m], xi, &res) != HP_OK) {
                rc = 70;
                break;
            }
            int rate = 0;
            for (int k = 0; k < res.n; ++k)
                rate |= (res.bladders[k].binding & (HP_BIND_RATE_DOWN | HP_BIND_RATE_UP)) != 0;
            if (bits) print_bits(level, trace, feed, j, m, &res);
            else printf("%ld %d %s %d\n", j, m, hp_status_name(res.status), rate);
            if (m == 1 && feed) {
                double P[HP_MAX_BLADDERS];
                sa_loop_readings(&res, &w.noise, P);
                if (hp_planner_set_measured(p[m], P, NULL) != HP_OK) rc = 70;
            }
        }
    }
    for (int m = 0; m < 2; ++m) hp_planner_destroy(p[m]);
    return rc;
}

int main(int argc, char **argv)
{
    if (argc == 3 && strcmp(argv[1], "clocks") == 0) return time_clocks(atol(argv[2]));
    if (argc != 7 && argc != 6 && argc != 4) return usage();
    const char *mode = argv[2];
    if (strcmp(mode, "tail") == 0 && argc == 7) {
        static hp_scene ts;
        hp_diag td = {{0}};
        long lv = sa_whole(argv[3]), feed = sa_whole(argv[5]), n = sa_whole(argv[6]);
        int tr = sa_loop_trace_of(argv[4]);
        if (lv < 0 || lv > 2 || tr < 0 || (feed != 0 && feed != 1) || n < 1) return usage();
        if (hp_scene_load(argv[1], &ts, &td) != HP_OK) {
            fprintf(stderr, "headplan-bench-count: %s\n", td.text);
            return 66;
        }
        return run_tail(&ts.layout, (int)lv, tr, (int)feed, n, 0);
    }
    if (argc == 4 && strcmp(mode, "bits") == 0) {
        static hp_scene bs;
        hp_diag bd = {{0}};
        long n = sa_whole(argv[3]);
        if (n < 1) return usage();
        if (hp_scene_load(argv[1], &bs, &bd) != HP_OK) {
            fprintf(stderr, "headplan-bench-count: %s\n", bd.text);
            return 66;
        }
        for (int lv = 0; lv < 3; ++lv)
            for (int tr = 0; tr < 3; ++tr)
                for (int feed = 0; feed < 2; ++feed) {
                    int rc = run_tail(&bs.layout, lv, tr, feed, n, 1);
                    if (rc) return rc;
                }
        return 0;
    }
    if (strcmp(mode, "loop") == 0 && argc == 6) {
        static hp_scene ls;
        hp_diag ld = {{0}};
        if (hp_scene_load(argv[1], &ls, &ld) != HP_OK) {
            fprintf(stderr, "headplan-bench-count: %s\n", ld.text);
            return 66;
        }
        int lv = atoi(argv[3]);
        return lv < 0 || lv > 2 ? usage() : run_loop(&ls.layout, lv, argv[4], atol(argv[5]));
    }
    int cold = strcmp(mode, "cold") == 0, timed = strcmp(mode, "time") == 0,
        answers = strcmp(mode, "answers") == 0, trace = strcmp(mode, "trace") == 0;
    if (!(cold || timed || answers || trace) || argc != (trace ? 6 : 7)) return usage();
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
    st.warm_start = trace || (answers && atoi(argv[6]) != 0);
    st.max_iter = 3000;
    st.max_time = 5.0;
    hp_planner *p = NULL;
    if (hp_planner_create(&sc.layout, &st, &p, &d) != HP_OK) {
        fprintf(stderr, "headplan-bench-count: %s\n", d.text);
        return 65;
    }
    if (timed || answers) {
        double mm = atof(argv[4]), deg = atof(argv[5]);
        int rc = timed ? time_plans(p, mm, deg, atol(argv[6]))
                       : print_answers(p, mm, deg, st.warm_start);
        hp_planner_destroy(p);
        return rc;
    }
    int count[HP_STATUS_COUNT_] = {0};
    long steps = 0, plans = 0;
    if (cold) {
        double mm = atof(argv[4]), deg = atof(argv[5]), t[N_TARGETS][6];
        long reps = atol(argv[6]);
        sa_targets(mm, deg, N_TARGETS, t);
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
