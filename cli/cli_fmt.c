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
 *     IEEE multiplication or division rounds correctly: Clinger's fast path), else by
 *     comparing it with the ends of v's rounding interval in integers (reads_back_exact),
 *     and only outside that range by strtod;
 *   - the three roundings come from one 128-bit product (round_digits), and only the
 *     chosen string is laid out;
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

/* m·2^e2·10^k = q + f with q an integer and 0 <= f < 1: returns q and sets *frac to the
 * class of f (−1: f < 1/2 but not 0, −2: f = 0, 0: f = 1/2, 1: f > 1/2). Needs m < 2^53,
 * 0 <= k <= 22, −127 < e2 <= 1: then m·10^k < 2^127 and nothing overflows. */
static u128 scaled(uint64_t m, int e2, int k, int *frac)
{
    u128 P = k <= 19 ? (u128)m * POW10U[k] : (u128)m * POW10U[19] * POW10U[k - 19];
    if (e2 >= 0) {
        *frac = -2;
        return P << e2;
    }
    int s = -e2;
    u128 q = P >> s, r = P - (q << s), half = (u128)1 << (s - 1);
    *frac = r == 0 ? -2 : r < half ? -1 : r == half ? 0 : 1;
    return q;
}

/* The p = 17 − j significant digits of q + f (q of 17 digits, f of class frac as scaled
 * gives it), rounded half to even: exactly what rounding m·2^e2·10^(k−j) gives, without a
 * second 128-bit product. */
static uint64_t round_digits(uint64_t q, int frac, int j)
{
    if (j == 0) return q + (frac == 1 || (frac == 0 && (q & 1u)));
    uint64_t t = q / POW10U[j], rem = q % POW10U[j], half = POW10U[j] / 2;
    int up = rem > half || (rem == half && (frac != -2 || (t & 1u)));
    return t + (uint64_t)up;
}

/* "00".."99": two digits per division by 100. */
static const char DIGITS2[201] = "00010203040506070809101112131415161718192021222324252627282930"
                                 "31323334353637383940414243444546474849505152535455565758596061"
                                 "62636465666768697071727374757677787980818283848586878889909192"
                                 "93949596979899";

/* The "%.{p}g" string of sign·D·10^(X−p+1), D having exactly p digits. */
static void layout(char *buf, int neg, uint64_t D, int p, int X)
{
    char dig[20];
    /* The last 8 digits and the rest (7 to 9: p is 15 to 17 here) in 32-bit arithmetic. */
    uint32_t lo = (uint32_t)(D % 100000000u), hi = (uint32_t)(D / 100000000u);
    int i = p;
    for (int j = 0; j < 4; ++j) {
        uint32_t r = lo % 100u;
        lo /= 100u;
        dig[--i] = DIGITS2[2 * r + 1];
        dig[--i] = DIGITS2[2 * r];
    }
    while (i >= 2) {
        uint32_t r = hi % 100u;
        hi /= 100u;
        dig[--i] = DIGITS2[2 * r + 1];
        dig[--i] = DIGITS2[2 * r];
    }
    if (i) dig[0] = (char)('0' + (int)hi);
    int nd = p;
    while (nd > 1 && dig[nd - 1] == '0') --nd;
    char *o = buf;
    if (neg) *o++ = '-';
    if (X < -4 || X >= p) {
        *o++ = dig[0];
        if (nd > 1) {
            *o++ = '.';
            memcpy(o, dig + 1, (size_t)(nd - 1));
            o += nd - 1;
        }
        int ax = X < 0 ? -X : X;
        *o++ = 'e';
        *o++ = X < 0 ? '-' : '+';
        if (ax >= 100) *o++ = (char)('0' + ax / 100);
        *o++ = (char)('0' + ax / 10 % 10);
        *o++ = (char)('0' + ax % 10);
    } else if (X >= 0) {
        for (int j = 0; j <= X; ++j) *o++ = j < nd ? dig[j] : '0';
        if (nd > X + 1) {
            *o++ = '.';
            memcpy(o, dig + X + 1, (size_t)(nd - X - 1));
            o += nd - X - 1;
        }
    } else {
        *o++ = '0';
        *o++ = '.';
        for (int j = 0; j < -X - 1; ++j) *o++ = '0';
        memcpy(o, dig, (size_t)nd);
        o += nd;
    }
    *o = '\0';
}

/* Whether sign·D·10^q reads back as v: 1 or 0 when decided exactly without a string (see
 * the top), −1 when strtod must decide. */
static int reads_back_fast(double v, uint64_t D, int q)
{
    if (!(D <= ((uint64_t)1 << 53) && q >= -22 && q <= 22)) return -1;
    double d = (double)D;
    double r = q < 0 ? d / POW10[-q] : d * POW10[q];
    return r == fabs(v);
}

/* Whether D·10^q (−22 <= q <= 0, D < 2^55) reads back as a = m·2^e2 (2^52 <= m < 2^53,
 * −80 < e2 <= 1), decided exactly where reads_back_fast cannot (D > 2^53): it does when it
 * lies inside a's rounding interval, whose ends (half-way to the neighbouring doubles) go
 * to the even mantissa. With B·2^t an end, the comparison D·10^q : B·2^t is made on
 * integers as D·2^(q−t) : B·5^(−q), both below 2^115. Returns −1 outside these ranges
 * (then strtod decides). */
static int reads_back_exact(uint64_t m, int e2, uint64_t D, int q)
{
    if (q > 0 || q < -22 || D >= ((uint64_t)1 << 55) || e2 <= -80 || e2 > 1) return -1;
    u128 five = 1;
    for (int i = 0; i < -q; ++i) five *= 5u;
    /* Upper end (2m+1)·2^(e2−1); lower end (2m−1)·2^(e2−1), or (4m−1)·2^(e2−2) when m is
     * a power of two (the double below is closer). */
    const int pow2 = m == ((uint64_t)1 << 52);
    const uint64_t Bhi = 2 * m + 1, Blo = pow2 ? 4 * m - 1 : 2 * m - 1;
    const int thi = e2 - 1, tlo = pow2 ? e2 - 2 : e2 - 1;
    int cmp[2];
    for (int side = 0; side < 2; ++side) {
        uint64_t B = side ? Bhi : Blo;
        int sh = q - (side ? thi : tlo); /* 0..54 for every v of the integer path */
        if (sh < -8 || sh > 60) return -1;  /* L < 2^115, R < 2^115: no overflow */
        u128 L = D, R = (u128)B * five;
        if (sh >= 0) L <<= sh;
        else R <<= -sh;
        cmp[side] = L < R ? -1 : L > R;
    }
    int even = (m & 1u) == 0;
    return (cmp[0] > 0 || (cmp[0] == 0 && even)) && (cmp[1] < 0 || (cmp[1] == 0 && even));
}

/* The integer path; 0 when v is outside its range (buf untouched then). */
static int fmt_exact(char buf[CLI_FMT_MAX], double v)
{
    double a = fabs(v);
    if (!(a >= 1e-6 && a < 1e16)) return 0;
    /* a = m·2^e2 with 2^52 <= m < 2^53 (a is normal here): the bits themselves. */
    uint64_t bits;
    memcpy(&bits, &a, sizeof bits);
    int be = (int)(bits >> 52);
    uint64_t m = (bits & (((uint64_t)1 << 52) - 1)) | ((uint64_t)1 << 52);
    int e2 = be - 1075, E = e2 + 53; /* a in [2^(E−1), 2^E) */
    /* X = floor(log10 a) exactly: the truncated a·10^(16−X) has 17 digits. The estimate
     * from the binary exponent is off by at most one. */
    int X = (int)floor((E - 1) * 0.30102999566398120), frac = 0;
    uint64_t T;
    for (int tries = 0;; ++tries) {
        if (tries > 3 || 16 - X < 0 || 16 - X > 22) return 0;
        u128 T128 = scaled(m, e2, 16 - X, &frac);
        if (T128 < POW10U[16]) --X;
        else if (T128 >= POW10U[17]) ++X;
        else {
            T = (uint64_t)T128;
            break;
        }
    }
    /* The shortest p that reads back, decided on the digits; only that string is laid out
     * (and the candidates strtod must decide). */
    for (int p = 15; p <= 17; ++p) {
        if (p - 1 - X < 0) return 0;
        uint64_t D = round_digits(T, frac, 17 - p); /* <= 10^17 */
        int Xp = X;
        if (D == POW10U[p]) { /* rounding carried into a new digit */
            D = POW10U[p - 1];
            ++Xp;
        }
        int ok = p == 17 ? 1 : reads_back_fast(v, D, Xp - p + 1);
        if (ok < 0) ok = reads_back_exact(m, e2, D, Xp - p + 1);
        if (ok == 0) continue;
        layout(buf, v < 0, D, p, Xp);
        if (ok == 1 || strtod(buf, NULL) == v) return 1;
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
