/* hp_scene_settings_override: each named override sets its field in the field's units (the
 * mm of level_tolerance_mm become metres), text and number alike, and each refusal names the
 * override and leaves the settings as they were; the value checks are the planner's own
 * (hp_settings_validate accepts what an override accepts). */
#include "support/test_util.h"
#include "headplan/headplan.h"

static void expect_refused(const char *name, const char *text, double number, const char *msg)
{
    hp_settings s, before;
    hp_settings_default(&s);
    before = s;
    hp_diag d = {{0}};
    assert_int_equal(hp_scene_settings_override(&s, name, text, number, &d), HP_ERR_INVALID);
    if (strcmp(d.text, msg) != 0) print_error("said '%s', want '%s'\n", d.text, msg);
    assert_string_equal(d.text, msg);
    assert_memory_equal(&s, &before, sizeof s);
}

static void test_sets_fields(void **state)
{
    (void)state;
    hp_settings s;
    hp_settings_default(&s);
    hp_diag d = {{0}};
    assert_int_equal(hp_scene_settings_override(&s, "backend", "nlopt-slsqp", 0, &d), HP_OK);
    assert_int_equal(s.backend, HP_BACKEND_NLOPT_SLSQP);
    assert_int_equal(hp_scene_settings_override(&s, "level", "plane", 0, &d), HP_OK);
    assert_int_equal(s.level, HP_LEVEL_PLANE);
    /* "load" is a level like the others; whether the scene states a load is its caller's check. */
    assert_int_equal(hp_scene_settings_override(&s, "level", "load", 0, &d), HP_OK);
    assert_int_equal(s.level, HP_LEVEL_LOAD);
    assert_int_equal(hp_scene_settings_override(&s, "level", "plane", 0, &d), HP_OK);
    assert_int_equal(hp_scene_settings_override(&s, "tolerance", "0.25", 0, &d), HP_OK);
    assert_true(s.tolerance == 0.25);
    assert_int_equal(hp_scene_settings_override(&s, "max_iter", NULL, 50, &d), HP_OK);
    assert_int_equal(s.max_iter, 50);
    assert_int_equal(hp_scene_settings_override(&s, "restarts", NULL, 3, &d), HP_OK);
    assert_int_equal(s.restarts, 3);
    assert_int_equal(hp_scene_settings_override(&s, "restarts", "0", 0, &d), HP_OK);
    assert_int_equal(s.restarts, 0);
    assert_int_equal(hp_scene_settings_override(&s, "restarts", NULL, 64, &d), HP_OK);
    assert_int_equal(s.restarts, 64);
    assert_int_equal(hp_scene_settings_override(&s, "max_time_s", NULL, 0.5, &d), HP_OK);
    assert_true(s.max_time == 0.5);
    assert_int_equal(hp_scene_settings_override(&s, "weight_mm_per_deg", "2", 0, &d), HP_OK);
    assert_true(s.weight_mm_per_deg == 2.0);
    /* 0.02 mm is 0.02 * 1e-3 m, the same multiplication the scene reader does. */
    assert_int_equal(hp_scene_settings_override(&s, "level_tolerance_mm", NULL, 0.02, &d), HP_OK);
    assert_true(s.level_tolerance == 0.02 * 1e-3);
    assert_int_equal(hp_scene_settings_override(&s, "warm_start", NULL, 0, &d), HP_OK);
    assert_int_equal(s.warm_start, 0);
    assert_int_equal(hp_settings_validate(&s, &d), HP_OK);
}

static void test_refusals(void **state)
{
    (void)state;
    expect_refused(
        "backend", "gurobi", 0,
        "backend: unknown backend 'gurobi' (realtime, ipopt, nlopt-slsqp, nlopt-cobyla)");
    expect_refused("level", "exact", 0,
                   "level: unknown level 'exact' (linear, plane, surface, auto, load)");
    expect_refused("level", NULL, 1, "level: expected a name");
    expect_refused("max_iter", NULL, 0, "max_iter: must be an integer in 1..1000000 (got 0)");
    expect_refused("max_iter", NULL, 2.5, "max_iter: must be an integer in 1..1000000 (got 2.5)");
    expect_refused("max_iter", NULL, 1e300,
                   "max_iter: must be an integer in 1..1000000 (got 1e+300)");
    expect_refused("restarts", NULL, -1, "restarts: must be an integer in 0..64 (got -1)");
    expect_refused("restarts", NULL, 65, "restarts: must be an integer in 0..64 (got 65)");
    expect_refused("restarts", NULL, 2.5, "restarts: must be an integer in 0..64 (got 2.5)");
    expect_refused("restarts", NULL, 1e300, "restarts: must be an integer in 0..64 (got 1e+300)");
    expect_refused("restarts", NULL, NAN, "restarts: must be an integer in 0..64 (got nan)");
    expect_refused("restarts", NULL, -INFINITY, "restarts: must be an integer in 0..64 (got -inf)");
    expect_refused("restarts", "7.0x", 0, "restarts: '7.0x': not a number");
    expect_refused("level_tolerance_mm", NULL, -1,
                   "level_tolerance_mm: must be finite and > 0 mm (got -1)");
    expect_refused("tolerance", NULL, NAN,
                   "tolerance: must be > 0 and at most 1 (mm and degrees) (got nan)");
    expect_refused("max_time_s", "0", 0, "max_time_s: must be > 0 and at most 3600 s (got 0)");
    expect_refused("max_time_s", "1s", 0, "max_time_s: '1s': not a number");
    expect_refused("warm_start", NULL, 2, "warm_start: must be 0 or 1 (got 2)");
    expect_refused("mu", NULL, 1, "mu: no such setting");
}

static void test_names(void **state)
{
    (void)state;
    size_t n = 0;
    hp_settings s;
    hp_settings_default(&s);
    /* Every listed name is known to the override (its refusal is about the value only). */
    for (const char *name; (name = hp_scene_override_name(n)); ++n) {
        hp_diag d = {{0}};
        hp_scene_settings_override(&s, name, "?", 0, &d);
        assert_null(strstr(d.text, "no such setting"));
    }
    assert_int_equal(n, 9);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sets_fields),
        cmocka_unit_test(test_refusals),
        cmocka_unit_test(test_names),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
