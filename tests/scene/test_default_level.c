/* A scene that states no model.level is planned at auto (the fidelity it needs), and its
 * settings resolve to the level hp_contact_auto picks for its layout and auto range, not
 * silently to linear. */
#include "support/test_util.h"

#include "headplan/headplan.h"

#include <stdlib.h>
#include <string.h>

static void test_no_model_section_is_auto(void **st)
{
    (void)st;
    /* The default scene without its model line: it then states no level. */
    char *text = hp_test_edit_file(HP_SOURCE_DIR "/scenarios/default.yaml", "\nmodel:", NULL);
    assert_null(strstr(text, "model:"));
    static hp_scene sc;
    hp_diag d = {{0}};
    assert_int_equal(hp_scene_parse(text, strlen(text), "nomodel.yaml", &sc, &d), HP_OK);
    free(text);
    assert_int_equal(sc.level, HP_LEVEL_AUTO);
    hp_settings s;
    assert_int_equal(hp_scene_settings(&sc, &s, &d), HP_OK);
    assert_int_equal(s.level, HP_LEVEL_AUTO);
    /* The level the planner resolves is auto's own choice for the default tolerance and
     * range (the scene leaves both to the planner's defaults), a curved one here: the
     * linear level's error bound over 10 mm, 5 degrees exceeds 0.01 mm. */
    hp_level want;
    assert_int_equal(hp_contact_auto(&sc.layout, HP_DEFAULT_LEVEL_TOLERANCE, HP_DEFAULT_AUTO_TRANS,
                                     HP_DEFAULT_AUTO_ROT, &want),
                     HP_OK);
    assert_true(want != HP_LEVEL_LINEAR);
    s.use_rate_limits = 0;
    hp_planner *p = NULL;
    assert_int_equal(hp_planner_create(&sc.layout, &s, &p, &d), HP_OK);
    assert_int_equal(hp_planner_level(p), want);
    hp_planner_destroy(p);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_no_model_section_is_auto),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
