/* cli_fmt: the shortest of "%.15g", "%.16g", "%.17g" that reads back to the same double.
 *
 * Printing ~60 numbers a row was most of a batch row's time: glibc's printf makes each
 * digit string with multi-precision arithmetic, and the search needs up to three of them
 * and two strtod calls. For |v| in [1e-6, 1e16) (every pose, radius, pressure and stretch
 * a plan returns) the same strings come from exact integer arithmetic here:
 *   - v = m·2^e (m < 2^53), so v·10^k for 0 <= k <= 22 is the 128-bit integer m·10^k
 *     shifted right by −e (or left by at most 1): its rounding to an integer, half to even,
 *     is exactly the rounding printf does (correct rounding of the binary value, ties to
 *     even in the default rounding mode), so D = round(v·10^(p−1−X)) are the p significant
 *     digits "%.{p}g" prints, X the decimal exponent;
 *   - whether D·10^(X−p+1) reads back as v is decided exactly when D <= 2^53 and
 *     |X−p+1| <= 22 (the double nearest D and the power of ten are both exact, and one
 *     IEEE multiplication or division rounds correctly: Clinger's fast path), else strtod
 *     decides;
 *   - the string is laid out as %g does: exponent form when X < −4 or X >= p, trailing
 *     zeros removed.
 * Anything else (0, integers, non-finite, tiny or huge magnitudes) takes the printf path.
 * tests/cli/test_cli_fmt.c compares both paths on millions of doubles. */
#define __STDC_WANT_IEC_60559_BFP_EXT__ 1 /* strfromd (ISO/IEC TS 18661-1, glibc >= 2.25) */
#include "cli/cli_args.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

__extension__ typedef unsigned __int128 u128;

static const double POW10[23] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                                 1e8,  1e9,  1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
                                 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};

static const uint64_t POW10U[20] = {1u,
                                    10u,
                                    100u,
                                    1000u,
                                    10000u,
                                    100000u,
                                    1000000u,
                                    10000000u,
                                    100000000u,
                                    1000000000u,
                                    10000000000u,
                                    100000000000u,
                                    1000000000000u,
                                    10000000000000u,
                                    100000000000000u,
                                    1000000000000000u,
                                    10000000000000000u,
                                    100000000000000000u,
                                    1000000000000000000u,
                                    10000000000000000000u};

/* m·2^e2·10^k as an integer, rounded half to even (round = 1) or truncated (0). Needs
 * m < 2^53, 0 <= k <= 22, −127 < e2 <= 1: then m·10^k < 2^127 and nothing overflows. */
static u128 scaled(uint64_t m, int e2, int k, int round)
{
    u128 P = k <= 19 ? (u128)m * POW10U[k] : (u128)m * POW10U[19] * POW10U[k - 19];
    if (e2 >= 0) return P << e2;
    int s = -e2;
    u128 q = P >> s, r = P - (q << s), half = (u128)1 << (s - 1);
    if (round && (r > half || (r == half && (q & 1u)))) ++q;
    return q;
}

/* The "%.{p}g" string of sign·D·10^(X−p+1), D having exactly p digits. */
static void layout(char *buf, int neg, uint64_t D, int p, int X)
{
    char dig[20];
    for (int i = p - 1; i >= 0; --i) {
        dig[i] = (char)('0' + (int)(D % 10u));
        D /= 10u;
    }
    int nd = p;
    while (nd > 1 && dig[nd - 1] == '0') --nd;
    char *o = buf;
    if (neg) *o++ = '-';
    if (X < -4 || X >= p) {
        *o++ = dig[0];
        if (nd > 1) {
            *o++ = '.';
            for (int i = 1; i < nd; ++i) *o++ = dig[i];
        }
        int ax = X < 0 ? -X : X;
        *o++ = 'e';
        *o++ = X < 0 ? '-' : '+';
        if (ax >= 100) *o++ = (char)('0' + ax / 100);
        *o++ = (char)('0' + ax / 10 % 10);
        *o++ = (char)('0' + ax % 10);
    } else if (X >= 0) {
        for (int i = 0; i <= X; ++i) *o++ = i < nd ? dig[i] : '0';
        if (nd > X + 1) {
            *o++ = '.';
            for (int i = X + 1; i < nd; ++i) *o++ = dig[i];
        }
    } else {
        *o++ = '0';
        *o++ = '.';
        for (int i = 0; i < -X - 1; ++i) *o++ = '0';
        for (int i = 0; i < nd; ++i) *o++ = dig[i];
    }
    *o = '\0';
}

/* 1 when sign·D·10^q reads back as v (exactly decided, see the top). */
static int reads_back(char *buf, double v, uint64_t D, int q)
{
    if (D <= ((uint64_t)1 << 53) && q >= -22 && q <= 22) {
        double d = (double)D;
        double r = q < 0 ? d / POW10[-q] : d * POW10[q];
        return r == fabs(v);
    }
    return strtod(buf, NULL) == v;
}

/* The integer path; 0 when v is outside its range (buf untouched then). */
static int fmt_exact(char buf[CLI_FMT_MAX], double v)
{
    double a = fabs(v);
    if (!(a >= 1e-6 && a < 1e16)) return 0;
    int E;
    double f = frexp(a, &E);
    uint64_t m = (uint64_t)ldexp(f, 53);
    int e2 = E - 53;
    /* X = floor(log10 a) exactly: the truncated a·10^(16−X) has 17 digits. The estimate
     * from the binary exponent (a in [2^(E−1), 2^E)) is off by at most one. */
    int X = (int)floor((E - 1) * 0.30102999566398120);
    for (int tries = 0;; ++tries) {
        if (tries > 3 || 16 - X < 0 || 16 - X > 22) return 0;
        u128 T = scaled(m, e2, 16 - X, 0);
        if (T < POW10U[16]) --X;
        else if (T >= POW10U[17]) ++X;
        else break;
    }
    for (int p = 15; p <= 17; ++p) {
        int k = p - 1 - X;
        if (k < 0 || k > 22) return 0;
        uint64_t D = (uint64_t)scaled(m, e2, k, 1); /* <= 10^17 */
        int Xp = X;
        if (D == POW10U[p]) { /* rounding carried into a new digit */
            D = POW10U[p - 1];
            ++Xp;
        }
        layout(buf, v < 0, D, p, Xp);
        if (p == 17 || reads_back(buf, v, D, Xp - p + 1)) return 1;
    }
    return 1;
}

const char *cli_fmt(char buf[CLI_FMT_MAX], double v)
{
    /* The fewest significant digits that read back to the same double: stable across runs
     * and machines, and without the noise digits of a fixed %.17g. Whole numbers (0,
     * pressures on a limit) skip the search. strfromd, not snprintf, on the printf path:
     * the same conversion without printf's format machinery, which glibc runs on its slow
     * positional path in any process with a printf hook registered (libquadmath, pulled in
     * through Ipopt's Fortran runtime, registers one). */
    if (v == 0.0 || (fabs(v) < 1e15 && v == (double)(long long)v)) {
        /* What "%.0f" prints: the integer's digits (and "-0" for negative zero). */
        long long n = (long long)v;
        uint64_t u = n < 0 ? (uint64_t)0 - (uint64_t)n : (uint64_t)n;
        char tmp[24];
        int len = 0;
        do {
            tmp[len++] = (char)('0' + (int)(u % 10u));
            u /= 10u;
        } while (u);
        char *o = buf;
        if (signbit(v)) *o++ = '-';
        while (len) *o++ = tmp[--len];
        *o = '\0';
        return buf;
    }
    if (fmt_exact(buf, v)) return buf;
    return cli_fmt_printf(buf, v);
}

const char *cli_fmt_printf(char buf[CLI_FMT_MAX], double v)
{
    strfromd(buf, CLI_FMT_MAX, "%.15g", v);
    if (strtod(buf, NULL) == v) return buf;
    strfromd(buf, CLI_FMT_MAX, "%.16g", v);
    if (strtod(buf, NULL) == v) return buf;
    strfromd(buf, CLI_FMT_MAX, "%.17g", v);
    return buf;
}
