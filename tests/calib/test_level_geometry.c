/* hp_level_is_geometry, the one answer to "is this level a contact geometry", against the
 * list written out here (linear, plane, surface: the levels hp_contact.h gives a distance
 * for), and every call that takes a contact geometry accepting exactly those levels and
 * refusing the others (auto, load, values outside the enum) with the same error as before
 * the predicate existed: the contact calls, the load model, the planner's load_geometry
 * setting, the layout fit's level and the calibrated scene's level (which also takes auto).
 * In the calib tests because calib reaches every module these calls live in. */
#include "support/test_util.h"
#include "support/default_layout.h"
#include "headplan/headplan.h"

/* The reference: the levels written out, not read from the library's table. */
static int listed(int l)
{
    return l == HP_LEVEL_LINEAR || l == HP_LEVEL_PLANE || l == HP_LEVEL_SURFACE;
}

/* Every value of the enum and one on each side of it. */
#define FIRST (-1)
#define LAST (HP_LEVEL_COUNT_ + 1)

static void test_predicate(void **state)
{
    (void)state;
    for (int l = FIRST; l <= LAST; ++l)
        assert_int_equal(hp_level_is_geometry((hp_level)l), listed(l));
}

static void test_contact_calls(void **state)
{
    (void)state;
    hp_layout L;
    assert_int_equal(default_layout(&L), 0);
    const double xi[6] = {1e-3, 0, -5e-4, 0, 0, 0};
    for (int l = FIRST; l <= LAST; ++l) {
        const hp_level lv = (hp_level)l;
        const hp_error want = listed(l) ? HP_OK : HP_ERR_INVALID;
        double rho[HP_MAX_BLADDERS], ro[HP_MAX_BLADDERS], b, x[6];
        assert_int_equal(hp_contact_eval(&L, lv, xi, rho, NULL, NULL), want);
        assert_int_equal(hp_contact_error_bound(&L, lv, 1e-3, 1e-2, &b), want);
        hp_layout_analysis an;
        assert_int_equal(hp_layout_analyze(&L, lv, &an), want);
        /* The radii of the nominal pose (surface): every geometry fits them. */
        assert_int_equal(hp_contact_eval(&L, HP_LEVEL_SURFACE, (double[6]){0}, ro, NULL, NULL),
                         HP_OK);
        assert_int_equal(hp_contact_fk(&L, lv, ro, NULL, x, NULL, NULL), want);
        hp_load_spec spec;
        hp_load_spec_default(&L.head, &spec);
        spec.law = HP_LOAD_LAW_CAP; /* the default bladders carry the head under the cap law only */
        hp_load_model *M = NULL;
        hp_diag d = {{0}};
        assert_int_equal(hp_load_model_create(&L, &spec, lv, &M, &d), want);
        if (!listed(l)) assert_non_null(strstr(d.text, "level must be linear, plane or surface"));
        hp_load_model_destroy(M);
    }
}

static void test_settings(void **state)
{
    (void)state;
    for (int l = FIRST; l <= LAST; ++l) {
        hp_settings s;
        hp_settings_default(&s);
        s.load_geometry = (hp_level)l;
        hp_diag d = {{0}};
        assert_int_equal(hp_settings_validate(&s, &d), listed(l) ? HP_OK : HP_ERR_INVALID);
        if (!listed(l))
            assert_non_null(strstr(d.text, "load_geometry: must be linear, plane or surface"));
    }
}

static void test_calib(void **state)
{
    (void)state;
    hp_layout L;
    assert_int_equal(default_layout(&L), 0);
    hp_calib_row row;
    memset(&row, 0, sizeof row);
    hp_layout_fit *fit = calloc(1, sizeof *fit);
    assert_non_null(fit);
    for (int l = FIRST; l <= LAST; ++l) {
        hp_layout_fit_options o;
        hp_layout_fit_options_default(&o);
        o.level = (hp_level)l;
        hp_diag d = {{0}};
        hp_error e = hp_fit_layout(&L, &row, 1, &o, fit, NULL, &d);
        /* One row fits nothing, but a geometry level passes the level check first. */
        if (listed(l)) assert_null(strstr(d.text, "level:"));
        else {
            assert_int_equal(e, HP_ERR_INVALID);
            assert_string_equal(d.text, "level: must be linear, plane or surface");
        }
        /* The scene writer takes a geometry or auto; it refuses before writing anything
         * (the path is a folder, so a level that passes is refused for the path instead). */
        hp_diag dw = {{0}};
        e = hp_calib_write_scene(HP_BINARY_DIR, &L, (hp_level)l, NULL, "x", NULL, 0, &dw);
        assert_int_equal(e, HP_ERR_INVALID);
        if (listed(l) || l == HP_LEVEL_AUTO) assert_string_not_equal(dw.text, "level: unknown");
        else assert_string_equal(dw.text, "level: unknown");
    }
    free(fit);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_predicate),
        cmocka_unit_test(test_contact_calls),
        cmocka_unit_test(test_settings),
        cmocka_unit_test(test_calib),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
