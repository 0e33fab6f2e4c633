/* cli_fmt's integer path against the printf path it replaces (cli_fmt_printf: "%.15g",
 * "%.16g", "%.17g" and strtod), string for string, and the string against the definition's
 * first requirement: it reads back to the same double (strtod); 4.1 million in all.
 * test_against_printf, 1.8 million inputs (seeded): log-uniform magnitudes over the
 * integer path's range and beyond it, both signs; random bit patterns; the neighbours of
 * every power of ten in range and of its halves; decimals of 1 to 17 random digits read by
 * strtod (short outputs); values just below the carries 9.99..9·10^X; whole numbers
 * (cli_fmt prints their digits itself; the reference is "%.0f").
 * test_every_exponent: every binary exponent the integer path covers, its extreme and
 * random mantissas, and the path must take every one of them (cli_fmt_exact).
 * test_decimal_ties: doubles that are exactly half-way between two 15- or 16-digit
 * decimals (so the round-half-to-even rule decides the digits) and their neighbours a few
 * ulps away (the read-back test decides between p = 15, 16, 17 there). */
#include "support/test_util.h"
#include "support/rng.h"

#include "cli/cli_args.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static uint64_t rng = 0x9E3779B97F4A7C15u;

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
    char c[CLI_FMT_MAX];
    size_t len = cli_fmt_len(c, v);
    if (len != strlen(a) || strcmp(c, a) != 0) fail_msg("%a: cli_fmt_len %zu for %s", v, len, c);
    if (isfinite(v) && strtod(a, NULL) != v) fail_msg("%a: %s does not read back", v, a);
    ++checked;
}

/* v and its n neighbours on each side. */
static void check_around(double v, int n)
{
    double lo = v, hi = v;
    check(v);
    for (int s = 0; s < n; ++s) {
        lo = nextafter(lo, 0.0);
        hi = nextafter(hi, INFINITY);
        check(lo);
        check(hi);
    }
}

/* nd random decimal digits, the first not 0, into s; returns nd. */
static int random_digits(char *s, int nd)
{
    for (int d = 0; d < nd; ++d)
        s[d] = (char)('0' + (d == 0 ? 1 + test_rng_next(&rng) % 9 : test_rng_next(&rng) % 10));
    return nd;
}

static void test_against_printf(void **state)
{
    (void)state;
    for (int i = 0; i < 600000; ++i) { /* log-uniform, 1e-8 .. 1e18 */
        double v = pow(10.0, -8.0 + 26.0 * test_rng_unit(&rng));
        check(test_rng_next(&rng) & 1 ? v : -v);
    }
    for (int i = 0; i < 300000; ++i) { /* any bit pattern (NaN, inf, subnormal included) */
        uint64_t u = test_rng_next(&rng);
        double v;
        memcpy(&v, &u, sizeof v);
        check(v);
    }
    for (int e = -7; e <= 17; ++e) /* powers of ten, their halves, and their neighbours */
        for (int h = 0; h < 2; ++h) check_around(h ? 5.0 * pow(10.0, e - 1) : pow(10.0, e), 2000);
    for (int i = 0; i < 600000; ++i) { /* short decimals, ties of rounding */
        char s[64];
        int nd = 1 + (int)(test_rng_next(&rng) % 17), e = (int)(test_rng_next(&rng) % 24) - 8;
        int n = random_digits(s, nd);
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
        double v = floor(pow(10.0, 15.0 * test_rng_unit(&rng)));
        check(test_rng_next(&rng) & 1 ? v : -v);
    }
    check(0.0);
    check(-0.0);
    print_message("%ld doubles checked\n", checked);
}

/* The double n·2^e2 (n < 2^53), exact. */
static double dyadic(uint64_t n, int e2) { return ldexp((double)n, e2); }

static void test_every_exponent(void **state)
{
    (void)state;
    long taken = 0;
    /* Binary exponents n2 with [2^n2, 2^(n2+1)) meeting [1e-6, 1e16): −20 .. 53. */
    for (int n2 = -20; n2 <= 53; ++n2) {
        for (int i = 0; i < 6000; ++i) {
            uint64_t m = (uint64_t)1 << 52;
            if (i == 1) m = ((uint64_t)1 << 53) - 1;
            else if (i == 2) m += 1;
            else if (i > 2) m |= test_rng_next(&rng) >> 12;
            double v = dyadic(m, n2 - 52);
            for (int sgn = 0; sgn < 2; ++sgn) {
                double w = sgn ? -v : v;
                check(w);
                char a[CLI_FMT_MAX], b[CLI_FMT_MAX];
                int in_range = fabs(w) >= 1e-6 && fabs(w) < 1e16;
                memset(a, 'x', sizeof a);
                int got = cli_fmt_exact(a, w);
                if (got != in_range) fail_msg("%a: cli_fmt_exact returned %d", w, got);
                if (got) {
                    cli_fmt(b, w);
                    if (strcmp(a, b) != 0) fail_msg("%a: cli_fmt_exact %s, cli_fmt %s", w, a, b);
                    ++taken;
                } else if (a[0] != 'x') {
                    fail_msg("%a: cli_fmt_exact wrote outside its range", w);
                }
            }
        }
    }
    /* The ends of the range and what lies outside it. */
    const double outside[] = {nextafter(1e-6, 0.0), 1e16, -1e16, 1e300, 5e-324, INFINITY, NAN};
    for (size_t i = 0; i < sizeof outside / sizeof outside[0]; ++i) {
        char a[CLI_FMT_MAX];
        if (cli_fmt_exact(a, outside[i]) != 0)
            fail_msg("%a: taken by the integer path", outside[i]);
        check(outside[i]);
    }
    char a[CLI_FMT_MAX];
    if (!cli_fmt_exact(a, 1e-6) || !cli_fmt_exact(a, nextafter(1e16, 0.0)))
        fail_msg("the ends 1e-6 and below 1e16 must take the integer path");
    print_message("%ld doubles on the integer path\n", taken);
}

/* Digits of n (n < 2^128). */
__extension__ typedef unsigned __int128 u128;

static int ndigits(u128 n)
{
    int d = 0;
    while (n) {
        n /= 10u;
        ++d;
    }
    return d;
}

static void test_decimal_ties(void **state)
{
    (void)state;
    /* N/2^j (N odd, at most 53 bits) is exactly the decimal N·5^j/10^j, whose last digit
     * is 5: with 16 or 17 significant digits it is a tie of "%.15g" or "%.16g". */
    long ties = 0;
    for (int i = 0; i < 120000; ++i) {
        int bits = 20 + (int)(test_rng_next(&rng) % 34); /* 20 .. 53 */
        uint64_t N = (test_rng_next(&rng) >> (64 - bits)) | ((uint64_t)1 << (bits - 1)) | 1u;
        /* j near where N·5^j has 16 or 17 digits (0.301·bits + 0.699·j of them). */
        int j = (int)lround((16.2 - 0.30103 * bits) / 0.69897) + (int)(test_rng_next(&rng) % 3) - 1;
        if (j < 1) j = 1;
        u128 dec = N; /* < 2^53·5^20 < 2^100 */
        for (int t = 0; t < j; ++t) dec *= 5u;
        int nd = ndigits(dec);
        if (nd != 16 && nd != 17) continue;
        double v = dyadic(N, -j);
        if (!(v >= 1e-6 && v < 1e16)) continue;
        ++ties;
        check(-v);
        check_around(v, 3);
    }
    /* Doubles nearest the half-way points of random 15- and 16-digit decimals (the last
     * digit 5 at digit 16 or 17), and their neighbours. */
    for (int i = 0; i < 100000; ++i) {
        char s[64];
        int p = 15 + (int)(test_rng_next(&rng) % 2), e = (int)(test_rng_next(&rng) % 22) - 6,
            n = random_digits(s, p);
        s[n++] = '5';
        snprintf(s + n, sizeof s - (size_t)n, "e%d", e - p);
        check_around(strtod(s, NULL), 2);
    }
    if (ties < 50000) fail_msg("only %ld exact ties generated", ties);
    print_message("%ld exact ties; %ld doubles checked so far\n", ties, checked);
}

/* The lane arithmetic cli_fmt's digit writer relies on (cli/cli_fmt.c, put8): division by
 * 100 below 10^4 and by 10 below 100 as a multiplication and a shift. */
static void test_lane_division(void **state)
{
    (void)state;
    for (uint64_t y = 0; y < 10000; ++y) assert_int_equal((y * 5243u) >> 19, y / 100u);
    for (uint64_t y = 0; y < 100; ++y) assert_int_equal((y * 103u) >> 10, y / 10u);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_against_printf), cmocka_unit_test(test_every_exponent),
        cmocka_unit_test(test_decimal_ties), cmocka_unit_test(test_lane_division)};
    return cmocka_run_group_tests(tests, NULL, NULL);
}
