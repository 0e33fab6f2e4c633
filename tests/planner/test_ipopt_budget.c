/* The Ipopt backend's time budget (max_time) is this plan's, read on the planner's one clock
 * (planner/clock.c: CLOCK_MONOTONIC), from the plan's start. It was read on clock(), the
 * process's CPU time, which counts every thread: under `headplan batch --jobs N` a plan's
 * budget ran out up to N times early. No timing is asserted: the test clock
 * (hpi_test_plan_clock) moves a fixed step at every reading, so a budget of B s with a step
 * of S s lasts a fixed number of readings, whatever the machine's load.
 * - A plan whose solver runs (a target beyond reach) stops with TIME_LIMIT on that clock and
 *   a safe output (pressures inside their limits);
 * - the next plan, with the counter run on, stops after the same number of iterations: the
 *   budget starts at each plan's start, not at the first;
 * - back on the real clock, with the same budget (60 s: no machine is that slow), the same
 *   plan is CLOSEST (it was the budget that stopped it). */
#include "support/test_util.h"
#include "support/layout_fixture.h"
#include "planner/clock.h"

static void check_limits(const hp_planner *p, const hp_result *r)
{
    const hp_layout *L = hp_planner_layout(p);
    for (int k = 0; k < r->n; ++k)
        assert_true(r->bladders[k].pressure >= L->bladders[k].p_min &&
                    r->bladders[k].pressure <= L->bladders[k].p_max);
}

static void test_budget_per_plan(void **state)
{
    (void)state;
    /* 60 s of budget (lf_planner_on), 18 s a reading: the plan's start and three more
     * readings fit, the fourth is past it. Ipopt needs more than three iterations for this
     * target. */
    hp_layout L;
    assert_int_equal(lf_layout(&L), HP_OK);
    hp_planner *p = lf_planner_on(&L, HP_BACKEND_IPOPT, HP_LEVEL_PLANE);
    assert_non_null(p);
    const double mm_deg[6] = {30, 0, 0, 0, 0, 0};
    double d[6];
    lf_pose(mm_deg, d);
    hp_result r[2];
    hpi_test_plan_clock(18.0);
    for (int t = 0; t < 2; ++t) {
        hp_planner_reset(p);
        assert_int_equal(hp_plan(p, d, &r[t]), HP_OK);
        print_message("plan %d on the test clock: %s after %d iterations\n", t,
                      hp_status_name(r[t].status), r[t].iterations);
        assert_int_equal(r[t].status, HP_STATUS_TIME_LIMIT);
        check_limits(p, &r[t]);
    }
    hpi_test_plan_clock(0.0);
    assert_true(r[0].iterations <= 4);
    assert_int_equal(r[1].iterations, r[0].iterations);
    hp_result c;
    hp_planner_reset(p);
    assert_int_equal(hp_plan(p, d, &c), HP_OK);
    print_message("on the real clock: %s after %d iterations\n", hp_status_name(c.status),
                  c.iterations);
    assert_int_equal(c.status, HP_STATUS_CLOSEST);
    assert_true(c.iterations > r[0].iterations);
    hp_planner_destroy(p);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_budget_per_plan),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
