/* The benchmark lab's timing protocol (bench/bench_timing.c): methods timed together take
 * turns in rounds, each walks its inputs without gaps, sample counts follow the budget rule,
 * and the per-round ratio is the median of the rounds' ratios. Fake methods that record
 * their calls stand in for planners: nothing here reads a time or depends on the load. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include "bench/bench_timing.h"

#include <math.h>

#define MAX_CALLS 4096

/* A global call log: which method ran each call, in order. */
static int call_log[MAX_CALLS];
static int n_calls;

typedef struct {
    int id;
    long next; /* the position the next call must start at */
    long gaps; /* calls that did not continue where the previous one stopped */
    long calls;
} fake;

static void fake_batch(void *ctx, long first, long count)
{
    fake *f = ctx;
    if (first != f->next) f->gaps++;
    f->next = first + count;
    f->calls++;
    if (n_calls < MAX_CALLS) call_log[n_calls++] = f->id;
}

static bench_options opts(void)
{
    bench_options o;
    bench_options_default(&o, 0, 1);
    o.samples = 30;
    o.warmup_batches = 2;
    return o;
}

/* Two methods: each walks its inputs without a gap; each gets all 30 samples in 7 rounds;
 * and they take turns: method 0 still runs after method 1 has started (timed one after the
 * other, method 0 would have finished before method 1's first call), in at least one run of
 * calls per round. */
static void test_rounds_interleave(void **state)
{
    (void)state;
    bench_options o = opts();
    fake f[2] = {{0, 0, 0, 0}, {1, 0, 0, 0}};
    bench_timed m[2] = {{.fn = fake_batch, .ctx = &f[0]}, {.fn = fake_batch, .ctx = &f[1]}};
    n_calls = 0;
    assert_int_equal(bench_time_set(&o, m, 2), 0);
    for (int i = 0; i < 2; ++i) {
        assert_int_equal(f[i].gaps, 0);
        assert_int_equal(m[i].out.samples, 30);
        assert_int_equal(m[i].out.rounds, 7);
        assert_true(m[i].out.batch >= 1);
        for (int r = 0; r < 7; ++r) assert_false(isnan(m[i].out.round_ns[r]));
        assert_true(m[i].out.p99_ns >= m[i].out.median_ns);
    }
    int first1 = -1, last0 = -1;
    for (int k = 0; k < n_calls; ++k) {
        if (call_log[k] == 1 && first1 < 0) first1 = k;
        if (call_log[k] == 0) last0 = k;
    }
    assert_true(first1 >= 0 && last0 > first1);
    /* Method 0's timed calls come in separate runs, interrupted by method 1's. */
    int runs0 = 0;
    for (int k = first1; k < n_calls; ++k)
        if (call_log[k] == 0 && call_log[k - 1] == 1) runs0++;
    assert_true(runs0 >= 7);
    /* Calls per method: calibration (≥ 1), 2 warm-up, its 30 timed batches, and one untimed
     * batch in each turn where it times any (these batches are short): at least 7 turns. */
    assert_true(f[0].calls >= 1 + 2 + 30 + 7);
}

/* One method alone (bench_time): the same sample count, an unbroken walk, one round whose
 * median is the method's, and at least 1 calibration + 2 warm-up + 30 timed calls. */
static void test_single(void **state)
{
    (void)state;
    bench_options o = opts();
    fake f = {0, 0, 0, 0};
    bench_timing t;
    assert_int_equal(bench_time(&o, fake_batch, &f, &t), 0);
    assert_int_equal(f.gaps, 0);
    assert_int_equal(t.samples, 30);
    assert_int_equal(t.rounds, 1);
    assert_true(t.round_ns[0] == t.median_ns);
    assert_true(f.calls >= 1 + 2 + 30);
}

/* The median of the per-round ratios, by hand: 2/1, 4/1, 9/3 -> {2, 3, 4} -> 3; four rounds
 * {1, 2, 4, 8} -> (2 + 4) / 2 = 3; a zero or missing round gives NaN. */
static void test_round_ratio(void **state)
{
    (void)state;
    const double a[3] = {2, 4, 9}, b[3] = {1, 1, 3};
    assert_true(bench_round_ratio(a, b, 3) == 3.0);
    const double c[4] = {1, 2, 4, 8}, one[4] = {1, 1, 1, 1};
    assert_true(bench_round_ratio(c, one, 4) == 3.0);
    const double z[3] = {1, 0, 1};
    assert_true(isnan(bench_round_ratio(a, z, 3)));
    assert_true(isnan(bench_round_ratio(a, b, 0)));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rounds_interleave),
        cmocka_unit_test(test_single),
        cmocka_unit_test(test_round_ratio),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
