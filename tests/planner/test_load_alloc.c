/* A plan at the load level (realtime backend) allocates nothing after hp_planner_create: reachable
 * poses, unreachable ones (the sinking search and the 6-D refinement), invalid input, with
 * and without the details (hp_load_info, which runs the forward statics). Linked with
 * -Wl,--wrap for every allocator (tests/CMakeLists.txt); a self-check proves the wrapping. */
#include "support/test_util.h"

#include "support/default_layout.h"
#include "headplan/hp_planner.h"
#include "support/load_fixture.h"

#include <stdlib.h>

#include "support/alloc_counter.h"

static void test_load_plan_no_alloc(void **st)
{
    (void)st;
    hp_layout L;
    assert_int_equal(default_layout(&L), 0);
    for (int k = 0; k < L.n; ++k) L.bladders[k].stretch_max = 1.6;
    hp_load_spec s;
    hp_load_spec_default(&L.head, &s);
    s.law = HP_LOAD_LAW_CAP; /* the default bladders carry the head under the cap law only */
    hp_settings set;
    hp_settings_default(&set);
    set.max_time = 60.0; /* the outcome, not the clock, is asserted */
    set.level = HP_LEVEL_SURFACE;
    hp_planner *p = NULL;
    alloc_armed = 1;
    alloc_count = 0;
    assert_int_equal(load_create(&L, &s, &set, HP_TIE_LEAST_SQUEEZE, &p, NULL), HP_OK);
    alloc_armed = 0;
    assert_true(alloc_count >= 1); /* the wrapping is active */
    const double deg = 0.0174532925199;
    const double ds[5][6] = {{0},
                             {1e-3, 0, -0.5e-3, 0.3 * deg, 0, -0.2 * deg},
                             {0, 0, 5e-3, 0, 0, 0},
                             {0, 0, 40e-3, 0, 0, 0} /* unreachable */,
                             {NAN, 0, 0, 0, 0, 0}};
    hp_status want[5] = {HP_STATUS_REACHED, HP_STATUS_REACHED, HP_STATUS_REACHED, HP_STATUS_CLOSEST,
                         HP_STATUS_INVALID_INPUT};
    for (int q = 0; q < 5; ++q)
        for (int details = 0; details < 2; ++details) {
            hp_result r;
            hp_load_info info;
            alloc_armed = 1;
            alloc_count = 0;
            hp_error e = load_plan(p, ds[q], &r, details ? &info : NULL);
            alloc_armed = 0;
            assert_int_equal(e, HP_OK);
            assert_int_equal(r.status, want[q]);
            assert_int_equal(alloc_count, 0);
        }
    hp_planner_destroy(p);
}

int main(void)
{
    const struct CMUnitTest tests[] = {cmocka_unit_test(test_load_plan_no_alloc)};
    return cmocka_run_group_tests(tests, NULL, NULL);
}
