/* The load planner accepts exactly the corrections hp_plan accepts: one outside the
 * identifiable range (a rotation of 90 degrees or more, a translation beyond the head's
 * smallest semi-axis, a component beyond hp_plan's caps) is INVALID_INPUT with hp_plan's
 * own message and the safe output, never an answer. The reference is a kinematic planner
 * built on the same layout. */
#include "support/test_util.h"

#include "support/default_layout.h"
#include "headplan/hp_planner.h"
#include "support/load_fixture.h"

#include <string.h>

#define DEG 0.0174532925199432958

static void test_same_refusals_as_hp_plan(void **state)
{
    (void)state;
    hp_layout L;
    assert_int_equal(default_layout(&L), 0);
    for (int k = 0; k < L.n; ++k) L.bladders[k].stretch_max = 1.6; /* can carry the head */
    assert_int_equal(hp_layout_prepare(&L, NULL), HP_OK);
    hp_load_spec s;
    hp_load_spec_default(&L.head, &s);
    s.law = HP_LOAD_LAW_CAP; /* the default bladders carry the head under the cap law only */
    hp_settings set;
    hp_settings_default(&set);
    set.max_time = 60.0; /* the outcome, not the clock, is asserted */
    set.level = HP_LEVEL_SURFACE;
    hp_diag d = {{0}};
    hp_planner *lp = NULL;
    hp_planner *kp = NULL;
    assert_int_equal(load_create(&L, &s, &set, HP_TIE_LEAST_SQUEEZE, &lp, &d), HP_OK);
    assert_int_equal(hp_planner_create(&L, &set, &kp, &d), HP_OK);
    double lo[HP_MAX_BLADDERS], hi[HP_MAX_BLADDERS];
    assert_int_equal(hp_planner_pressure_bounds(lp, lo, hi), HP_OK);
    /* The smallest semi-axis of the default head is 77.5 mm. */
    const double bad[][6] = {
        {0, 0, 0, 100 * DEG, 0, 0},       /* the adversarial case: REACHED before, rest inf */
        {0, 0, 0, 0, -120 * DEG, 0},      /* CLOSEST before */
        {0, 0, 0, 60 * DEG, 60 * DEG, 0}, /* a turn of 82.8 deg: inside, accepted by both */
        {0.2, 0, 0, 0, 0, 0},             /* SOLVER_ERROR before */
        {0, 0, 0.080, 0, 0, 0},
        {0, 0, 0, 0, 0, 4.0}, /* beyond hp_plan's |rotation| <= pi cap */
        {0, NAN, 0, 0, 0, 0},
    };
    const int nb = (int)(sizeof bad / sizeof bad[0]);
    hp_result ok, r, kr;
    const double zero[6] = {0};
    assert_int_equal(load_plan(lp, zero, &ok, NULL), HP_OK);
    assert_int_equal(ok.status, HP_STATUS_REACHED);
    int refused = 0;
    for (int i = 0; i < nb; ++i) {
        assert_int_equal(hp_plan(kp, bad[i], &kr), HP_OK);
        if (kr.status != HP_STATUS_INVALID_INPUT) continue; /* hp_plan accepts it: not here */
        ++refused;
        hp_load_info info;
        assert_int_equal(load_plan(lp, bad[i], &r, &info), HP_OK);
        assert_int_equal(r.status, HP_STATUS_INVALID_INPUT);
        assert_string_equal(hp_planner_error(lp), hp_planner_error(kp));
        /* The safe output: the last answer's pressures at its pose, every one in bounds. */
        assert_true(isinf(r.pose_error));
        for (int k = 0; k < r.n; ++k) {
            assert_true(r.bladders[k].pressure == ok.bladders[k].pressure);
            assert_true(r.bladders[k].pressure >= lo[k] && r.bladders[k].pressure <= hi[k]);
        }
        for (int j = 0; j < 6; ++j) assert_true(r.achieved[j] == ok.achieved[j]);
    }
    assert_int_equal(refused, nb - 1); /* all but the 60/60 deg turn (82.8 deg) */
    /* Inside the range the request is not refused (89 deg about one axis). */
    const double in[6] = {0, 0, 0, 89 * DEG, 0, 0};
    assert_int_equal(load_plan(lp, in, &r, NULL), HP_OK);
    assert_int_not_equal(r.status, HP_STATUS_INVALID_INPUT);
    hp_planner_destroy(kp);
    hp_planner_destroy(lp);
}

int main(void)
{
    const struct CMUnitTest tests[] = {cmocka_unit_test(test_same_refusals_as_hp_plan)};
    return cmocka_run_group_tests(tests, NULL, NULL);
}
