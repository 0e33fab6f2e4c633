/* hp_horizon_rh_step allocates nothing after hp_horizon_rh_create: every contact level, both
 * predictions, horizons 1..HP_HORIZON_MAX, binding rate limits, a NaN row and a refused time
 * stamp. Linked with -Wl,--wrap for every allocation function (tests/CMakeLists.txt); a
 * self-check proves the wrapping is active. */
#include "support/test_util.h"
#include "tests/horizon/horizon_fixture.h"

#include "support/alloc_counter.h"

static void test_wrap_active(void **st)
{
    (void)st;
    hf_case *c = hf_load("horizon/step.yaml", "step.csv", 10);
    assert_non_null(c);
    hp_horizon_rh *rh = NULL;
    alloc_armed = 1;
    alloc_count = 0;
    hp_error e = hp_horizon_rh_create(&c->sc.layout, &c->s, NULL, c->p0, &rh, NULL);
    alloc_armed = 0;
    assert_int_equal(e, HP_OK);
    assert_true(alloc_count >= 2);
    hp_horizon_rh_destroy(rh);
    free(c);
}

static void steps_without_allocation(hp_level level, hp_prediction pred, int N)
{
    hf_case *c = hf_load("horizon/step.yaml", "step.csv", 150);
    assert_non_null(c);
    c->s.level = level;
    hp_horizon_settings hs;
    hp_horizon_settings_default(&hs);
    hs.horizon = N;
    hs.prediction = pred;
    hs.rate_max_per_s = 2000.0;
    hp_horizon_rh *rh = NULL;
    assert_int_equal(hp_horizon_rh_create(&c->sc.layout, &c->s, &hs, c->p0, &rh, NULL), HP_OK);
    long total = 0;
    int closest = 0;
    for (size_t t = 0; t < c->T; ++t) {
        double desired[6];
        memcpy(desired, c->rows[t].correction, sizeof desired);
        if (t == 77) desired[2] = NAN; /* refused by hp_plan: the safe output */
        hp_result r;
        alloc_armed = 1;
        alloc_count = 0;
        hp_error e = hp_horizon_rh_step(rh, c->rows[t].t, desired, &r);
        hp_error e2 = hp_horizon_rh_step(rh, c->rows[t].t, desired, &r); /* same t: refused */
        alloc_armed = 0;
        total += alloc_count;
        assert_int_equal(e, HP_OK);
        assert_int_equal(e2, HP_ERR_INVALID);
        if (t == 77) assert_int_equal(r.status, HP_STATUS_INVALID_INPUT);
        closest += r.status == HP_STATUS_CLOSEST;
    }
    assert_int_equal(total, 0);
    assert_true(closest > 0); /* the rate limits bound: the solver ran, not only the chain */
    hp_horizon_rh_destroy(rh);
    free(c);
}

static void test_linear_hold(void **st)
{
    (void)st;
    steps_without_allocation(HP_LEVEL_LINEAR, HP_PREDICT_HOLD, 10);
}
static void test_plane_velocity(void **st)
{
    (void)st;
    steps_without_allocation(HP_LEVEL_PLANE, HP_PREDICT_VELOCITY, 5);
}
static void test_surface_velocity(void **st)
{
    (void)st;
    steps_without_allocation(HP_LEVEL_SURFACE, HP_PREDICT_VELOCITY, 3);
}
static void test_surface_periodic(void **st)
{
    (void)st;
    steps_without_allocation(HP_LEVEL_SURFACE, HP_PREDICT_PERIODIC, 10);
}
static void test_one_row(void **st)
{
    (void)st;
    steps_without_allocation(HP_LEVEL_LINEAR, HP_PREDICT_HOLD, 1);
}
static void test_longest(void **st)
{
    (void)st;
    steps_without_allocation(HP_LEVEL_LINEAR, HP_PREDICT_VELOCITY, HP_HORIZON_MAX);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_wrap_active),      cmocka_unit_test(test_linear_hold),
        cmocka_unit_test(test_plane_velocity),   cmocka_unit_test(test_surface_velocity),
        cmocka_unit_test(test_one_row),          cmocka_unit_test(test_longest),
        cmocka_unit_test(test_surface_periodic),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
