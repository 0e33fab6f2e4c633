/* hp_scene_analyze, the analysis `headplan analyze` and Python's analyze() report, against
 * its steps called one by one: auto resolves to the level hp_contact_auto picks, the
 * conditioning is hp_layout_analyze's at that level and the reach is the planner's
 * (hp_planner_reach), not the layout's own (which ignores the planner's caps), bit for bit. */
#include "support/test_util.h"
#include "headplan/headplan.h"

static void check_scene(const char *file, const char *level)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/scenarios/%s", HP_SOURCE_DIR, file);
    hp_scene *sc = calloc(1, sizeof *sc);
    assert_non_null(sc);
    hp_diag d = {{0}};
    hp_settings s;
    assert_int_equal(hp_scene_load(path, sc, &d), HP_OK);
    assert_int_equal(hp_scene_settings(sc, &s, &d), HP_OK);
    if (level) assert_int_equal(hp_scene_settings_override(&s, "level", level, 0, &d), HP_OK);
    hp_scene_analysis x;
    assert_int_equal(hp_scene_analyze(&sc->layout, &s, &x, &d), HP_OK);

    hp_level want = s.level;
    if (want == HP_LEVEL_AUTO)
        assert_int_equal(
            hp_contact_auto(&sc->layout, s.level_tolerance, s.auto_trans, s.auto_rot, &want),
            HP_OK);
    assert_int_equal(x.requested, s.level);
    assert_int_equal(x.level, want);
    /* Every geometry's bound (linear, plane, surface: written out), NaN for the others. */
    for (int l = 0; l < HP_LEVEL_COUNT_; ++l) {
        if (l != HP_LEVEL_LINEAR && l != HP_LEVEL_PLANE && l != HP_LEVEL_SURFACE) {
            assert_true(isnan(x.bound[l]));
            continue;
        }
        double bl;
        assert_int_equal(
            hp_contact_error_bound(&sc->layout, (hp_level)l, s.auto_trans, s.auto_rot, &bl), HP_OK);
        assert_memory_equal(&bl, &x.bound[l], sizeof bl);
    }
    assert_true(x.bound[HP_LEVEL_SURFACE] == 0.0);
    hp_layout_analysis an;
    assert_int_equal(hp_layout_analyze(&sc->layout, want, &an), HP_OK);
    assert_int_equal(an.rank, x.an.rank);
    assert_memory_equal(an.singular_values, x.an.singular_values, sizeof an.singular_values);
    hp_settings ps = s;
    ps.level = want;
    hp_planner *p = NULL;
    assert_int_equal(hp_planner_create(&sc->layout, &ps, &p, &d), HP_OK);
    double reach[6][2];
    assert_int_equal(hp_planner_reach(p, reach), HP_OK);
    hp_planner_destroy(p);
    /* NaN (an axis not commanded) compares equal bit for bit too. */
    assert_memory_equal(reach, x.an.reach, sizeof reach);
    free(sc);
}

static void test_default_scene(void **state)
{
    (void)state;
    check_scene("default.yaml", NULL);
    check_scene("default.yaml", "linear");
    check_scene("sphere_head.yaml", NULL);
}

static void test_null(void **state)
{
    (void)state;
    hp_scene_analysis x;
    hp_settings s;
    hp_settings_default(&s);
    hp_diag d = {{0}};
    assert_int_equal(hp_scene_analyze(NULL, &s, &x, &d), HP_ERR_NULL);
    assert_non_null(strstr(d.text, "NULL"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_default_scene),
        cmocka_unit_test(test_null),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
