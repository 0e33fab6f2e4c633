/* hpi_strict_double against strtod, its reference: on every string it accepts it returns
 * strtod's double bit for bit, whether its own fast path (M·10^q with M <= 2^53, |q| <= 22)
 * or strtod decided. Inputs (seeded, 700 000): decimals of 1 to 20 digits with the point
 * anywhere or absent, leading and trailing zeros, signs, exponents from −40 to 40 (both
 * cases, with and without sign), the fast path's edges (2^53 and its neighbours, 10^±22 and
 * 10^±23), and strings it must refuse (some of them shaped like the one-pass path's plain
 * decimals until a late character). */
#include "support/test_util.h"
#include "support/rng.h"
#include "scene/strict_number.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static uint64_t rng = 0x2545F4914F6CDD1Du;

static void same_as_strtod(const char *s)
{
    double got = 0.0;
    const char *why = hpi_strict_double(s, strlen(s), &got);
    if (why) fail_msg("'%s' refused: %s", s, why);
    double want = strtod(s, NULL);
    if (memcmp(&got, &want, sizeof got) != 0) fail_msg("'%s': %a, strtod %a", s, got, want);
}

static void test_random_decimals(void **st)
{
    (void)st;
    char s[64];
    for (int t = 0; t < 700000; ++t) {
        int nd = 1 + (int)(test_rng_next(&rng) % 20);
        int point = (int)(test_rng_next(&rng) % (uint64_t)(nd + 2)), n = 0;
        if (test_rng_next(&rng) % 3 == 0) s[n++] = test_rng_next(&rng) & 1 ? '-' : '+';
        int zeros = (int)(test_rng_next(&rng) % 4); /* leading zeros */
        for (int i = 0; i < zeros; ++i) s[n++] = '0';
        for (int i = 0; i < nd; ++i) {
            if (i == point) s[n++] = '.';
            uint64_t r = test_rng_next(&rng) % 10;
            s[n++] = (char)('0' + (t % 7 == 0 && i > nd / 2 ? 0 : (int)r)); /* trailing 0s */
        }
        if (point == nd && test_rng_next(&rng) & 1) s[n++] = '.';
        if (test_rng_next(&rng) % 3 == 0) {
            s[n++] = test_rng_next(&rng) & 1 ? 'e' : 'E';
            int e = (int)(test_rng_next(&rng) % 81) - 40;
            if (e >= 0 && test_rng_next(&rng) & 1) s[n++] = '+';
            n += snprintf(s + n, sizeof s - (size_t)n, "%d", e);
        }
        s[n] = '\0';
        same_as_strtod(s);
    }
}

static void test_edges(void **st)
{
    (void)st;
    const char *ok[] = {"9007199254740992",
                        "9007199254740993",
                        "9007199254740991",
                        "-9007199254740993",
                        "900719925474099.3",
                        "1e22",
                        "1e23",
                        "1e-22",
                        "1e-23",
                        "123456789012345.6e7",
                        "0.0000000000000000000001",
                        "4.9406564584124654e-300",
                        "-0",
                        "+0.0",
                        "0e400",
                        ".5",
                        "5.",
                        "-.5e+1",
                        "1.7976931348623157e308",
                        "0.1",
                        "0.3",
                        "2.2250738585072014e-308",
                        "00000000000000000000000000001.5",
                        "1.00000000000000000000001",
                        "0.00000000000000000000001",
                        "-0.000000000000000000000012345"};
    for (size_t i = 0; i < sizeof ok / sizeof ok[0]; ++i) same_as_strtod(ok[i]);
    const char *bad[] = {"",   "nan", "inf",  "0x1p3", " 1",    "1 ",     "1e",         "e5",
                         "-",  ".",   "1..2", "1e+",   "1e309", "1e-400", "+-1",        "1.2.3",
                         "+.", "--1", "1.-2", "1a",    "1,5",   "-.",     "0.5\xc2\xa0"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        double v = 42.0;
        if (!hpi_strict_double(bad[i], strlen(bad[i]), &v)) fail_msg("'%s' accepted", bad[i]);
        assert_true(v == 42.0);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_random_decimals),
        cmocka_unit_test(test_edges),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
