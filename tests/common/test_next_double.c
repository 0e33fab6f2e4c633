/* The neighbouring doubles by integer steps on the representation (common/next_double.h)
 * against libm's nextafter, the independent reference, bit for bit: over seeded random
 * doubles of every sign and magnitude (random 64-bit patterns, NaNs skipped), the window
 * pressures and radii the planner steps (uniform in ±20 kPa and in [1e-3, 1e-1] m), and
 * the edges where the step crosses a binade, zero, the subnormals or the overflow
 * threshold. Both directions; the sign of a zero result is compared too (memcmp). */
#include "support/test_util.h"
#include "support/rng.h"

#include "common/next_double.h"

#include <float.h>

static int same_bits(double a, double b) { return memcmp(&a, &b, sizeof a) == 0; }

static void check(double x, long *n)
{
    double up = hpi_next_up(x), ref_up = nextafter(x, INFINITY);
    double dn = hpi_next_down(x), ref_dn = nextafter(x, -INFINITY);
    if (!same_bits(up, ref_up) || !same_bits(dn, ref_dn)) {
        print_error("x = %a: up %a (nextafter %a), down %a (nextafter %a)\n", x, up, ref_up, dn,
                    ref_dn);
        fail();
    }
    ++*n;
}

static void test_next_double_is_nextafter(void **state)
{
    (void)state;
    long n = 0;
    const double edges[] = {0.0,      -0.0,    DBL_TRUE_MIN, -DBL_TRUE_MIN, DBL_MIN,
                            -DBL_MIN, DBL_MAX, -DBL_MAX,     1.0,           -1.0,
                            2.0,      0.5,     INFINITY,     -INFINITY};
    for (size_t i = 0; i < sizeof edges / sizeof edges[0]; ++i) {
        check(edges[i], &n);
        check(nextafter(edges[i], 0.0), &n);
    }
    uint64_t seed = 0x0e11d;
    for (int i = 0; i < 200000; ++i) {
        uint64_t u = test_rng_next(&seed);
        double x;
        memcpy(&x, &u, sizeof x);
        if (!isnan(x)) check(x, &n);
        check(test_rng_uniform(&seed, -2e4, 2e4), &n);
        check(test_rng_uniform(&seed, 1e-3, 1e-1), &n);
    }
    /* NaN in, NaN out (nextafter's answer; never on the planner's path) */
    assert_true(isnan(hpi_next_up(NAN)) && isnan(hpi_next_down(NAN)));
    print_message("%ld doubles stepped both ways, nextafter's bits each time\n", n);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_next_double_is_nextafter),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
