/* hp_scene_plan_level: the one decision of which planner plans a scene (the command line
 * and the Python module both call it). References: a planner created here from the scene's
 * settings (its level and reason: auto compares the levels' model error), and the scene
 * files' stated model.level. */
#include "support/test_util.h"

#include "headplan/hp_planner.h"
#include "headplan/hp_scene.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define SCN HP_SOURCE_DIR "/scenarios/"

static void load(const char *name, hp_scene *sc)
{
    hp_diag d = {{0}};
    hp_error e = hp_scene_load(name, sc, &d);
    if (e) print_error("%s: %s\n", name, d.text);
    assert_int_equal(e, HP_OK);
}

/* load_supine.yaml with its `model: {level: auto, ...}` line rewritten to level: load. */
static void supine_level_load(hp_scene *sc)
{
    char *text = hp_test_edit_file(SCN "load_supine.yaml", "level: auto", "level: load");
    hp_diag d = {{0}};
    assert_int_equal(hp_scene_parse(text, strlen(text), SCN "load_supine.yaml", sc, &d), HP_OK);
    free(text);
}

static void test_auto_follows_the_model_error(void **state)
{
    (void)state;
    hp_scene *sc = malloc(sizeof *sc);
    assert_non_null(sc);
    load(SCN "load_supine.yaml", sc);
    assert_int_equal(sc->level, HP_LEVEL_AUTO);
    /* The reference: the planner built from the scene's own settings. */
    hp_settings s;
    assert_int_equal(hp_scene_settings(sc, &s, NULL), HP_OK);
    hp_planner *p = NULL;
    assert_int_equal(hp_planner_create(&sc->layout, &s, &p, NULL), HP_OK);
    int ref = hp_planner_level(p) == HP_LEVEL_LOAD;
    char ref_why[HP_DIAG_MAX];
    assert_int_equal(hp_planner_level_choice(p, ref_why, sizeof ref_why), HP_OK);
    hp_planner_destroy(p);
    /* no preload: the contact levels' pressures find no rest under the weight */
    /* measured at the scene's correction (hp_scene_settings: auto_pose) */
    assert_non_null(strstr(ref_why, "auto chose load by model error at the pose x 1 mm, y 0 mm, "
                                    "z -0.5 mm, pitch 0.3 deg, roll 0 deg, yaw -0.2 deg"));
    assert_non_null(strstr(ref_why, "surface no rest (0 % carried)"));
    int use = -1;
    char why[HP_DIAG_MAX];
    hp_level_refusal refused = HP_LEVEL_REFUSED_LOAD;
    assert_int_equal(hp_scene_plan_level(sc, NULL, &use, why, sizeof why, &refused, NULL), HP_OK);
    assert_int_equal(refused, HP_LEVEL_REFUSED_NONE);
    assert_int_equal(use, ref);
    assert_int_equal(use, 1);
    assert_string_equal(why, ref_why);
    assert_int_equal(hp_scene_plan_level(sc, "auto", &use, why, sizeof why, &refused, NULL), HP_OK);
    assert_int_equal(use, 1);
    /* A kinematic level named by the caller plans it kinematically. */
    const char *kin[3] = {"linear", "plane", "surface"};
    for (int i = 0; i < 3; ++i) {
        assert_int_equal(hp_scene_plan_level(sc, kin[i], &use, why, sizeof why, &refused, NULL),
                         HP_OK);
        assert_int_equal(use, 0);
        assert_string_equal(why, "");
    }
    assert_int_equal(hp_scene_plan_level(sc, "load", &use, why, sizeof why, &refused, NULL), HP_OK);
    assert_int_equal(use, 1);
    /* the library's reason names no command-line flag: a C caller has none */
    assert_string_equal(why, "load: asked for by the caller's level");
    hp_diag d = {{0}};
    assert_int_equal(hp_scene_plan_level(sc, "cubic", &use, why, sizeof why, &refused, &d),
                     HP_ERR_INVALID);
    assert_non_null(strstr(d.text, "unknown level 'cubic'"));
    /* which refusal it is, without reading the message */
    assert_int_equal(refused, HP_LEVEL_REFUSED_UNKNOWN);
    free(sc);
}

/* model.level: load: the load level, and hp_scene_settings says what it documents (the
 * kinematic planner's surface level), never "load". */
static void test_level_load_scene(void **state)
{
    (void)state;
    hp_scene *sc = malloc(sizeof *sc);
    assert_non_null(sc);
    supine_level_load(sc);
    assert_int_equal(sc->level_load, 1);
    int use = -1;
    char why[256];
    hp_level_refusal refused = HP_LEVEL_REFUSED_LOAD;
    assert_int_equal(hp_scene_plan_level(sc, NULL, &use, why, sizeof why, &refused, NULL), HP_OK);
    assert_int_equal(use, 1);
    assert_string_equal(why, "load: asked for by model.level");
    assert_int_equal(hp_scene_plan_level(sc, "surface", &use, why, sizeof why, &refused, NULL),
                     HP_OK);
    assert_int_equal(use, 0);
    hp_settings s;
    assert_int_equal(hp_scene_settings(sc, &s, NULL), HP_OK);
    assert_int_equal(s.level, HP_LEVEL_LOAD);
    assert_true(s.load.mass == sc->load.mass);
    free(sc);
}

/* A scene without a `load` section stays kinematic whatever its level, and "load" asked
 * of it is refused with the reason. */
static void test_no_load_section(void **state)
{
    (void)state;
    hp_scene *sc = malloc(sizeof *sc);
    assert_non_null(sc);
    load(SCN "default.yaml", sc);
    assert_int_equal(sc->has_load, 0);
    int use = -1;
    char why[256] = "x";
    hp_level_refusal refused = HP_LEVEL_REFUSED_LOAD;
    assert_int_equal(hp_scene_plan_level(sc, NULL, &use, why, sizeof why, &refused, NULL), HP_OK);
    assert_int_equal(use, 0);
    assert_string_equal(why, "");
    assert_int_equal(hp_scene_plan_level(sc, "auto", &use, why, sizeof why, &refused, NULL), HP_OK);
    assert_int_equal(use, 0);
    hp_diag d = {{0}};
    assert_int_equal(hp_scene_plan_level(sc, "load", &use, why, sizeof why, &refused, &d),
                     HP_ERR_INVALID);
    assert_int_equal(use, 0);
    assert_non_null(strstr(d.text, "load needs a scene with a 'load' section"));
    assert_int_equal(refused, HP_LEVEL_REFUSED_NO_LOAD);
    assert_int_equal(hp_scene_plan_level(NULL, NULL, &use, why, sizeof why, &refused, NULL),
                     HP_ERR_NULL);
    free(sc);
}

/* The refusal a kinematic-only caller gives (batch, horizon, render, Python's Planner):
 * one sentence from the library, the reason being hp_scene_plan_level's own. */
static void test_kinematic_only(void **state)
{
    (void)state;
    hp_scene *sc = malloc(sizeof *sc);
    assert_non_null(sc);
    load(SCN "load_supine.yaml", sc);
    int use = -1;
    char why[256], want[2048];
    assert_int_equal(hp_scene_plan_level(sc, NULL, &use, why, sizeof why, NULL, NULL), HP_OK);
    snprintf(want, sizeof want,
             "%s: the scene is planned at the load level (%s), which batch does not plan: "
             "it would plan without the head's weight and disagree with solve",
             sc->file, why);
    hp_diag d = {{0}};
    hp_level_refusal refused = HP_LEVEL_REFUSED_NONE;
    assert_int_equal(hp_scene_kinematic_only(sc, NULL, "batch", &refused, &d), HP_ERR_DOMAIN);
    assert_int_equal(refused, HP_LEVEL_REFUSED_LOAD);
    assert_string_equal(d.text, want);
    assert_int_equal(hp_scene_kinematic_only(sc, "surface", "batch", &refused, NULL), HP_OK);
    assert_int_equal(refused, HP_LEVEL_REFUSED_NONE);
    assert_int_equal(hp_scene_kinematic_only(sc, "cubic", "batch", &refused, &d), HP_ERR_INVALID);
    assert_int_equal(refused, HP_LEVEL_REFUSED_UNKNOWN);
    assert_int_equal(hp_scene_kinematic_only(sc, NULL, NULL, &refused, NULL), HP_ERR_NULL);
    load(SCN "default.yaml", sc);
    assert_int_equal(hp_scene_kinematic_only(sc, NULL, "batch", &refused, &d), HP_OK);
    assert_int_equal(hp_scene_kinematic_only(sc, "load", "batch", &refused, &d), HP_ERR_INVALID);
    assert_int_equal(refused, HP_LEVEL_REFUSED_NO_LOAD);
    free(sc);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_auto_follows_the_model_error),
        cmocka_unit_test(test_level_load_scene),
        cmocka_unit_test(test_no_load_section),
        cmocka_unit_test(test_kinematic_only),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
