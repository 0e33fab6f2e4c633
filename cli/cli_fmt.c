/* cli_fmt: the shortest of "%.15g", "%.16g", "%.17g" that reads back to the same double.
 *
 * Printing ~60 numbers a row was most of a batch row's time: glibc's printf makes each
 * digit string with multi-precision arithmetic, and the search needs up to three of them
 * and two strtod calls. For |v| in [1e-6, 1e16) that is not a whole number below 1e15
 * (every pose, radius, pressure and stretch a plan returns) the same string comes from
 * exact integer arithmetic in 64 and 128 bits (cli_fmt_exact), without printf or strtod.
 *
 * Why the strings are the definition's, step by step. Write |v| = m·2^e2 (2^52 <= m < 2^53,
 * v is normal here), n2 = floor(log2|v|) and k = 16 − floor(n2·log10 2), 1 to 23 here.
 *   1. The scaled value. |v|·10^k = m·5^k·2^(e2+k) = P/2^s with P = m·5^k (< 2^107, an
 *      exact 128-bit product; 5^k < 2^54 comes from the POW5 table) and s = −(e2+k) (made
 *      at least 1 by shifting P left, by at most 3, for the few |v| >= 2^51). So T =
 *      floor(P/2^s) and the remainder r = P mod 2^s are exact; T has 17 or 18 digits
 *      because floor(log10|v|) is k's estimate or one more (checked, never assumed).
 *   2. The candidates. "%.{p}g" prints |v| rounded to p significant digits, correctly and
 *      half to even (glibc rounds the exact binary value in the current rounding mode,
 *      to nearest by default). With j = digits(T) − p, that is (T + r/2^s)/10^j rounded
 *      half to even: the quotient and remainder of T by 10^j (a constant divisor) and, on
 *      a tie of the remainder, whether r is 0 decide it exactly (round_at).
 *   3. Reading back. strtod also rounds correctly to nearest, ties to even, so a
 *      candidate C reads back as v exactly when it lies in v's rounding interval: within
 *      half the gap to each neighbouring double, the ends included when m is even. In
 *      units of 2^−s the gap above v is W = 5^k (times 2^shift of step 1), the gap below
 *      W too, or W/2 when m = 2^52 (the double below is closer); C's distance to v is
 *      (10^j − rem)·2^s − r above or rem·2^s + r below, all below 2^64 (s <= 53, j <= 3,
 *      the distance is at most half of 10^j). So the read-back test is two integer
 *      comparisons; 17 digits always read back. (In this range no output depends on the
 *      ends' rule or on the narrower side below 2^n: a midpoint between two doubles here
 *      has more than 16 significant digits, or is an odd integer above 2^53 where the
 *      16-digit candidate is v itself and the 15-digit one a multiple of ten; and no
 *      15- or 16-digit candidate of a power of two falls between the two sides' widths
 *      (checked with exact fractions). The exact rule is kept all the same; mutating it
 *      therefore fails no test.) The first p of 15, 16, 17 whose candidate reads back
 *      gives the definition's string.
 *   4. The layout is %g's: the exponent X of the rounded value (a carry to 10^p adds
 *      one), exponent form when X < −4 or X >= p (at least two exponent digits), else
 *      fixed, trailing zeros removed. The digits come eight at a time (put8: two halves,
 *      then four pairs, then eight digits in the lanes of one 64-bit word) into a
 *      fixed-size scratch, and the string is assembled with fixed-size copies.
 * A shortest-digit algorithm (Ryu, Schubfach) would give the same strings only by an
 * argument of its own (at most 15 shortest digits are "%.15g"'s without its trailing
 * zeros; its closest candidate of 16 digits is "%.16g"'s except perhaps on the narrow side
 * below a power of two) and needs approximated powers of ten; in this range the exact
 * product with 5^k computes the definition's own candidates instead.
 * Anything else (0, whole numbers below 1e15 printed as integers, non-finite, tiny or
 * huge magnitudes) takes the printf path. tests/cli/test_cli_fmt.c compares both paths
 * string for string on millions of doubles, with every binary exponent of this range. */
#define __STDC_WANT_IEC_60559_BFP_EXT__ 1 /* strfromd (ISO/IEC TS 18661-1, glibc >= 2.25) */
#include "cli/cli_args.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

__extension__ typedef unsigned __int128 u128;

/* The integer path is a handful of small steps; the compiler's own inlining budget left
 * calls (and register saves) between them. */
#if defined(__GNUC__)
#define FMT_INLINE static inline __attribute__((always_inline))
#else
#define FMT_INLINE static inline
#endif

/* 5^k, 0 <= k <= 23 (k's range here; 5^23 < 2^54). */
static const uint64_t POW5[24] = {UINT64_C(1),
                                  UINT64_C(5),
                                  UINT64_C(25),
                                  UINT64_C(125),
                                  UINT64_C(625),
                                  UINT64_C(3125),
                                  UINT64_C(15625),
                                  UINT64_C(78125),
                                  UINT64_C(390625),
                                  UINT64_C(1953125),
                                  UINT64_C(9765625),
                                  UINT64_C(48828125),
                                  UINT64_C(244140625),
                                  UINT64_C(1220703125),
                                  UINT64_C(6103515625),
                                  UINT64_C(30517578125),
                                  UINT64_C(152587890625),
                                  UINT64_C(762939453125),
                                  UINT64_C(3814697265625),
                                  UINT64_C(19073486328125),
                                  UINT64_C(95367431640625),
                                  UINT64_C(476837158203125),
                                  UINT64_C(2384185791015625),
                                  UINT64_C(11920928955078125)};

#define E8 UINT64_C(100000000)
#define E15 UINT64_C(1000000000000000)
#define E16 UINT64_C(10000000000000000)
#define E17 UINT64_C(100000000000000000)
#define E18 UINT64_C(1000000000000000000)

/* |v|·10^k = (T + r/2^s) exactly (step 1 of the top), with what the read-back test needs. */
typedef struct scaled {
    uint64_t T, r; /* 10^16 <= T < 10^18, r < 2^s */
    int s;         /* 1..53 */
    uint64_t W;    /* the gap to the next double above, in units of 2^−s */
    int even;      /* m even: the interval's ends read back */
    int pow2;      /* m = 2^52: the gap below is W/2 */
} scaled;

/* T + r/2^s rounded half to even to a multiple of pj = 10^j (j = 0..3; pj a constant
 * where inlined): returns the quotient and sets *in to whether quotient·pj reads back
 * (steps 2 and 3 of the top). */
FMT_INLINE uint64_t round_at(const scaled *x, uint64_t pj, int *in)
{
    uint64_t t = x->T / pj, rem = x->T - t * pj;
    /* The part of T + r/2^s above t·pj, and pj, in units of 2^−s: below 1000·2^53. */
    uint64_t frac = (rem << x->s) + x->r, unit = pj << x->s;
    int up = 2 * frac > unit || (2 * frac == unit && (t & 1u));
    uint64_t d = up ? unit - frac : frac;         /* the distance to v, at most unit/2 */
    uint64_t d2 = !up && x->pow2 ? 4 * d : 2 * d; /* 4d <= 2·unit < 2^64 */
    *in = d2 < x->W || (d2 == x->W && x->even);
    return t + (uint64_t)up;
}

/* The first of the 15-, 16- and 17-digit candidates that reads back (17 always does),
 * from T's last j15, j15 − 1, j15 − 2 digits rounded off (pj15 = 10^j15, 100 or 1000);
 * sets *p to its digit count. The 16-digit candidate is tried first: unless m = 2^52, v's
 * rounding interval is symmetric, and the 15-digit candidate is also a 16-digit decimal
 * no nearer to v than the 16-digit one, so when the 16-digit one does not read back
 * neither does the 15-digit one (about half of all results need 17 digits). */
FMT_INLINE uint64_t first_reading_back(const scaled *x, uint64_t pj15, int *p)
{
    int in16, in15;
    uint64_t D16 = round_at(x, pj15 / 10, &in16);
    if (in16 || x->pow2) {
        uint64_t D15 = round_at(x, pj15, &in15);
        if (in15) {
            *p = 15;
            return D15;
        }
    }
    if (in16) {
        *p = 16;
        return D16;
    }
    *p = 17;
    return round_at(x, pj15 / 100, &in16);
}

/* Writes the eight decimal digits of n < 10^8, most significant first: n splits into two
 * halves of four digits, each half into two pairs, each pair into two digits, all lanes
 * of one 64-bit word at a time (the first digits in the low lanes). Division by 100 of a
 * lane below 10^4 is (y·5243) >> 19 and by 10 of a lane below 100 is (y·103) >> 10, both
 * exact over those ranges (tests/cli/test_cli_fmt.c checks every y) and without carries
 * between lanes (y·5243 < 2^26, y·103 < 2^14). */
FMT_INLINE void put8(char *o, uint32_t n)
{
    uint64_t hi = n / 10000u, x = hi | (uint64_t)(n - hi * 10000u) << 32;
    uint64_t q = ((x * 5243u) >> 19) & UINT64_C(0x0000007F0000007F);
    x = q | (x - q * 100u) << 16;
    q = ((x * 103u) >> 10) & UINT64_C(0x000F000F000F000F);
    x = (q | (x - q * 10u) << 8) + UINT64_C(0x3030303030303030);
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
    memcpy(o, &x, 8);
#else
    for (int i = 0; i < 8; ++i) o[i] = (char)(x >> 8 * i);
#endif
}

/* The "%.{p}g" string of sign·D·10^(X−p+1), D having exactly p digits (15 to 17); returns
 * its length. */
FMT_INLINE size_t layout(char buf[CLI_FMT_MAX], int neg, uint64_t D, int p, int X)
{
    /* D's digits, left-padded with zeros to 17, then filler the fixed-size copies below
     * read (up to dig + 32). */
    char dig[32];
    uint64_t top = D / E16, rest = D - top * E16, mid = rest / E8;
    dig[0] = (char)('0' + (int)top);
    put8(dig + 1, (uint32_t)mid);
    put8(dig + 9, (uint32_t)(rest - mid * E8));
    memset(dig + 17, '0', sizeof dig - 17);
    const char *d = dig + 17 - p;
    int nd = p;
    while (nd > 1 && d[nd - 1] == '0') --nd;
    char *o = buf;
    *o = '-';
    o += neg;
    if (X >= 0 && X < p && X <= 13) {
        /* Fixed, X + 1 <= 14 integer digits, at most 16 after the point: o + X + 18 <= buf
         * + 32. The fraction's copy overwrites the integer copy's surplus. */
        memcpy(o, d, 16);
        if (nd > X + 1) {
            o[X + 1] = '.';
            memcpy(o + X + 2, d + X + 1, 16);
            o += nd + 1;
        } else {
            o += X + 1;
        }
    } else if (X < 0 && X >= -4) {
        /* "0." and −X − 1 zeros, then the digits (the 24-byte copy ends by buf + 30). */
        memcpy(o, "0.000", 6);
        memcpy(o + 1 - X, d, 24);
        o += 1 - X + nd;
    } else if (X < -4 || X >= p) {
        *o++ = d[0];
        if (nd > 1) {
            *o++ = '.';
            memcpy(o, d + 1, (size_t)(nd - 1));
            o += nd - 1;
        }
        int ax = X < 0 ? -X : X;
        *o++ = 'e';
        *o++ = X < 0 ? '-' : '+';
        if (ax >= 100) *o++ = (char)('0' + ax / 100);
        *o++ = (char)('0' + ax / 10 % 10);
        *o++ = (char)('0' + ax % 10);
    } else { /* fixed, 15 to 17 integer digits */
        for (int j = 0; j <= X; ++j) *o++ = d[j];
        if (nd > X + 1) {
            *o++ = '.';
            memcpy(o, d + X + 1, (size_t)(nd - X - 1));
            o += nd - X - 1;
        }
    }
    *o = '\0';
    return (size_t)(o - buf);
}

/* cli_fmt_exact's work (inlined into cli_fmt_len); returns the string's length, 0 when v
 * is outside the range. */
FMT_INLINE size_t fmt_exact(char buf[CLI_FMT_MAX], double v)
{
    double a = fabs(v);
    if (!(a >= 1e-6 && a < 1e16)) return 0;
    uint64_t bits;
    memcpy(&bits, &a, sizeof bits);
    const uint64_t hidden = (uint64_t)1 << 52;
    const int be = (int)(bits >> 52);
    const uint64_t m = (bits & (hidden - 1)) | hidden;
    const int e2 = be - 1075, n2 = be - 1023; /* |v| = m·2^e2 in [2^n2, 2^(n2+1)) */
    /* floor(n2·log10 2) as floor(n2·78913/2^18) (exact for |n2| < 1000), kept
     * non-negative before the shift by adding 400·2^18. Were it off, the safeguards below
     * would send v to the printf path: tests/cli/test_cli_fmt.c asserts that this path
     * takes every binary exponent of the range. */
    const int est = (int)(((int64_t)n2 * 78913 + ((int64_t)400 << 18)) >> 18) - 400;
    const int k = 16 - est, sh = -(e2 + k);
    if (k < 0 || k > 23 || sh > 53 || sh < -2) return 0; /* never in range: a safeguard */
    scaled x = {0, 0, sh, POW5[k], (m & 1u) == 0, m == hidden};
    if (sh >= 1) {
        /* P = m·5^k in two 64-bit halves; T = P >> s needs shifts by 1..63 only. */
        u128 P = (u128)m * POW5[k];
        uint64_t hi = (uint64_t)(P >> 64), lo = (uint64_t)P;
        if (hi >> sh) return 0; /* T >= 2^64: a safeguard, never in range */
        x.T = hi << (64 - sh) | lo >> sh;
        x.r = lo & (((uint64_t)1 << sh) - 1);
    } else {
        /* |v| >= 2^51, k = 1: |v|·10 = m·5·2^(−sh) is a whole number below 2^58. (Every
         * candidate here is v itself or at least a gap away from it: no output depends on
         * W's exact value.) */
        if (k > 1) return 0; /* a safeguard */
        x.T = (m * POW5[k]) << -sh;
        x.s = 1;
        x.W = POW5[k] << (1 - sh);
    }
    if (x.T < E16 || x.T >= E18) return 0; /* a safeguard too */
    /* T of 17 digits: v's decimal exponent is 16 − k; of 18: 17 − k. */
    int p, X = x.T < E17 ? 16 - k : 17 - k;
    uint64_t D = x.T < E17 ? first_reading_back(&x, 100, &p) : first_reading_back(&x, 1000, &p);
    if (D == (p == 15 ? E15 : p == 16 ? E16 : E17)) { /* rounding carried into a new digit */
        D /= 10;
        ++X;
    }
    return layout(buf, v < 0, D, p, X);
}

int cli_fmt_exact(char buf[CLI_FMT_MAX], double v) { return fmt_exact(buf, v) != 0; }

const char *cli_fmt(char buf[CLI_FMT_MAX], double v)
{
    cli_fmt_len(buf, v);
    return buf;
}

size_t cli_fmt_len(char buf[CLI_FMT_MAX], double v)
{
    /* The fewest significant digits that read back to the same double: stable across runs
     * and machines, and without the noise digits of a fixed %.17g. Whole numbers (0,
     * pressures on a limit) skip the search. strfromd, not snprintf, on the printf path:
     * the same conversion without printf's format machinery, which glibc runs on its slow
     * positional path in any process with a printf hook registered (libquadmath, pulled in
     * through Ipopt's Fortran runtime, registers one). */
    if (v == 0.0) { /* a quarter of a batch row's numbers (errors, uncommanded motion) */
        char *o = buf;
        if (signbit(v)) *o++ = '-';
        o[0] = '0';
        o[1] = '\0';
        return (size_t)(o - buf) + 1;
    }
    if (fabs(v) < 1e15 && v == (double)(long long)v) {
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
        return (size_t)(o - buf);
    }
    size_t n = fmt_exact(buf, v);
    return n ? n : strlen(cli_fmt_printf(buf, v));
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
