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
    c->s.max_time = 1e-12; /* s: half of it is far below a clock tick */
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

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_binding_budget_is_marked_and_repeatable),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
