/* The offline plan of a long trace is solved in windows by default, so its NLP (and Ipopt's
 * memory, about 27 kB per row: 545 MB for a 20,000-row trace in one solve) does not grow with
 * the trace: the same window for 2,000 and 20,000 rows. Checked on the sizes the code itself
 * reports (no timing, no large solve): hp_horizon_offline_windows, and the largest NLP an
 * actual offline solve reports in hp_horizon_info.largest_window. */
#include "support/test_util.h"
#include "tests/horizon/horizon_fixture.h"

static void test_default_window_is_flat(void **st)
{
    (void)st;
    hp_horizon_settings hs;
    hp_horizon_settings_default(&hs);
    int w2, o2, w20, o20, w, o;
    hp_horizon_offline_windows(&hs, 2000, &w2, &o2);
    hp_horizon_offline_windows(&hs, 20000, &w20, &o20);
    assert_int_equal(w2, w20);
    assert_int_equal(o2, o20);
    assert_true(w20 > 0 && w20 <= HP_HORIZON_WHOLE_MAX && o20 > 0 && o20 < w20);
    /* a trace up to the documented length is solved at once */
    hp_horizon_offline_windows(&hs, HP_HORIZON_WHOLE_MAX, &w, &o);
    assert_int_equal(w, 0);
    hp_horizon_offline_windows(&hs, HP_HORIZON_WHOLE_MAX + 1, &w, &o);
    assert_int_equal(w, w20);
    /* the caller's own window is kept, a window of T rows is one solve */
    hs.window = 20000;
    hp_horizon_offline_windows(&hs, 20000, &w, &o);
    assert_int_equal(w, 20000);
    hs.window = 300;
    hs.overlap = 50;
    hp_horizon_offline_windows(&hs, 20000, &w, &o);
    assert_true(w == 300 && o == 50);
}

/* What an offline solve reports as its largest NLP: the whole trace below the length, the
 * caller's window otherwise. */
static void test_reported_nlp_size(void **st)
{
    (void)st;
    hf_case *c = hf_load("horizon/step.yaml", "step.csv", 100);
    assert_non_null(c);
    hp_horizon_settings hs;
    hp_horizon_settings_default(&hs);
    hp_horizon_row *o = calloc(c->T, sizeof *o);
    hp_horizon_info info;
    hp_diag d = {{0}};
    assert_int_equal(
        hp_horizon_offline(&c->sc.layout, &c->s, &hs, c->rows, c->T, c->p0, o, &info, &d), HP_OK);
    assert_int_equal(info.largest_window, 100);
    assert_int_equal(info.windows, 1);
    hs.window = 40;
    hs.overlap = 10;
    assert_int_equal(
        hp_horizon_offline(&c->sc.layout, &c->s, &hs, c->rows, c->T, c->p0, o, &info, &d), HP_OK);
    assert_int_equal(info.largest_window, 40);
    assert_int_equal(info.windows, 3); /* rows 0-39, 30-69, 60-99 */
    free(o);
    free(c);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_default_window_is_flat),
        cmocka_unit_test(test_reported_nlp_size),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
