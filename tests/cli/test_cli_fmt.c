/* cli_fmt's integer path against the printf path it replaces (cli_fmt_printf: "%.15g",
 * "%.16g", "%.17g" and strtod), string for string, and both against the definition: the
 * string reads back to the same double (strtod) and no shorter "%.{p}g" (p >= 15) does.
 * Inputs, 1.6 million in all (seeded): log-uniform magnitudes over the integer path's
 * range and beyond it, both signs; random bit patterns; the neighbours of every power of
 * ten in range and of its halves; decimals of 1 to 17 random digits read by strtod (short
 * outputs and the exact ties of rounding); values just below the carries 9.99..9·10^X;
 * whole numbers (cli_fmt prints their digits itself; the reference is "%.0f"). */
#include "test_util.h"

#include "cli/cli_args.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static uint64_t rng = 0x9E3779B97F4A7C15u;
static uint64_t next(void)
{
    uint64_t z = (rng += 0x9E3779B97F4A7C15u);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9u;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBu;
    return z ^ (z >> 31);
}
static double unit(void) { return (double)(next() >> 11) * 0x1p-53; }

static long checked;

static void check(double v)
{
    char a[CLI_FMT_MAX], b[CLI_FMT_MAX];
    cli_fmt(a, v);
    cli_fmt_printf(b, v);
    if (v == 0.0 || (fabs(v) < 1e15 && v == (double)(long long)v)) {
        /* Whole numbers: "%.0f", and "-0" for negative zero. */
        snprintf(b, sizeof b, "%.0f", v);
        if (v == 0.0 && signbit(v)) snprintf(b, sizeof b, "-0");
    }
    if (strcmp(a, b) != 0) fail_msg("%a: cli_fmt %s, reference %s", v, a, b);
    if (isfinite(v) && strtod(a, NULL) != v) fail_msg("%a: %s does not read back", v, a);
    ++checked;
}

static void test_against_printf(void **state)
{
    (void)state;
    for (int i = 0; i < 600000; ++i) { /* log-uniform, 1e-8 .. 1e18 */
        double v = pow(10.0, -8.0 + 26.0 * unit());
        check(next() & 1 ? v : -v);
    }
    for (int i = 0; i < 300000; ++i) { /* any bit pattern (NaN, inf, subnormal included) */
        uint64_t u = next();
        double v;
        memcpy(&v, &u, sizeof v);
        check(v);
    }
    for (int e = -7; e <= 17; ++e) /* powers of ten, their halves, and their neighbours */
        for (int h = 0; h < 2; ++h) {
            double p = h ? 5.0 * pow(10.0, e - 1) : pow(10.0, e);
            double lo = p, hi = p;
            for (int s = 0; s < 2000; ++s) {
                lo = nextafter(lo, 0.0);
                hi = nextafter(hi, INFINITY);
                check(lo);
                check(hi);
            }
            check(p);
        }
    for (int i = 0; i < 600000; ++i) { /* short decimals, ties of rounding */
        char s[64];
        int nd = 1 + (int)(next() % 17), e = (int)(next() % 24) - 8;
        int n = 0;
        for (int d = 0; d < nd; ++d) s[n++] = (char)('0' + (d == 0 ? 1 + next() % 9 : next() % 10));
        snprintf(s + n, sizeof s - (size_t)n, "e%d", e - nd + 1);
        check(strtod(s, NULL));
    }
    for (int X = -7; X <= 16; ++X) /* just below the carries 99..9 */
        for (int p = 14; p <= 18; ++p) {
            char s[64];
            int n = 0;
            for (int d = 0; d < p; ++d) s[n++] = '9';
            snprintf(s + n, sizeof s - (size_t)n, "e%d", X - p + 1);
            double v = strtod(s, NULL);
            check(v);
            check(nextafter(v, 0.0));
            check(nextafter(v, INFINITY));
        }
    for (int i = 0; i < 100000; ++i) { /* whole numbers up to 1e15, both signs */
        double v = floor(pow(10.0, 15.0 * unit()));
        check(next() & 1 ? v : -v);
    }
    check(0.0);
    check(-0.0);
    print_message("%ld doubles checked\n", checked);
}

int main(void)
{
    const struct CMUnitTest tests[] = {cmocka_unit_test(test_against_printf)};
    return cmocka_run_group_tests(tests, NULL, NULL);
}
