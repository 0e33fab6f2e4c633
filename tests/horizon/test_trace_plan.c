/* hp_trace_plan_run against the sequence it promises, written out here with the planner's
 * own public calls (and the internal per-plan rate limit, as greedy sets it): the state before
 * each row is the previous planned row's result alone (the nominal answer, or the start
 * pressures, before the first), skipped rows pass it through, and with per-row rates each
 * row's allowance is min(rate_max, rate_max_per_s · interval). Every result is compared bit
 * for bit: the trace call must be that sequence, not an approximation of it. */
#include "support/test_util.h"
#include "tests/horizon/horizon_fixture.h"
#include "horizon/horizon_internal.h"

#define ROWS 120

/* 1 when two results agree bit for bit in every field a front-end shows (time excluded). */
static int same_result(const hp_result *a, const hp_result *b)
{
    if (a->status != b->status || a->n != b->n || a->raw_code != b->raw_code ||
        a->iterations != b->iterations)
        return 0;
    if (memcmp(a->achieved, b->achieved, sizeof a->achieved) != 0 ||
        memcmp(a->commanded, b->commanded, sizeof a->commanded) != 0 ||
        memcmp(a->uncommanded, b->uncommanded, sizeof a->uncommanded) != 0)
        return 0;
    for (int k = 0; k < a->n; ++k) {
        const hp_bladder_result *x = &a->bladders[k], *y = &b->bladders[k];
        if (memcmp(&x->pressure, &y->pressure, sizeof x->pressure) != 0 ||
            memcmp(&x->ri, &y->ri, sizeof x->ri) != 0 ||
            memcmp(&x->ro, &y->ro, sizeof x->ro) != 0 ||
            memcmp(&x->stretch, &y->stretch, sizeof x->stretch) != 0 || x->binding != y->binding)
            return 0;
    }
    return 1;
}

/* The reference: rows planned by hand. start NULL: hp_planner_reset; hs NULL: no per-row
 * rates. Skipped rows get status -1. */
static void reference(const hf_case *c, const unsigned char *skip, const double *start,
                      const hp_horizon_settings *hs, hp_result *ref)
{
    hp_planner *p = NULL;
    assert_int_equal(hp_planner_create(&c->sc.layout, &c->s, &p, NULL), HP_OK);
    if (start) assert_int_equal(hp_planner_set_previous(p, start), HP_OK);
    else hp_planner_reset(p);
    const hp_result *prev = NULL;
    for (size_t t = 0; t < c->T; ++t) {
        if (skip && skip[t]) {
            ref[t].status = (hp_status)-1;
            continue;
        }
        if (prev) assert_int_equal(hp_planner_set_previous_result(p, prev), HP_OK);
        if (hs) {
            double dt = t ? c->rows[t].t - c->rows[t - 1].t : hs->start_interval_s;
            double delta[HP_MAX_BLADDERS];
            for (int k = 0; k < c->sc.layout.n; ++k)
                delta[k] = fmin(c->sc.layout.bladders[k].rate_max, hs->rate_max_per_s * dt);
            assert_int_equal(hp_planner_set_rate_max(p, delta), HP_OK);
        }
        assert_int_equal(hp_plan(p, c->rows[t].correction, &ref[t]), HP_OK);
        prev = &ref[t];
    }
    hp_planner_destroy(p);
}

/* The trace call over the same rows into out (skipped rows keep status -1). */
static void traced(const hf_case *c, const unsigned char *skip, const double *start,
                   const hp_horizon_settings *hs, hp_result *out)
{
    hp_planner *p = NULL;
    hp_trace_plan *tp = NULL;
    hp_diag d = {{0}};
    assert_int_equal(hp_planner_create(&c->sc.layout, &c->s, &p, NULL), HP_OK);
    assert_int_equal(hp_trace_plan_create(p, hs, &tp, &d), HP_OK);
    if (start) assert_int_equal(hp_trace_plan_set_start(tp, start, &d), HP_OK);
    for (size_t t = 0; t < c->T; ++t) out[t].status = (hp_status)-1;
    hp_error e = hp_trace_plan_run(tp, c->rows, skip, c->T, NULL, NULL, out, &d);
    if (e != HP_OK) fprintf(stderr, "%s\n", d.text);
    assert_int_equal(e, HP_OK);
    hp_trace_plan_destroy(tp);
    hp_planner_destroy(p);
}

static void compare(const hf_case *c, const hp_result *a, const hp_result *b, const char *what)
{
    size_t differ = 0, planned = 0;
    for (size_t t = 0; t < c->T; ++t) {
        if ((int)a[t].status == -1 || (int)b[t].status == -1) {
            differ += a[t].status != b[t].status;
            continue;
        }
        planned++;
        differ += !same_result(&a[t], &b[t]);
    }
    if (differ) fprintf(stderr, "%s: %zu of %zu rows differ\n", what, differ, c->T);
    assert_int_equal(differ, 0);
    assert_true(planned > 0);
}

/* Rows the way batch plans them: nominal start, the planner's own rate limits, every
 * seventh row skipped as a bad row of the file. */
static void test_batch_sequence(void **state)
{
    (void)state;
    hf_case *c = hf_load("horizon/step.yaml", "step.csv", ROWS);
    assert_non_null(c);
    unsigned char skip[ROWS] = {0};
    for (size_t t = 0; t < c->T; t += 7) skip[t] = 1;
    hp_result *a = calloc(2 * c->T, sizeof *a);
    assert_non_null(a);
    reference(c, skip, NULL, NULL, a);
    traced(c, skip, NULL, NULL, a + c->T);
    compare(c, a, a + c->T, "batch sequence");
    free(a);
    free(c);
}

/* Rows the way greedy plans them: the start pressures, per-row rates of 2 kPa/s from the
 * intervals (the step trace binds them: the test would not see a missing allowance if no row
 * reached it, so at least one row must be CLOSEST). */
static void test_greedy_sequence(void **state)
{
    (void)state;
    hf_case *c = hf_load("horizon/step.yaml", "step.csv", ROWS);
    assert_non_null(c);
    hp_horizon_settings hs;
    hp_horizon_settings_default(&hs);
    hs.rate_max_per_s = 2e3;
    hp_result *a = calloc(2 * c->T, sizeof *a);
    assert_non_null(a);
    reference(c, NULL, c->p0, &hs, a);
    traced(c, NULL, c->p0, &hs, a + c->T);
    compare(c, a, a + c->T, "greedy sequence");
    size_t closest = 0;
    for (size_t t = 0; t < c->T; ++t) closest += a[t].status == HP_STATUS_CLOSEST;
    assert_true(closest > 0);
    free(a);
    free(c);
}

/* A run split in two, the second half on a fresh planner given the last row of the first as
 * its state (hp_trace_plan_set_state), continues as the whole run does: batch's shards. */
static void test_split_run(void **state)
{
    (void)state;
    hf_case *c = hf_load("horizon/step.yaml", "step.csv", ROWS);
    assert_non_null(c);
    hp_result *a = calloc(2 * c->T, sizeof *a);
    assert_non_null(a);
    traced(c, NULL, NULL, NULL, a);
    size_t k = c->T / 2;
    hp_planner *p = NULL;
    hp_trace_plan *tp = NULL;
    assert_int_equal(hp_planner_create(&c->sc.layout, &c->s, &p, NULL), HP_OK);
    assert_int_equal(hp_trace_plan_create(p, NULL, &tp, NULL), HP_OK);
    /* Only the fields the contract names: n, achieved, ri, ro, pressure. */
    hp_result prev;
    memset(&prev, 0xff, sizeof prev);
    prev.n = a[k - 1].n;
    memcpy(prev.achieved, a[k - 1].achieved, sizeof prev.achieved);
    for (int b = 0; b < prev.n; ++b) {
        prev.bladders[b].ri = a[k - 1].bladders[b].ri;
        prev.bladders[b].ro = a[k - 1].bladders[b].ro;
        prev.bladders[b].pressure = a[k - 1].bladders[b].pressure;
    }
    assert_int_equal(hp_trace_plan_set_state(tp, &prev), HP_OK);
    assert_int_equal(
        hp_trace_plan_run(tp, c->rows + k, NULL, c->T - k, NULL, NULL, a + c->T + k, NULL), HP_OK);
    for (size_t t = k; t < c->T; ++t) assert_true(same_result(&a[t], &a[c->T + t]));
    hp_trace_plan_destroy(tp);
    hp_planner_destroy(p);
    free(a);
    free(c);
}

/* With per-row rates a time stamp not after the previous one stops the run naming the line;
 * the rows before it are planned and handed to the sink. */
static hp_error count_rows(void *ctx, size_t i, const hp_result *r)
{
    (void)i;
    (void)r;
    *(size_t *)ctx += 1;
    return HP_OK;
}

static void test_bad_interval(void **state)
{
    (void)state;
    hf_case *c = hf_load("horizon/step.yaml", "step.csv", 10);
    assert_non_null(c);
    c->rows[5].t = c->rows[4].t;
    hp_horizon_settings hs;
    hp_horizon_settings_default(&hs);
    hp_planner *p = NULL;
    hp_trace_plan *tp = NULL;
    hp_diag d = {{0}};
    assert_int_equal(hp_planner_create(&c->sc.layout, &c->s, &p, NULL), HP_OK);
    assert_int_equal(hp_trace_plan_create(p, &hs, &tp, &d), HP_OK);
    size_t n = 0;
    assert_int_equal(hp_trace_plan_run(tp, c->rows, NULL, c->T, count_rows, &n, NULL, &d),
                     HP_ERR_INVALID);
    assert_int_equal(n, 5);
    char want[64];
    snprintf(want, sizeof want, "line %ld: t_s:", c->rows[5].line);
    assert_non_null(strstr(d.text, want));
    /* A bad setting is refused at create, naming the field. */
    hp_trace_plan_destroy(tp);
    hs.start_interval_s = -1;
    assert_int_equal(hp_trace_plan_create(p, &hs, &tp, &d), HP_ERR_INVALID);
    assert_null(tp);
    assert_non_null(strstr(d.text, "start_interval_s"));
    hp_planner_destroy(p);
    free(c);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_batch_sequence),
        cmocka_unit_test(test_greedy_sequence),
        cmocka_unit_test(test_split_run),
        cmocka_unit_test(test_bad_interval),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
