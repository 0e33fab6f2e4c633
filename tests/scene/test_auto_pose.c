/* settings.auto_pose: the correction at which auto, on settings that state a load, measures
 * every level's model error (hp_planner.h). The fixture tests/scene/auto_pose.yaml is built so
 * that the pose decides: at the nominal pose linear meets model.tolerance_mm 0.35, at its
 * correction (a 3 deg pitch) no contact level does and the load level does (its comment says
 * why). References: the planner's own level and reason, a planner at a named level planning
 * the same pose (whether it is reachable), and hp_planner_level_for. The measured numbers
 * are checked against solve's model error by tests/cli/auto_pose.sh. */
#include "support/test_util.h"

#include "headplan/hp_planner.h"
#include "headplan/hp_scene.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define FIXTURE HP_SOURCE_DIR "/tests/scene/auto_pose.yaml"
#define DEG (3.14159265358979323846 / 180.0)

static hp_scene *fixture(hp_settings *s)
{
    hp_scene *sc = malloc(sizeof *sc);
    assert_non_null(sc);
    hp_diag d = {{0}};
    if (hp_scene_load(FIXTURE, sc, &d) != HP_OK) print_error("%s\n", d.text);
    assert_int_equal(hp_scene_settings(sc, s, &d), HP_OK);
    return sc;
}

/* The level a planner built from (L, s) plans at, and its reason into why. */
static hp_level choose(const hp_layout *L, const hp_settings *s, char *why, size_t len)
{
    hp_planner *p = NULL;
    hp_diag d = {{0}};
    if (hp_planner_create(L, s, &p, &d) != HP_OK) print_error("create: %s\n", d.text);
    assert_non_null(p);
    hp_level level = hp_planner_level(p);
    assert_int_equal(hp_planner_level_choice(p, why, len), HP_OK);
    hp_planner_destroy(p);
    /* hp_planner_level_for runs the same decision without the rest of the planner. */
    hp_level same = HP_LEVEL_AUTO;
    char same_why[HP_DIAG_MAX];
    assert_int_equal(hp_planner_level_for(L, s, &same, same_why, sizeof same_why, &d), HP_OK);
    assert_int_equal(same, level);
    assert_string_equal(same_why, why);
    return level;
}

static void has(const char *text, const char *part)
{
    if (!strstr(text, part)) {
        print_error("'%s'\n  not in '%s'\n", part, text);
        fail();
    }
}

/* The default is the nominal pose, so a caller that never sets it is unchanged. */
static void test_default_is_the_nominal_pose(void **state)
{
    (void)state;
    hp_settings s;
    memset(&s, 0xff, sizeof s);
    hp_settings_default(&s);
    for (int i = 0; i < 6; ++i) assert_true(s.auto_pose[i] == 0.0);
    assert_int_equal(hp_settings_validate(&s, NULL), HP_OK);
}

/* A scene's correction is where its settings measure (hp_scene_settings); the pose decides
 * the level, and the reason names the pose it measured at. */
static void test_the_pose_decides(void **state)
{
    (void)state;
    hp_settings s;
    hp_scene *sc = fixture(&s);
    assert_true(sc->has_correction);
    for (int i = 0; i < 6; ++i) assert_true(s.auto_pose[i] == sc->correction[i]);
    assert_true(fabs(s.auto_pose[3] - 3 * DEG) < 1e-15);
    char why[HP_DIAG_MAX];

    /* At the nominal pose: linear meets the tolerance (the choice before this setting). */
    hp_settings nominal = s;
    memset(nominal.auto_pose, 0, sizeof nominal.auto_pose);
    assert_int_equal(choose(&sc->layout, &nominal, why, sizeof why), HP_LEVEL_LINEAR);
    has(why, "auto chose linear by model error at the nominal pose (tolerance 0.35 mm, "
             "0.35 deg): linear ");
    has(why, " meets it");

    /* At the correction: every contact level exceeds it, the load level meets it. */
    assert_int_equal(choose(&sc->layout, &s, why, sizeof why), HP_LEVEL_LOAD);
    has(why, "auto chose load by model error at the pose x 0 mm, y 0 mm, z 0 mm, pitch 3 deg, "
             "roll 0 deg, yaw 0 deg (tolerance 0.35 mm, 0.35 deg): linear ");
    has(why, " exceed it; load ");
    has(why, " meets it");

    /* The same pose with a tolerance every level meets: the cheapest, linear. */
    hp_settings wide = s;
    wide.level_tolerance = 0.1; /* 100 mm */
    assert_int_equal(choose(&sc->layout, &wide, why, sizeof why), HP_LEVEL_LINEAR);
    has(why, "auto chose linear by model error at the pose x 0 mm, y 0 mm, z 0 mm, pitch 3 deg");
    free(sc);
}

/* A correction a level cannot reach is compared at that level's closest answer, said so. */
static void test_unreachable_is_compared_at_the_closest_answer(void **state)
{
    (void)state;
    hp_settings s;
    hp_scene *sc = fixture(&s);
    const double far[6] = {5e-3, 5e-3, 5e-3, 3 * DEG, 3 * DEG, 3 * DEG};
    memcpy(s.auto_pose, far, sizeof far);
    s.level_tolerance = 0.1; /* 100 mm: the measurement meets it, so linear is chosen */
    /* The reference: a linear planner cannot reach it. */
    hp_settings lin = s;
    lin.level = HP_LEVEL_LINEAR;
    lin.use_rate_limits = 0;
    hp_planner *p = NULL;
    assert_int_equal(hp_planner_create(&sc->layout, &lin, &p, NULL), HP_OK);
    hp_result r;
    assert_int_equal(hp_plan(p, far, &r), HP_OK);
    assert_int_equal(r.status, HP_STATUS_CLOSEST);
    hp_planner_destroy(p);
    char why[HP_DIAG_MAX];
    assert_int_equal(choose(&sc->layout, &s, why, sizeof why), HP_LEVEL_LINEAR);
    has(why, "at the pose x 5 mm, y 5 mm, z 5 mm, pitch 3 deg, roll 3 deg, yaw 3 deg");
    has(why, " deg at its closest answer meets it");
    free(sc);
}

/* Every component is checked by the one validator (finite, within hp_plan's range), and the
 * identifiable range at create where auto measures there; the field and component named. */
static void test_auto_pose_checked(void **state)
{
    (void)state;
    static const char *const names[6] = {"x", "y", "z", "pitch", "roll", "yaw"};
    hp_settings s;
    hp_scene *sc = fixture(&s);
    const double bad[3] = {NAN, INFINITY, 0};
    for (int i = 0; i < 6; ++i) {
        for (int j = 0; j < 3; ++j) {
            hp_settings t = s;
            /* out of range: beyond 1 m, beyond pi rad */
            t.auto_pose[i] = j < 2 ? bad[j] : i < 3 ? -1.5 : 4.0;
            hp_diag d = {{0}};
            assert_int_equal(hp_settings_validate(&t, &d), HP_ERR_INVALID);
            char want[128];
            snprintf(want, sizeof want, "auto_pose (the correction auto measures at) %s: %s",
                     names[i], j < 2 ? "not finite" : "out of range (|translation| <= 1 m");
            has(d.text, want);
            hp_planner *p = NULL;
            assert_int_equal(hp_planner_create(&sc->layout, &t, &p, &d), HP_ERR_INVALID);
            assert_null(p);
            has(d.text, want);
        }
    }
    /* Within pi but outside the ellipsoid's identifiable range (below 90 deg). */
    s.auto_pose[3] = 100 * DEG;
    assert_int_equal(hp_settings_validate(&s, NULL), HP_OK);
    hp_diag d = {{0}};
    hp_planner *p = NULL;
    assert_int_equal(hp_planner_create(&sc->layout, &s, &p, &d), HP_ERR_INVALID);
    has(d.text, "auto_pose (the correction auto measures at) rotation: angle 100.0 deg is "
                "outside the identifiable range");
    /* A named level does not measure there: the pose is not used, and not refused. */
    s.level = HP_LEVEL_SURFACE;
    assert_int_equal(hp_planner_create(&sc->layout, &s, &p, &d), HP_OK);
    hp_planner_destroy(p);
    free(sc);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_default_is_the_nominal_pose),
        cmocka_unit_test(test_the_pose_decides),
        cmocka_unit_test(test_unreachable_is_compared_at_the_closest_answer),
        cmocka_unit_test(test_auto_pose_checked),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
