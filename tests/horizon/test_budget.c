/* The receding horizon under a time budget that binds: its output is not left to depend on
 * the machine without a word. A budget below the clock's resolution stops every horizon solve
 * before its first iteration, whatever the load, so two runs give the same output, and every
 * row says that its budget stopped it (time-limit, as headplan batch labels such a row),
 * with pressures inside every limit. */
#include "support/test_util.h"
#include "tests/horizon/horizon_fixture.h"
#include "horizon/horizon_internal.h"

static void test_binding_budget_is_marked_and_repeatable(void **st)
{
    (void)st;
    hf_case *c = hf_load("horizon/step.yaml", "step.csv", 80);
    assert_non_null(c);
    c->s.max_time = 1e-12; /* s: its four fifths are far below a clock tick */
    hp_horizon_settings hs;
    hp_horizon_settings_default(&hs);
    hp_horizon_row *a = calloc(c->T, sizeof *a), *b = calloc(c->T, sizeof *b);
    hp_diag d = {{0}};
    assert_int_equal(hp_horizon_receding(&c->sc.layout, &c->s, &hs, c->rows, c->T, c->p0, a, &d),
                     HP_OK);
    assert_int_equal(hp_horizon_receding(&c->sc.layout, &c->s, &hs, c->rows, c->T, c->p0, b, &d),
                     HP_OK);
    for (size_t t = 0; t < c->T; ++t) {
        if (a[t].status != HP_STATUS_TIME_LIMIT)
            print_error("line %ld: %s, want time-limit\n", c->rows[t].line,
                        hp_status_name(a[t].status));
        assert_int_equal(a[t].status, HP_STATUS_TIME_LIMIT);
        assert_memory_equal(&a[t], &b[t], sizeof a[t]);
        for (int k = 0; k < c->sc.layout.n; ++k) {
            const hp_bladder *B = &c->sc.layout.bladders[k];
            assert_true(a[t].pressure[k] >= B->p_min && a[t].pressure[k] <= B->p_max);
        }
    }
    free(a);
    free(b);
    free(c);
}

/* Plans the first 200 rows of the breathing trace with every prediction, horizon settings
 * from hs_in (prediction set here) and budget max_time, and asserts what holds for any solve
 * however short: each row is planned (reached, closest, or time-limit when its budget cut the
 * solve), its pressures are inside every limit and its change from the row before within the
 * row's rate allowance, exactly, because hp_plan applies whatever iterate the solve stopped
 * at. */
static void rows_keep_every_limit(const hp_horizon_settings *hs_in, double max_time)
{
    hf_case *c = hf_load("horizon/breathing.yaml", "breathing.csv", 200);
    assert_non_null(c);
    c->s.max_time = max_time;
    static const hp_prediction preds[] = {HP_PREDICT_HOLD, HP_PREDICT_VELOCITY,
                                          HP_PREDICT_PERIODIC};
    hp_horizon_row *a = calloc(c->T, sizeof *a);
    double *delta = calloc(c->T * HP_MAX_BLADDERS, sizeof *delta);
    assert_true(a && delta);
    const int n = c->sc.layout.n;
    for (size_t p = 0; p < sizeof preds / sizeof preds[0]; ++p) {
        hp_horizon_settings hs = *hs_in;
        hs.prediction = preds[p];
        hs.start_interval_s = hp_horizon_start_interval(c->rows, c->T, hs.start_interval_s);
        hp_diag d = {{0}};
        assert_int_equal(hp_horizon_rates(&c->sc.layout, &hs, c->rows, c->T, delta, &d), HP_OK);
        assert_int_equal(
            hp_horizon_receding(&c->sc.layout, &c->s, &hs, c->rows, c->T, c->p0, a, &d), HP_OK);
        for (size_t t = 0; t < c->T; ++t) {
            const hp_status st_t = a[t].status;
            if (st_t != HP_STATUS_REACHED && st_t != HP_STATUS_CLOSEST &&
                st_t != HP_STATUS_TIME_LIMIT)
                print_error("%s, line %ld: %s\n", hp_prediction_name(preds[p]), c->rows[t].line,
                            hp_status_name(st_t));
            assert_true(st_t == HP_STATUS_REACHED || st_t == HP_STATUS_CLOSEST ||
                        st_t == HP_STATUS_TIME_LIMIT);
            for (int k = 0; k < n; ++k) {
                const hp_bladder *B = &c->sc.layout.bladders[k];
                const double P = a[t].pressure[k], prev = t ? a[t - 1].pressure[k] : c->p0[k];
                assert_true(P >= B->p_min && P <= B->p_max);
                assert_true(fabs(P - prev) <= delta[t * (size_t)n + (size_t)k]);
            }
        }
    }
    free(a);
    free(delta);
    free(c);
}

/* A control loop's deadline (100 µs a call, docs/horizon.md, A deadline): which rows the
 * clock stops depends on the machine and its load, so only what holds for every such subset
 * is asserted (on a machine fast enough to stop none, the test below still cuts solves). */
static void test_deadline_rows_keep_every_limit(void **st)
{
    (void)st;
    hp_horizon_settings hs;
    hp_horizon_settings_default(&hs);
    rows_keep_every_limit(&hs, 1e-4);
}

/* The same, with every solve cut short by the machine-independent means: one and two
 * iterations a call (rh_max_iter), the scenes' patient budget. */
static void test_short_solves_keep_every_limit(void **st)
{
    (void)st;
    hp_horizon_settings hs;
    hp_horizon_settings_default(&hs);
    for (int it = 1; it <= 2; ++it) {
        hs.rh_max_iter = it;
        rows_keep_every_limit(&hs, HF_MAX_TIME_S);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_binding_budget_is_marked_and_repeatable),
        cmocka_unit_test(test_deadline_rows_keep_every_limit),
        cmocka_unit_test(test_short_solves_keep_every_limit),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
