/* A scene that states no model.level is planned at auto (the fidelity it needs), and its
 * settings resolve to the level hp_contact_auto picks for its layout and auto range, not
 * silently to linear. */
#include "test_util.h"

#include "headplan/headplan.h"

#include <stdio.h>
#include <string.h>

static void test_no_model_section_is_auto(void **st)
{
    (void)st;
    char path[512], text[8192];
    snprintf(path, sizeof path, "%s/scenarios/default.yaml", HP_SOURCE_DIR);
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    size_t n = fread(text, 1, sizeof text - 1, f);
    fclose(f);
    text[n] = '\0';
    /* Drop the model line: the scene then states no level. */
    char *m = strstr(text, "\nmodel:");
    assert_non_null(m);
    char *end = strchr(m + 1, '\n');
    memmove(m, end, strlen(end) + 1);
    static hp_scene sc;
    hp_diag d = {{0}};
    assert_int_equal(hp_scene_parse(text, strlen(text), "nomodel.yaml", &sc, &d), HP_OK);
    assert_int_equal(sc.level, HP_LEVEL_AUTO);
    hp_settings s;
    assert_int_equal(hp_scene_settings(&sc, &s, &d), HP_OK);
    assert_int_equal(s.level, HP_LEVEL_AUTO);
    /* The level the planner resolves is auto's own choice for the default tolerance and
     * range (the scene leaves both to the planner's defaults), a curved one here: the
     * linear level's error bound over 10 mm, 5 degrees exceeds 0.01 mm. */
    hp_level want;
    assert_int_equal(hp_contact_auto(&sc.layout, HP_DEFAULT_LEVEL_TOLERANCE,
                                     HP_DEFAULT_AUTO_TRANS, HP_DEFAULT_AUTO_ROT, &want),
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
