/* A time budget that must expire (max_time 1 ns: the clock has moved past it by the first
 * time the realtime backend reads it) on plans whose solver runs: targets beyond reach and
 * chains of large steps under rate limits, at the plane and surface levels. No timing is
 * asserted; what is asserted:
 * - the status is TIME_LIMIT (the budget stopped the solve), never a solver error;
 * - the output is safe: every pressure inside [p_min, p_max] and inside its rate window,
 *   and the pressures' forward model (hp_iab_fk, the volume law, hp_contact_fk from the
 *   nominal pose) gives back the pose the result states as achieved;
 * - the work after the budget ran out is bounded: counted by the backend's test counts
 *   (contact evaluations and QPs begun after the deadline), at most RT_LATE_MAX a solve
 *   (the evaluations that find the feasible point to stop at: the previous answer, else the
 *   nominal pose). Before the clock was read inside the line search, the restoration and its
 *   bisection, a solve stopped by time went on through all three (tens of evaluations). */
#include "support/test_util.h"
#include "support/layout_fixture.h"
#include "planner/backend_testing.h"
#include "planner/clock.h"

#define RT_LATE_MAX 3

static const double beyond[][6] = {
    {30, 0, 0, 0, 0, 0},   {0, -25, 0, 0, 0, 0}, {0, 0, 20, 10, 0, 0},
    {12, 8, -9, 6, -7, 5}, {0, 0, 0, 0, 0, 20},  {-20, 15, 0, 0, 8, 0},
};
#define N_BEYOND (int)(sizeof beyond / sizeof beyond[0])

/* A realtime planner of this level, rate limit and budget that has planned the zero
 * correction (answered by the direct chain, REACHED); P0 gets its pressures, the first
 * previous pressures (the rate windows' centres) of every walk here. */
static hp_planner *budget_planner(hp_level level, double rate, double max_time, double *P0)
{
    hp_settings s;
    hp_settings_default(&s);
    s.backend = HP_BACKEND_REALTIME;
    s.level = level;
    s.max_time = max_time;
    hp_planner *p = NULL;
    assert_int_equal(lf_planner_settings(&s, rate, &p), HP_OK);
    const double zero[6] = {0};
    hp_result r0;
    assert_int_equal(hp_plan(p, zero, &r0), HP_OK);
    assert_int_equal(r0.status, HP_STATUS_REACHED);
    for (int k = 0; k < r0.n; ++k) P0[k] = r0.bladders[k].pressure;
    return p;
}

/* The safety checks of one result; P0 the previous pressures (the rate windows' centres). */
static void check_safe(const hp_planner *p, const hp_result *r, const double *P0, double rate,
                       const char *what)
{
    const hp_layout *L = hp_planner_layout(p);
    for (int k = 0; k < r->n; ++k) {
        const hp_bladder *B = &L->bladders[k];
        double P = r->bladders[k].pressure;
        if (!(P >= B->p_min && P <= B->p_max && P >= P0[k] - rate && P <= P0[k] + rate)) {
            print_error("%s: bladder %d pressure %.17g outside its limits or rate window\n", what,
                        k, P);
            fail();
        }
    }
    double xi[6];
    assert_int_equal(lf_round_trip(L, hp_planner_level(p), r, xi), HP_OK);
    for (int i = 0; i < 6; ++i) {
        /* 1e-7 m and 1e-6 rad: far above the forward fit's convergence (~1e-12), far below
         * anything a head can feel. */
        double tol = i < 3 ? 1e-7 : 1e-6;
        if (!(fabs(xi[i] - r->achieved[i]) <= tol)) {
            print_error("%s: component %d: forward model %.12g, stated achieved %.12g\n", what, i,
                        xi[i], r->achieved[i]);
            fail();
        }
    }
}

static void test_expired_budget(void **state)
{
    (void)state;
    const hp_level levels[] = {HP_LEVEL_PLANE, HP_LEVEL_SURFACE};
    long solves = 0, late = 0, stopped = 0;
    for (int l = 0; l < 2; ++l) {
        for (int rl = 0; rl < 2; ++rl) {
            double rate = rl ? 400.0 : INFINITY;
            /* The previous pressures: the nominal ones, then each result's own (a stopped
             * solve's iterate, or the safe output, which is the previous answer). */
            double P0[HP_MAX_BLADDERS];
            hp_planner *p = budget_planner(levels[l], rate, 1e-9, P0);
            uint64_t seed = 0xdead + (uint64_t)(2 * l + rl);
            for (int t = 0; t < 3 * N_BEYOND; ++t) {
                double d[6], mm_deg[6];
                for (int i = 0; i < 6; ++i)
                    mm_deg[i] = beyond[t % N_BEYOND][i] * (1.0 + 0.2 * lf_uniform(&seed));
                lf_pose(mm_deg, d);
                hp_result r;
                hpi_test_realtime_count(1);
                assert_int_equal(hp_plan(p, d, &r), HP_OK);
                hpi_test_realtime_count(0);
                hp_test_rt_counts c;
                hpi_test_realtime_counts(&c);
                char what[80];
                snprintf(what, sizeof what, "%s rate %g plan %d (%s)", hp_level_name(levels[l]),
                         rate, t, hp_status_name(r.status));
                if (c.solves > 0) {
                    if (r.status != HP_STATUS_TIME_LIMIT) {
                        print_error("%s: the solver ran; want time-limit: %s\n", what,
                                    hp_planner_error(p));
                        fail();
                    }
                    ++stopped;
                }
                check_safe(p, &r, P0, rate, what);
                for (int k = 0; k < r.n; ++k) P0[k] = r.bladders[k].pressure;
                solves += c.solves;
                late += c.late;
                if (c.late > RT_LATE_MAX * c.solves) {
                    print_error("%s: %ld pieces of work begun after the deadline in %ld "
                                "solves\n",
                                what, c.late, c.solves);
                    fail();
                }
            }
            hp_planner_destroy(p);
        }
    }
    print_message("expired budget: %ld plans stopped by time, %ld solves, %ld late pieces "
                  "of work\n",
                  stopped, solves, late);
    assert_true(stopped >= 36); /* the solver ran on most of the 72 plans */
}

/* One walk of test_binding_budget_makes_progress: from the nominal pose toward a held target
 * (rate-limited, test clock, a budget of `budget` readings), at most 40 plans, every answer
 * checked (check_safe) and none the safe output (solver-error: the core refused the
 * backend's answer); readings fed back when fed. Sets *stopped to the plans the budget
 * stopped and returns the plan that reached the target's closest point, or -1. */
static int budget_walk(hp_level level, int fed, int budget, int *stopped)
{
    static const double target_mm_deg[6] = {4, -3, 3, 2, -1.5, 1.5};
    const double rate = 400.0;
    double P0[HP_MAX_BLADDERS], d[6];
    hp_planner *p = budget_planner(level, rate, 1e-6 * budget, P0);
    hpi_test_plan_clock(1e-6);
    hp_result r;
    lf_pose(target_mm_deg, d);
    int done = -1;
    *stopped = 0;
    for (int t = 0; t < 40 && done < 0; ++t) {
        assert_int_equal(hp_plan(p, d, &r), HP_OK);
        char what[96];
        snprintf(what, sizeof what, "%s %s budget %d plan %d (%s)", hp_level_name(level),
                 fed ? "readings" : "answers", budget, t, hp_status_name(r.status));
        check_safe(p, &r, P0, rate, what);
        if (r.status == HP_STATUS_SOLVER_ERROR) { /* the safe output: a refused answer */
            print_error("%s: %s\n", what, hp_planner_error(p));
            fail();
        }
        *stopped += r.status == HP_STATUS_TIME_LIMIT;
        if (r.status == HP_STATUS_REACHED || r.status == HP_STATUS_CLOSEST) done = t;
        for (int k = 0; k < r.n; ++k)
            P0[k] = r.bladders[k].pressure + (fed ? (k % 2 ? 1.0 : -1.0) : 0.0);
        if (fed) assert_int_equal(hp_planner_set_measured(p, P0, NULL), HP_OK);
    }
    hpi_test_plan_clock(0.0);
    hp_planner_destroy(p);
    return done;
}

/* A budget that binds on every plan of a walk to a held target still moves the plan toward
 * it: a solve the clock stops keeps the step its QP paid for (one line-search trial) or the
 * part of it three bisection steps find feasible, so a loop under a tight budget reaches its
 * target over cycles instead of answering from where it started forever (each plan
 * time-limit, the pose never moving: the loop benchmark's step trace at 3 us before). The
 * test clock (hpi_test_plan_clock, which the realtime backend's budget clock follows: every
 * reading 1 us later) makes the budget a count of clock readings, so which plans it stops is
 * the same on every machine and under any tool. Asserted, at the plane and surface levels,
 * rate-limited, with the plans' own answers and with readings fed back: every answer safe
 * (check_safe); with a budget of 2 readings every walk has at least 10 plans stopped by it,
 * and with 2 and 3 readings every walk reaches its target's closest point (status reached or
 * closest) within its 40 plans. */
static void test_binding_budget_makes_progress(void **state)
{
    (void)state;
    const hp_level levels[] = {HP_LEVEL_PLANE, HP_LEVEL_SURFACE};
    static const int budgets[] = {2, 3};
    for (int l = 0; l < 2; ++l)
        for (int fed = 0; fed < 2; ++fed)
            for (size_t b = 0; b < sizeof budgets / sizeof budgets[0]; ++b) {
                int stopped;
                int done = budget_walk(levels[l], fed, budgets[b], &stopped);
                print_message("%s, %s, budget %2d readings: %2d plans stopped by it, %s at "
                              "plan %d\n",
                              hp_level_name(levels[l]), fed ? "readings" : "answers", budgets[b],
                              stopped, done >= 0 ? "closest point" : "not reached", done);
                if (done < 0) {
                    print_error("%s budget %d (%s): the walk did not reach its target in 40 "
                                "plans\n",
                                hp_level_name(levels[l]), budgets[b], fed ? "readings" : "answers");
                    fail();
                }
                if (budgets[b] == 2 && stopped < 10) {
                    print_error("%s budget 2 (%s): %d plans stopped; want the budget to bind\n",
                                hp_level_name(levels[l]), fed ? "readings" : "answers", stopped);
                    fail();
                }
            }
}

/* A stopped solve whose point reached is outside a curved limit keeps the interpolated step
 * fraction when that point holds, which it nearly always does: the bisection below it, and
 * its answer's radii (those of its last feasible point, or of its anchor when it kept
 * nothing, not evaluated again at the answer), are then rarely walked. The backend's test
 * hook (hpi_test_realtime_late_path) sends the walks of test_binding_budget_makes_progress
 * (budget 2 readings) down each: the bisection at once, and the anchor itself (a bisection
 * stopped before its first step). Asserted: every answer safe and its forward model giving
 * the stated pose (check_safe); bisections that kept part of the step, and answers at the
 * anchor, among them (the backend's test counts); none the safe output. An answer inside
 * the segment carrying the anchor's radii fails the forward model's check (a mutation
 * tried). */
static void test_late_bisection_answers_hold(void **state)
{
    (void)state;
    const hp_level levels[] = {HP_LEVEL_PLANE, HP_LEVEL_SURFACE};
    const int paths[] = {HP_TEST_LATE_BISECT, HP_TEST_LATE_ANCHOR};
    long kept = 0, anchor = 0;
    for (int m = 0; m < 2; ++m) {
        hpi_test_realtime_late_path(paths[m]);
        for (int l = 0; l < 2; ++l)
            for (int fed = 0; fed < 2; ++fed) {
                int stopped;
                hp_test_rt_counts c;
                hpi_test_realtime_count(1);
                (void)budget_walk(levels[l], fed, 2, &stopped);
                hpi_test_realtime_count(0);
                hpi_test_realtime_counts(&c);
                kept += c.bisect_kept;
                anchor += c.bisect_anchor;
            }
    }
    hpi_test_realtime_late_path(HP_TEST_LATE_AS_BUILT);
    print_message("late bisections: %ld kept part of the step, %ld answered at the anchor\n", kept,
                  anchor);
    assert_true(kept > 0);
    assert_true(anchor > 0);
}

/* An SQP step after the first begins only while a quarter of the longest step so far still
 * fits in the budget (RT_STEP_FIT in the backend), so the step in flight at a deadline is
 * one predicted to end at most three quarters of a step late. On the test clock (every
 * reading 1 us later) a solve reads its start at T and its first step's start at T + 1;
 * when that step's full step is taken the next reading is the second step's start, T + 2,
 * the longest step so far 1 us: the second step needs 2.25 us of budget (when the full step
 * is refused, the line search's own readings make every later one past 2.3 us). Each target
 * beyond reach is planned by a fresh planner from the nominal pose under budgets of 1.9,
 * 2.1 and 2.3 us (the backend's test counters stay off: they read the clock too). Asserted
 * per level: some answers differ between 2.1 and 2.3 us (a second step under 2.3 only),
 * and those under 2.1 are the same bits as under 1.9, where the clock itself is past the
 * deadline at T + 2 (a predicted stop ends as a stop by time does); every answer safe. A
 * backend reading only whether the clock is past the deadline begins the second step under
 * 2.1 too, one predicting more than 0.3 of the step under neither. */
static void test_step_begins_only_if_it_fits(void **state)
{
    (void)state;
    const hp_level levels[] = {HP_LEVEL_PLANE, HP_LEVEL_SURFACE};
    static const double budgets[] = {1.9e-6, 2.1e-6, 2.3e-6};
    for (int l = 0; l < 2; ++l) {
        int more = 0;
        for (int t = 0; t < N_BEYOND; ++t) {
            double P[3][HP_MAX_BLADDERS];
            for (int b = 0; b < 3; ++b) {
                double d[6], P0[HP_MAX_BLADDERS];
                hp_planner *p = budget_planner(levels[l], INFINITY, budgets[b], P0);
                hp_result r;
                lf_pose(beyond[t], d);
                hpi_test_plan_clock(1e-6);
                assert_int_equal(hp_plan(p, d, &r), HP_OK);
                hpi_test_plan_clock(0.0);
                char what[80];
                snprintf(what, sizeof what, "%s budget %g s target %d (%s)",
                         hp_level_name(levels[l]), budgets[b], t, hp_status_name(r.status));
                check_safe(p, &r, P0, INFINITY, what);
                for (int k = 0; k < r.n; ++k) P[b][k] = r.bladders[k].pressure;
                if (b == 2 && memcmp(P[1], P[2], (size_t)r.n * sizeof P[0][0]) != 0) {
                    ++more;
                    if (memcmp(P[0], P[1], (size_t)r.n * sizeof P[0][0]) != 0) {
                        print_error("%s: a second step under 2.3 us, and the answer under "
                                    "2.1 us differs from 1.9 us's\n",
                                    what);
                        fail();
                    }
                }
                hp_planner_destroy(p);
            }
        }
        print_message("%s: %d of %d targets took a second step under 2.3 us and not under 2.1\n",
                      hp_level_name(levels[l]), more, N_BEYOND);
        assert_true(more > 0);
    }
}

/* Tiny budgets on the real clock (0.3, 1 and 3 us), every contact level, rate-limited,
 * walks between far targets with the plans' own answers and with noisy readings fed back:
 * which plans the clock stops, and where (before a QP, in the line search, at a point
 * outside a curved limit that the step fraction or the bisection then pulls back), depends
 * on the machine and its load, so only what holds for every such stop is asserted: every
 * answer safe (check_safe), never a call error. On any machine most of these plans stop
 * (a binding surface plan's solve is several microseconds), and under the sanitizers all
 * do: the paths after a deadline are run either way. */
static void test_tiny_real_budgets_stay_safe(void **state)
{
    (void)state;
    hpi_test_plan_clock(0.0); /* the real clock, even after a failed test left the test one on */
    hpi_test_realtime_late_path(HP_TEST_LATE_AS_BUILT);
    const hp_level levels[] = {HP_LEVEL_LINEAR, HP_LEVEL_PLANE, HP_LEVEL_SURFACE};
    static const double budgets[] = {3e-7, 1e-6, 3e-6};
    const double rate = 400.0;
    long plans = 0, stopped = 0;
    for (int l = 0; l < 3; ++l)
        for (size_t b = 0; b < sizeof budgets / sizeof budgets[0]; ++b)
            for (int fed = 0; fed < 2; ++fed) {
                double P0[HP_MAX_BLADDERS], d[6], mm_deg[6] = {0};
                hp_planner *p = budget_planner(levels[l], rate, budgets[b], P0);
                uint64_t seed = 0xbee5 + (uint64_t)(6 * l + 2 * (int)b + fed);
                hp_result r;
                for (int t = 0; t < 60; ++t) {
                    if (t % 15 == 0) /* a new target, held for 15 plans */
                        for (int i = 0; i < 6; ++i)
                            mm_deg[i] = (i < 3 ? 6.0 : 4.0) * lf_uniform(&seed);
                    lf_pose(mm_deg, d);
                    assert_int_equal(hp_plan(p, d, &r), HP_OK);
                    char what[96];
                    snprintf(what, sizeof what, "%s budget %g s %s plan %d (%s)",
                             hp_level_name(levels[l]), budgets[b], fed ? "readings" : "answers", t,
                             hp_status_name(r.status));
                    check_safe(p, &r, P0, rate, what);
                    ++plans;
                    stopped += r.status == HP_STATUS_TIME_LIMIT;
                    for (int k = 0; k < r.n; ++k)
                        P0[k] = r.bladders[k].pressure + (fed ? 3.0 * lf_uniform(&seed) : 0.0);
                    if (fed) assert_int_equal(hp_planner_set_measured(p, P0, NULL), HP_OK);
                    /* a reading a hair beyond a limit is clamped onto it: the windows' centre */
                    const hp_layout *L = hp_planner_layout(p);
                    for (int k = 0; k < r.n; ++k)
                        P0[k] = fmin(fmax(P0[k], L->bladders[k].p_min), L->bladders[k].p_max);
                }
                hp_planner_destroy(p);
            }
    print_message("tiny real budgets: %ld plans, %ld stopped by the clock (machine-dependent), "
                  "every answer safe\n",
                  plans, stopped);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_expired_budget),
        cmocka_unit_test(test_binding_budget_makes_progress),
        cmocka_unit_test(test_late_bisection_answers_hold),
        cmocka_unit_test(test_step_begins_only_if_it_fits),
        cmocka_unit_test(test_tiny_real_budgets_stay_safe),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
