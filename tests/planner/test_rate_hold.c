/* A rate limit so small that every bladder can only hold its pressure (rate_max 1e-297 Pa,
 * i.e. 1e-300 kPa, and 1e-9 Pa): each bladder's radius window is a single point, or a few
 * ulps. Holding the previous pressures meets every limit, so every backend must answer
 * (reached, uncommanded or closest) with pressures within the allowance of the previous
 * ones (for 1e-297 Pa: the same bits), at the pose those pressures hold, and a closest
 * answer names the rate limit as what binds. The previous pressures come from a plan
 * without rate limits at the same level (hp_planner_set_previous), the same moved a few
 * ulps (no radius need have exactly such a pressure), or the planner's own last answer.
 * Pressures that hold no pose at the planner's level are no answer: refused, and held. */
#include "support/test_util.h"
#include "support/layout_fixture.h"
#include "common/units.h"

#define N_CORR 5
#define N_START 4

/* Corrections (mm, deg) planned one after the other against the held pressures: the first
 * is met after the nominal pressures, the others are out of reach of held ones. */
static const double corrections[N_CORR][6] = {
    {0, 0, 0, 0, 0, 0},      {1.0, 0, 0, 0, 0, 0},         {-0.5, 0.8, 0.3, 0.2, 0, -0.3},
    {0, 0, -2.0, 0, 0.5, 0}, {0.2, -0.1, 0.05, 0, 0, 0.1},
};

/* The poses (mm, deg) whose pressures start each chain; start 3 is start 1's pressures
 * moved 5 ulps up (another computation of the same pressures: a kPa round trip moves one). */
static const double starts[N_START][6] = {{0, 0, 0, 0, 0, 0},
                                          {1.5, -1.0, 0.8, 0.5, -0.4, 0.6},
                                          {-2.0, 0.5, -1.0, 0, 0.8, -0.5},
                                          {1.5, -1.0, 0.8, 0.5, -0.4, 0.6}};

/* The pressures of a plan of `mm_deg` without rate limits at `level` (realtime, reached). */
static void pressures_of(hp_level level, const double mm_deg[6], double P[HP_MAX_BLADDERS])
{
    hp_planner *p = NULL;
    assert_int_equal(lf_planner(level, INFINITY, &p), HP_OK);
    double d[6];
    hp_result r;
    lf_pose(mm_deg, d);
    assert_int_equal(hp_plan(p, d, &r), HP_OK);
    assert_int_equal(r.status, HP_STATUS_REACHED);
    for (int k = 0; k < r.n; ++k) P[k] = r.bladders[k].pressure;
    hp_planner_destroy(p);
}

/* A planner on the default layout with every rate_max = rate. */
static hp_planner *limited(hp_backend bk, hp_level level, double rate)
{
    hp_planner *p = NULL;
    assert_int_equal(lf_planner_backend(bk, level, rate, &p), HP_OK);
    return p;
}

#define FAIL(...)                                                                                  \
    do {                                                                                           \
        print_error(__VA_ARGS__);                                                                  \
        print_error("\n");                                                                         \
        return 0;                                                                                  \
    } while (0)

/* Every check of answer r against the held pressures P0 under allowance rate. Prints what
 * fails and returns 0 (so that every plan is checked and a failure shows its extent). */
static int check_answer(const hp_planner *p, const hp_result *r, const double *P0, double rate,
                        const char *what)
{
    const hp_layout *L = hp_planner_layout(p);
    if (!(r->status == HP_STATUS_REACHED || r->status == HP_STATUS_CLOSEST ||
          r->status == HP_STATUS_UNCOMMANDED))
        FAIL("%s: status %s: %s", what, hp_status_name(r->status), hp_planner_error(p));
    unsigned rate_flags = 0;
    for (int k = 0; k < r->n; ++k) {
        /* The window as the planner defines it, [P0 - rate, P0 + rate] in double
         * precision: for 1e-297 Pa both ends are P0 itself. */
        double P = r->bladders[k].pressure;
        if (!(P >= P0[k] - rate && P <= P0[k] + rate))
            FAIL("%s: bladder %d: |dP| %.3g Pa over the allowance %.3g Pa", what, k,
                 fabs(P - P0[k]), rate);
        rate_flags |= r->bladders[k].binding & (HP_BIND_RATE_DOWN | HP_BIND_RATE_UP);
    }
    if (r->status == HP_STATUS_CLOSEST && !rate_flags)
        FAIL("%s: closest, but no bladder names the rate limit", what);
    /* The pose those pressures hold, by a user's own round trip (public FK from the nominal
     * pose): within 1e-6 mm / deg, the planner's HP_IDENT_FK_TOL (1e-7) with room for the
     * fit's own stopping; 1 Pa more or less on one bladder moves it ~1e-3 mm. */
    double xi[6];
    if (lf_round_trip(L, hp_planner_level(p), r, xi) != HP_OK) FAIL("%s: no round trip", what);
    for (int i = 0; i < 6; ++i) {
        double s = i < 3 ? HP_MM_PER_M : HP_DEG_PER_RAD;
        double a = r->achieved[i] * s, b = (r->commanded[i] ? xi[i] : 0.0) * s;
        if (!(fabs(a - b) <= 1e-6))
            FAIL("%s: achieved[%d] %.9g, the pressures hold %.9g", what, i, a, b);
    }
    return 1;
}

/* Every start and correction on one backend, level and rate; adds the plans answered
 * reached and closest to n[0], n[1]. Returns the number of plans that failed a check. */
static int run_chain(hp_backend bk, hp_level level, double rate, int n[2])
{
    hp_planner *p = limited(bk, level, rate);
    int failed = 0;
    for (int st = 0; st < N_START; ++st) {
        double P0[HP_MAX_BLADDERS];
        pressures_of(level, starts[st], P0);
        if (st == 3)
            for (int k = 0; k < hp_planner_layout(p)->n; ++k)
                for (int u = 0; u < 5; ++u) P0[k] = nextafter(P0[k], INFINITY);
        assert_int_equal(hp_planner_set_previous(p, P0), HP_OK);
        for (int c = 0; c < N_CORR; ++c) {
            char what[128];
            snprintf(what, sizeof what, "%s, %s level, rate %.0e Pa, start %d, correction %d",
                     hp_backend_name(bk), hp_level_name(level), rate, st, c);
            double d[6];
            hp_result r;
            lf_pose(corrections[c], d);
            assert_int_equal(hp_plan(p, d, &r), HP_OK);
            if (!check_answer(p, &r, P0, rate, what)) ++failed;
            n[0] += r.status == HP_STATUS_REACHED;
            n[1] += r.status == HP_STATUS_CLOSEST;
            for (int k = 0; k < r.n; ++k) P0[k] = r.bladders[k].pressure;
        }
    }
    hp_planner_destroy(p);
    return failed;
}

static void test_every_backend_holds(void **st)
{
    (void)st;
    const double rates[2] = {1e-297, 1e-9}; /* Pa: 1e-300 kPa, and 1 nPa */
    const hp_level levels[2] = {HP_LEVEL_LINEAR, HP_LEVEL_AUTO};
    int failed = 0;
    for (int b = 0; b < HP_BACKEND_COUNT_; ++b) {
        int n[2] = {0, 0};
        for (int l = 0; l < 2; ++l)
            for (int i = 0; i < 2; ++i) failed += run_chain((hp_backend)b, levels[l], rates[i], n);
        print_message("%s: %d reached, %d closest of %d plans\n", hp_backend_name((hp_backend)b),
                      n[0], n[1], 4 * N_START * N_CORR);
        /* Both labels occur: the held pose meets the first correction after the nominal
         * pressures and misses the others by millimetres. */
        assert_true(n[0] >= 1 && n[1] >= 1);
    }
    assert_int_equal(failed, 0);
}

/* Pressures that hold no pose at the planner's level (the surface level's pressures of a
 * 1.5 mm / 0.5 degree pose, given to a planner at the linear level: its least-squares fit
 * misses the contacts by about 1e-3 mm RMS) cannot be held as an answer: every backend
 * refuses the plan as infeasible-start, says why, and holds them to the bit. */
static void test_pressures_holding_no_pose(void **st)
{
    (void)st;
    double P0[HP_MAX_BLADDERS];
    pressures_of(HP_LEVEL_AUTO, starts[1], P0);
    for (int b = 0; b < HP_BACKEND_COUNT_; ++b) {
        hp_planner *p = limited((hp_backend)b, HP_LEVEL_LINEAR, 1e-297);
        assert_int_equal(hp_planner_set_previous(p, P0), HP_OK);
        double d[6];
        hp_result r;
        lf_pose(corrections[1], d);
        assert_int_equal(hp_plan(p, d, &r), HP_OK);
        assert_int_equal(r.status, HP_STATUS_INFEASIBLE_START);
        assert_non_null(strstr(hp_planner_error(p), "hold no pose at the linear level"));
        for (int k = 0; k < r.n; ++k)
            assert_memory_equal(&r.bladders[k].pressure, &P0[k], sizeof(double));
        hp_planner_destroy(p);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_backend_holds),
        cmocka_unit_test(test_pressures_holding_no_pose),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
