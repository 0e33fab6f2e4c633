/* The backend table lists every backend of the public enum, each complete and named as
 * hp_backend_name says, with the capabilities the core relies on instead of enum tests;
 * backend-only options go through hp_planner_set_option. */
#include "planner/planner_internal.h"
#include "support/layout_fixture.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <string.h>
#include <cmocka.h>

static void test_every_backend_in_the_table(void **st)
{
    (void)st;
    for (int b = 0; b < HP_BACKEND_COUNT_; ++b) {
        const hp_backend_ops *ops = hpi_backend_table((hp_backend)b);
        assert_non_null(ops);
        assert_non_null(ops->create);
        assert_non_null(ops->solve);
        assert_non_null(ops->destroy);
        assert_string_equal(ops->name, hp_backend_name((hp_backend)b));
        hp_backend parsed;
        assert_int_equal(hp_backend_parse(ops->name, &parsed), HP_OK);
        assert_int_equal(parsed, b);
        /* A backend that warm-starts itself says so and implements the call. */
        assert_int_equal((ops->caps & HP_BACKEND_WARM_STARTS) != 0, ops->warm_point != NULL);
    }
    assert_null(hpi_backend_table(HP_BACKEND_COUNT_));
    assert_null(hpi_backend_table((hp_backend)-1));
}

/* The documented capabilities: the control loop's path is real time and needs no lock,
 * Ipopt certifies its optimum but is serialised (Debian's MUMPS), NLopt's stopping tests
 * certify nothing (the core checks first-order conditions for it). */
static void test_capabilities(void **st)
{
    (void)st;
    unsigned rt = hpi_backend_table(HP_BACKEND_REALTIME)->caps;
    unsigned ip = hpi_backend_table(HP_BACKEND_IPOPT)->caps;
    unsigned sq = hpi_backend_table(HP_BACKEND_NLOPT_SLSQP)->caps;
    unsigned cb = hpi_backend_table(HP_BACKEND_NLOPT_COBYLA)->caps;
    assert_true(rt & HP_BACKEND_REAL_TIME && rt & HP_BACKEND_THREAD_SAFE &&
                rt & HP_BACKEND_CERTIFIES);
    assert_true(ip & HP_BACKEND_CERTIFIES && !(ip & HP_BACKEND_THREAD_SAFE));
    assert_true(!(sq & HP_BACKEND_CERTIFIES) && !(cb & HP_BACKEND_CERTIFIES));
    for (int b = 0; b < HP_BACKEND_COUNT_; ++b)
        if (b != HP_BACKEND_REALTIME)
            assert_false(hpi_backend_table((hp_backend)b)->caps & HP_BACKEND_REAL_TIME);
}

/* Ipopt's limited-memory switch is an option of that backend: known there, refused by name
 * elsewhere, a bad value refused; the quasi-Newton solve reaches the same closest answer as
 * the exact Hessian (to 1e-5 mm/deg: it stops on the same KKT tolerance, 1e-9, but its
 * Hessian is only an approximation). */
static void test_backend_option(void **st)
{
    (void)st;
    hp_layout L;
    assert_int_equal(lf_layout(&L), HP_OK);
    hp_settings s;
    hp_settings_default(&s);
    s.level = HP_LEVEL_LINEAR;
    s.backend = HP_BACKEND_REALTIME;
    hp_planner *p = NULL;
    assert_int_equal(hp_planner_create(&L, &s, &p, NULL), HP_OK);
    assert_int_equal(hp_planner_set_option(p, "hessian_approximation", 1), HP_ERR_INVALID);
    assert_non_null(strstr(hp_planner_error(p), "realtime backend has no options"));
    assert_int_equal(hp_planner_set_option(p, NULL, 1), HP_ERR_NULL);
    hp_planner_destroy(p);

    s.backend = HP_BACKEND_IPOPT;
    s.max_time = 60.0; /* CLOSEST, never time-limit: under ASan on a loaded machine the
                        * default 1 s budget ran out (fresh-clone CI of d5eef1a) */
    hp_planner *exact = NULL, *lbfgs = NULL;
    assert_int_equal(hp_planner_create(&L, &s, &exact, NULL), HP_OK);
    assert_int_equal(hp_planner_create(&L, &s, &lbfgs, NULL), HP_OK);
    assert_int_equal(hp_planner_set_option(lbfgs, "hessian_aproximation", 1), HP_ERR_INVALID);
    assert_non_null(strstr(hp_planner_error(lbfgs), "unknown option 'hessian_aproximation'"));
    assert_int_equal(hp_planner_set_option(lbfgs, "hessian_approximation", 2), HP_ERR_INVALID);
    assert_int_equal(hp_planner_set_option(lbfgs, "hessian_approximation", 1), HP_OK);
    const double far[6] = {0.02, 0, 0, 0, 0, 0.1}; /* 20 mm, 5.7 deg: beyond reach */
    hp_result a, b;
    assert_int_equal(hp_plan(exact, far, &a), HP_OK);
    assert_int_equal(hp_plan(lbfgs, far, &b), HP_OK);
    assert_int_equal(a.status, HP_STATUS_CLOSEST);
    assert_int_equal(b.status, HP_STATUS_CLOSEST);
    for (int i = 0; i < 6; ++i)
        assert_true(fabs(a.achieved[i] - b.achieved[i]) * (i < 3 ? 1e3 : 57.29577951308232) < 1e-5);
    hp_planner_destroy(exact);
    hp_planner_destroy(lbfgs);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_backend_in_the_table),
        cmocka_unit_test(test_capabilities),
        cmocka_unit_test(test_backend_option),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
