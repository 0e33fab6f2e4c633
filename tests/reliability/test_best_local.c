/* The best local answer (issue 32): within the clinically relevant range (|t| <= 20 mm, each
 * angle <= 15 deg) the realtime backend's answer is never farther from the desired pose than
 * the best of Ipopt, NLopt SLSQP and the multi-start reference (multistart_ref.h: Ipopt
 * from the nominal pose and from seeded starts) by more than BL_TOL; over the catalogue's
 * layout scenes and seeded generated layouts (sweep_draws.h: ellipsoid and sphere heads,
 * off-centre heads and pivots, soft bladders, rate limits), at the plane and surface levels,
 * cold plans (the rate windows around the nominal pressures).
 *
 * The distance is the planner's objective, the weighted pose error (sw_dist: mm, deg at the
 * default weight). Every backend is asked the same program; an answer counts when it is
 * REACHED, CLOSEST or UNCOMMANDED (confirmed by the planner's forward model).
 *
 * Sizes: the quick size below runs in CI; HP_BEST_LOCAL_SIZE=N multiplies the layouts and
 * targets by N. HP_BEST_LOCAL_BEYOND=1 (or =MM,DEG) draws corrections beyond the clinical
 * range, up to 60 mm and 45 deg per angle (or MM and DEG; the rotation kept below 90 deg
 * about its axis, the translation below 0.95 of the head's smallest semi-axis), and counts
 * how often and by how much each backend is worse than the best answer instead of
 * asserting; HP_BEST_LOCAL_CSV=FILE appends one row per plan (docs/control-loop.md, "The
 * best local answer"; chart: tests/reliability/best_local.gp). The Ipopt and SLSQP compared
 * plan with their default restarts (the reference with one solve a start);
 * HP_BEST_LOCAL_IPOPT_RESTARTS=N gives Ipopt N instead (0: one start, to count how often
 * one start is worse: docs/planner.md, Restarts). test_slsqp_restarts and
 * test_ipopt_restarts check the restarts on programs where one start ends at a local
 * minimum. */
#include "multistart_ref.h"

#include <stdlib.h>
#include <string.h>

#define BL_SEED 0xbe57100cu
#if defined(__SANITIZE_ADDRESS__)
#define BL_LAYOUTS 2
#define BL_TARGETS 2
#define BL_SCENE_TARGETS 1
#define BL_STARTS 4
#else
#define BL_LAYOUTS 8
#define BL_TARGETS 4
#define BL_SCENE_TARGETS 3
#define BL_STARTS 8
#endif
/* Realtime's distance may exceed the best answer's by this much (mm/deg). The backends stop
 * within their tolerances (realtime 1e-9, Ipopt 1e-10 mm/deg; SLSQP's answers ~1e-5 short,
 * docs/planner.md) of a local optimum, and the distance moves by at most as much as the
 * pose: 1e-4 is ten times the loosest of them, far below any other local optimum's gap
 * (the sweep's smallest measured: 0.035). */
#define BL_TOL 1e-4

static const hp_level bl_levels[2] = {HP_LEVEL_PLANE, HP_LEVEL_SURFACE};
enum { BL_RT, BL_IPOPT, BL_SLSQP, BL_REF, BL_N };
static const char *const bl_names[BL_N] = {"realtime", "ipopt", "nlopt-slsqp", "multi-start"};

typedef struct bl_tally {
    long plans, answered, closest, rt_none, starts, started;
    long worse[BL_N], none[BL_N]; /* by backend: worse than the best, no answer */
    double worst[BL_N];
} bl_tally;

typedef struct bl_run {
    int beyond;        /* 1: corrections beyond the clinical range, counted, not asserted */
    double tmax, amax; /* the range drawn: translation norm [mm], each angle [deg] */
    FILE *csv;
    bl_tally t[2];
} bl_run;

/* A correction: translation of norm up to tmax mm along a random direction (shortened to
 * 0.95 of the head's smallest semi-axis), each angle uniform within ±amax deg. */
static void bl_target(uint64_t *s, double tmax, double amax, const hp_identifiable *id,
                      double xi[6])
{
    double u[3];
    sw_unit3(s, u);
    double t = fmin(test_rng_uniform(s, 0, tmax) * 1e-3, 0.95 * id->trans_limit);
    for (int i = 0; i < 3; ++i) xi[i] = t * u[i];
    for (int i = 3; i < 6; ++i) xi[i] = test_rng_uniform(s, -amax, amax) * PI / 180.0;
    /* Keep the rotation angle about its own axis below 90 deg (identifiable). */
    while (!(hp_pose_rotation_angle(xi) < 0.97 * PI / 2))
        for (int i = 3; i < 6; ++i) xi[i] *= 0.9;
}

static double bl_dist(const hp_result *r) { return ms_answer(r) ? sw_dist(r) : INFINITY; }

/* Plans xi with every backend and the reference; tallies realtime against the best. */
static void bl_compare(hp_planner *const pl[3], ms_ref *ref, const char *what, hp_level level,
                       const double xi[6], uint64_t seed, bl_run *run, bl_tally *t)
{
    hp_result r[BL_N];
    for (int b = 0; b < 3; ++b) {
        hp_planner_reset(pl[b]);
        assert_int_equal(hp_plan(pl[b], xi, &r[b]), HP_OK);
    }
    t->starts += BL_STARTS + 1;
    t->started += ms_ref_best(ref, xi, BL_STARTS, seed, &r[BL_REF]);
    double d[BL_N], best = INFINITY;
    for (int b = 0; b < BL_N; ++b) best = fmin(best, d[b] = bl_dist(&r[b]));
    t->plans++;
    if (run->csv) {
        fprintf(run->csv, "%s,%s,%.6f,%.6f", what, hp_level_name(level),
                sqrt(xi[0] * xi[0] + xi[1] * xi[1] + xi[2] * xi[2]) * 1e3,
                fmax(fabs(xi[3]), fmax(fabs(xi[4]), fabs(xi[5]))) * 180 / PI);
        for (int b = 0; b < BL_N; ++b)
            fprintf(run->csv, ",%s,%.9g", hp_status_name(r[b].status), d[b]);
        fprintf(run->csv, ",%.9g\n", best);
    }
    if (!isfinite(best)) return;
    t->answered++;
    t->closest += r[BL_RT].status == HP_STATUS_CLOSEST;
    for (int b = 0; b < BL_N; ++b) {
        if (!isfinite(d[b])) {
            t->none[b]++;
            continue;
        }
        t->worst[b] = fmax(t->worst[b], d[b] - best);
        t->worse[b] += d[b] - best > BL_TOL;
    }
    if (!(d[BL_RT] - best <= BL_TOL) || !(d[BL_SLSQP] - best <= BL_TOL))
        print_message("%s %s %s: realtime %.9g (%s), ipopt %.9g, slsqp %.9g (%s), multi-start "
                      "%.9g at %.3f %.3f %.3f mm %.3f %.3f %.3f deg\n",
                      d[BL_RT] - best <= BL_TOL ? "SLSQP" : "WORSE", what, hp_level_name(level),
                      d[BL_RT], hp_status_name(r[BL_RT].status), d[BL_IPOPT], d[BL_SLSQP],
                      hp_status_name(r[BL_SLSQP].status), d[BL_REF], xi[0] * 1e3, xi[1] * 1e3,
                      xi[2] * 1e3, xi[3] * 180 / PI, xi[4] * 180 / PI, xi[5] * 180 / PI);
}

/* A planner of backend b as ms_planner makes it, with `restarts` further starts. */
static hp_planner *bl_planner(const hp_layout *L, hp_backend b, hp_level level, int restarts)
{
    hp_settings st;
    hp_settings_default(&st);
    st.backend = b;
    st.level = level;
    st.warm_start = 1;
    st.max_time = 60.0;
    if (b == HP_BACKEND_IPOPT) st.tolerance = 1e-10;
    st.restarts = restarts;
    hp_planner *p = NULL;
    assert_int_equal(hp_planner_create(L, &st, &p, NULL), HP_OK);
    return p;
}

/* HP_BEST_LOCAL_IPOPT_RESTARTS=N (0..64): the compared Ipopt's restarts (default: the
 * library's, HP_DEFAULT_RESTARTS), to count how often one start is worse (N = 0). */
static int bl_ipopt_restarts(void)
{
    const char *e = getenv("HP_BEST_LOCAL_IPOPT_RESTARTS");
    if (!e) return HP_DEFAULT_RESTARTS;
    char *end;
    long n = strtol(e, &end, 10);
    if (*e == '\0' || *end != '\0' || n < 0 || n > 64) {
        print_error("HP_BEST_LOCAL_IPOPT_RESTARTS: an integer in 0..64, got '%s'\n", e);
        fail();
    }
    return (int)n;
}

static void bl_layout(const hp_layout *L, const char *what, uint64_t *s, int n, bl_run *run)
{
    hp_identifiable id;
    assert_int_equal(hp_layout_identify(L, &id), HP_OK);
    for (int l = 0; l < 2; ++l) {
        hp_planner *pl[3] = {ms_planner(L, HP_BACKEND_REALTIME, bl_levels[l]),
                             bl_planner(L, HP_BACKEND_IPOPT, bl_levels[l], bl_ipopt_restarts()),
                             ms_planner(L, HP_BACKEND_NLOPT_SLSQP, bl_levels[l])};
        ms_ref ref;
        ms_ref_create(&ref, L, bl_levels[l]);
        for (int j = 0; j < n; ++j) {
            double xi[6];
            bl_target(s, run->tmax, run->amax, &id, xi);
            bl_compare(pl, &ref, what, bl_levels[l], xi, test_rng_next(s), run, &run->t[l]);
        }
        ms_ref_destroy(&ref);
        for (int b = 0; b < 3; ++b) hp_planner_destroy(pl[b]);
    }
}

static int bl_size(void)
{
    const char *e = getenv("HP_BEST_LOCAL_SIZE");
    int n = e ? atoi(e) : 1;
    return n > 0 ? n : 1;
}

static void bl_report(const char *name, const bl_tally *t)
{
    print_message("%s: %ld plans, %ld with an answer (realtime closest %ld); multi-start: %ld "
                  "of %ld starts answered\n",
                  name, t->plans, t->answered, t->closest, t->started, t->starts);
    for (int b = 0; b < BL_N; ++b)
        print_message("  %-12s worse than the best by more than %g: %ld, no answer: %ld, "
                      "largest gap %.3g\n",
                      bl_names[b], BL_TOL, t->worse[b], t->none[b], t->worst[b]);
}

static void bl_assert(const bl_run *run)
{
    if (run->beyond) return; /* counted and charted, not asserted */
    for (int l = 0; l < 2; ++l) {
        assert_true(run->t[l].answered > 0);
        assert_int_equal(run->t[l].worse[BL_RT], 0);
        assert_int_equal(run->t[l].none[BL_RT], 0);
    }
}

static void bl_open(bl_run *run)
{
    memset(run, 0, sizeof *run);
    run->tmax = 20.0; /* the clinically relevant range */
    run->amax = 15.0;
    const char *bey = getenv("HP_BEST_LOCAL_BEYOND");
    if (bey) {
        char end;
        run->beyond = 1;
        run->tmax = 60.0;
        run->amax = 45.0;
        if (strcmp(bey, "1") != 0 &&
            (sscanf(bey, "%lf,%lf%c", &run->tmax, &run->amax, &end) != 2 ||
             !(run->tmax > 0 && run->tmax <= 100) || !(run->amax > 0 && run->amax < 90))) {
            print_error("HP_BEST_LOCAL_BEYOND: 1 or TRANSLATION_MM,ANGLE_DEG (0 < mm <= 100, "
                        "0 < deg < 90), got '%s'\n",
                        bey);
            fail();
        }
    }
    const char *path = getenv("HP_BEST_LOCAL_CSV");
    if (!path) return;
    /* Both tests of one run write to the file: the first starts it afresh, the second
     * appends (a second run never doubles the rows). */
    static int started;
    run->csv = fopen(path, started ? "a" : "w");
    started = 1;
    if (!run->csv) {
        print_error("HP_BEST_LOCAL_CSV: cannot open %s\n", path);
        fail();
    }
    if (fseek(run->csv, 0, SEEK_END) == 0 && ftell(run->csv) == 0) {
        fprintf(run->csv, "case,level,t_mm,angle_deg");
        for (int b = 0; b < BL_N; ++b)
            fprintf(run->csv, ",%s_status,%s_dist", bl_names[b], bl_names[b]);
        fprintf(run->csv, ",best_dist\n");
    }
}

static void bl_close(bl_run *run)
{
    if (run->csv) assert_int_equal(fclose(run->csv), 0);
}

static void test_catalogue(void **st)
{
    (void)st;
    uint64_t s = BL_SEED ^ 0xca7u;
    bl_run run;
    bl_open(&run);
    for (int i = 0; i < SW_CATALOGUE; ++i) {
        hp_scene *sc = sw_scene(sw_catalogue[i]);
        bl_layout(&sc->layout, sw_catalogue[i], &s, BL_SCENE_TARGETS * bl_size(), &run);
        free(sc);
    }
    bl_close(&run);
    bl_report("catalogue, plane", &run.t[0]);
    bl_report("catalogue, surface", &run.t[1]);
    bl_assert(&run);
}

static void test_generated_layouts(void **st)
{
    (void)st;
    uint64_t s = BL_SEED;
    bl_run run;
    bl_open(&run);
    for (int i = 0; i < BL_LAYOUTS * bl_size(); ++i) {
        hp_layout L;
        char kind[64], what[96];
        if (sw_layout(&s, &L, kind, sizeof kind) != HP_OK) continue;
        snprintf(what, sizeof what, "layout %d (%s)", i, kind);
        bl_layout(&L, what, &s, BL_TARGETS, &run);
    }
    bl_close(&run);
    bl_report("generated, plane", &run.t[0]);
    bl_report("generated, surface", &run.t[1]);
    bl_assert(&run);
}

typedef struct bl_case {
    int layout, target;
    hp_level level;
} bl_case;

/* Backend b's restarts (hp_settings.restarts) on programs of test_sweep.c's generated sweep
 * where b's one-start answer is a local minimum: with its default restarts b's answer must
 * be the multi-start reference's to BL_TOL; with restarts = 0 it must be the local minimum,
 * farther by more than 0.01, which keeps the comparison able to fail. */
static void bl_restarts(hp_backend b, const bl_case *cases, int n)
{
    for (int c = 0; c < n; ++c) {
        hp_layout L;
        char kind[64];
        double xi[6];
        sw_replay(cases[c].layout, cases[c].target, &L, kind, sizeof kind, xi);
        ms_ref ref;
        ms_ref_create(&ref, &L, cases[c].level);
        hp_result best, a, one;
        /* The full reference on every build: three plans (with the sanitizers' 4 starts
         * layout 12's better optimum was not found). */
        ms_ref_best(&ref, xi, 8, BL_SEED + (uint64_t)c, &best);
        assert_int_equal(best.status, HP_STATUS_CLOSEST);
        hp_planner *p = bl_planner(&L, b, cases[c].level, HP_DEFAULT_RESTARTS);
        hp_planner *p0 = bl_planner(&L, b, cases[c].level, 0);
        assert_int_equal(hp_plan(p, xi, &a), HP_OK);
        assert_int_equal(hp_plan(p0, xi, &one), HP_OK);
        print_message("layout %d target %d %s (%s): %s %.9g (%s), without restarts %.9g "
                      "(%s), multi-start %.9g\n",
                      cases[c].layout, cases[c].target, hp_level_name(cases[c].level), kind,
                      hp_backend_name(b), bl_dist(&a), hp_status_name(a.status), bl_dist(&one),
                      hp_status_name(one.status), sw_dist(&best));
        assert_int_equal(one.status, HP_STATUS_CLOSEST);
        assert_true(sw_dist(&one) > sw_dist(&best) + 0.01); /* the local minimum, without */
        assert_int_equal(a.status, HP_STATUS_CLOSEST);
        assert_true(sw_dist(&a) <= sw_dist(&best) + BL_TOL);
        /* Its note says it is a local optimum only without restarts. */
        assert_null(strstr(hp_planner_note(p), "a local optimum"));
        assert_non_null(strstr(hp_planner_note(p0), "a local optimum"));
        hp_planner_destroy(p);
        hp_planner_destroy(p0);
        ms_ref_destroy(&ref);
    }
}

/* NLopt SLSQP: the three programs of test_sweep.c's generated sweep (2400 plans) where
 * SLSQP's cold answer is a local minimum 11-14.5 mm/deg from the closest pose the
 * multi-start reference finds (this file's comparison run over that sweep's draws): layout
 * 12 target 19 at the plane level (rate windows; SLSQP 79.924, reference 78.663), layout 17
 * target 4 at the surface level (soft bladders; 66.750 against 66.591) and layout 33 target
 * 21 at the plane level (rate windows; 36.833 against 36.798): the closest poses are found
 * from the starts 3/4, 7/8 and 1/2 of the way to the target (planner/multistart.c), all
 * among the default restarts. Outside the clinical range (both corrections beyond 20 mm or
 * 15 deg), where the realtime backend also answers the local minimum: counted by the
 * beyond mode, not asserted. */
static void test_slsqp_restarts(void **st)
{
    (void)st;
    static const bl_case cases[3] = {
        {12, 19, HP_LEVEL_PLANE}, {17, 4, HP_LEVEL_SURFACE}, {33, 21, HP_LEVEL_PLANE}};
    bl_restarts(HP_BACKEND_NLOPT_SLSQP, cases, 3);
}

/* Ipopt: layout 12 target 19 at the plane level, where Ipopt's one start ends at 79.588 and
 * the reference (and SLSQP with restarts) at 78.663; the default restarts find it. */
static void test_ipopt_restarts(void **st)
{
    (void)st;
    static const bl_case cases[1] = {{12, 19, HP_LEVEL_PLANE}};
    bl_restarts(HP_BACKEND_IPOPT, cases, 1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_catalogue),
        cmocka_unit_test(test_generated_layouts),
        cmocka_unit_test(test_slsqp_restarts),
        cmocka_unit_test(test_ipopt_restarts),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
