/* hp_plan allocates nothing after hp_planner_create (realtime backend, every contact level,
 * every path: direct chain, QP, SQP, restoration, rate limits, invalid input).
 *
 * The test is linked with -Wl,--wrap for malloc, calloc, realloc, free, aligned_alloc,
 * posix_memalign and C++ operator new/new[] (tests/CMakeLists.txt), so every call from the
 * statically linked library lands in the counters below while they are armed. A self-check
 * proves the wrapping is active. */
#include "support/test_util.h"
#include "support/layout_fixture.h"

#include <stdlib.h>

#include "support/alloc_counter.h"

/* The wrapping is active for the library's own calls: hp_planner_create allocates (its
 * planner and the backend's workspace) and each allocation must be counted, in any build
 * type (a compiler may elide a malloc/free pair written in this file). */
static void test_wrap_active(void **st)
{
    (void)st;
    hp_layout L;
    assert_int_equal(lf_layout(&L), HP_OK);
    hp_planner *p = NULL;
    alloc_armed = 1;
    alloc_count = 0;
    hp_error e = hp_planner_create(&L, NULL, &p, NULL);
    alloc_armed = 0;
    assert_int_equal(e, HP_OK);
    assert_true(alloc_count >= 2);
    alloc_armed = 1;
    alloc_count = 0;
    hp_planner_destroy(p);
    alloc_armed = 0;
    assert_true(alloc_count >= 2);
}

static void plans_without_allocation(hp_level level, double rate)
{
    hp_planner *p = NULL;
    assert_int_equal(lf_planner(level, rate, &p), HP_OK);
    hp_result r;
    uint64_t seed = 31337;
    long total = 0;
    for (int t = 0; t < 60; ++t) {
        double c[6], xi[6];
        double scale = (t % 3 == 0) ? 0.5 : (t % 3 == 1) ? 8.0 : 40.0; /* reach, limits, far */
        for (int i = 0; i < 6; ++i) c[i] = scale * lf_uniform(&seed);
        lf_pose(c, xi);
        if (t % 17 == 5) xi[t % 6] = NAN;
        alloc_armed = 1;
        alloc_count = 0;
        hp_error e = hp_plan(p, xi, &r);
        alloc_armed = 0;
        total += alloc_count;
        assert_int_equal(e, HP_OK);
    }
    print_message("%s level, rate %g: %ld allocations in 60 plans\n", hp_level_name(level), rate,
                  total);
    assert_int_equal(total, 0);
    hp_planner_destroy(p);
}

static void test_linear(void **st)
{
    (void)st;
    plans_without_allocation(HP_LEVEL_LINEAR, INFINITY);
}
static void test_plane(void **st)
{
    (void)st;
    plans_without_allocation(HP_LEVEL_PLANE, INFINITY);
}
static void test_surface(void **st)
{
    (void)st;
    plans_without_allocation(HP_LEVEL_SURFACE, INFINITY);
}
static void test_rate(void **st)
{
    (void)st;
    plans_without_allocation(HP_LEVEL_SURFACE, 400.0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_wrap_active), cmocka_unit_test(test_linear),
        cmocka_unit_test(test_plane),       cmocka_unit_test(test_surface),
        cmocka_unit_test(test_rate),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
