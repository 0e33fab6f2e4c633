/* Strict decimal number parsing (see strict_number.h). */
#define _POSIX_C_SOURCE 200809L
#include "scene/strict_number.h"
#include "common/c_locale.h"

#include <errno.h>
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Grammar check first: strtod alone would accept "nan", "inf", "0x1p3" and leading spaces. */
int hpi_decimal_syntax(const char *s, size_t len)
{
    size_t i = 0, digits = 0;
    if (i < len && (s[i] == '+' || s[i] == '-')) ++i;
    while (i < len && s[i] >= '0' && s[i] <= '9') ++i, ++digits;
    if (i < len && s[i] == '.') {
        ++i;
        while (i < len && s[i] >= '0' && s[i] <= '9') ++i, ++digits;
    }
    if (digits == 0) return 0;
    if (i < len && (s[i] == 'e' || s[i] == 'E')) {
        ++i;
        if (i < len && (s[i] == '+' || s[i] == '-')) ++i;
        size_t exp_digits = 0;
        while (i < len && s[i] >= '0' && s[i] <= '9') ++i, ++exp_digits;
        if (exp_digits == 0) return 0;
    }
    return i == len;
}

/* 10^q for 0 <= q <= 22: all exact doubles. */
static const double P10[23] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                               1e8,  1e9,  1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
                               1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};

/* The value of s[0..len) (already known to be a decimal number) when it is M·10^q with an
 * integer M <= 2^53 and |q| <= 22: then M and 10^q are exact doubles and one IEEE
 * multiplication or division rounds correctly, so the result is strtod's, bit for bit
 * (Clinger's fast path). Every number of a trace written to 4 decimals is one. Returns 0
 * when it cannot decide (then strtod does). */
static int fast_decimal(const char *s, size_t len, double *out)
{
    size_t i = 0;
    int neg = 0, sig = 0, q = 0;
    unsigned long long M = 0;
    if (s[i] == '+' || s[i] == '-') neg = s[i++] == '-';
    for (int frac = 0; i < len; ++i) {
        if (s[i] == '.') {
            frac = 1;
            continue;
        }
        if (s[i] < '0' || s[i] > '9') break;
        if (sig || s[i] != '0') ++sig;
        if (sig > 16) return 0; /* M would pass 10^16 > 2^53 */
        M = 10 * M + (unsigned long long)(s[i] - '0');
        q -= frac;
    }
    if (i < len) { /* the exponent */
        ++i;
        int eneg = 0, e = 0;
        if (s[i] == '+' || s[i] == '-') eneg = s[i++] == '-';
        for (; i < len; ++i) {
            e = 10 * e + (s[i] - '0');
            if (e > 400) return 0;
        }
        q += eneg ? -e : e;
    }
    if (M > (1ull << 53) || q < -22 || q > 22) return 0;
    double v = q < 0 ? (double)M / P10[-q] : (double)M * P10[q];
    *out = neg ? -v : v;
    return 1;
}

/* The common case in one pass: [+-]digits[.digits] or [+-][digits].digits, no exponent,
 * at most 16 significant digits, M <= 2^53 and at most 22 digits after the point. Then the
 * grammar holds and the value is fast_decimal's, so strtod's (a batch trace's numbers are
 * all of this form: checking the grammar and then scanning again cost twice). Returns 0,
 * out untouched, for anything else, malformed or not: the general path decides. */
static int plain_decimal(const char *s, size_t len, double *out)
{
    size_t i = 0;
    int neg = 0, digits = 0, sig = 0, q = 0, point = 0;
    unsigned long long M = 0;
    if (s[0] == '+' || s[0] == '-') neg = s[i++] == '-';
    for (; i < len; ++i) {
        unsigned d = (unsigned)(unsigned char)s[i] - '0';
        if (d > 9) {
            if (s[i] != '.' || point) return 0;
            point = 1;
            continue;
        }
        ++digits;
        if (sig || d) ++sig;
        M = 10 * M + d;
        q -= point;
    }
    if (digits == 0 || sig > 16 || M > (1ull << 53) || q < -22) return 0;
    double v = (double)M / P10[-q];
    *out = neg ? -v : v;
    return 1;
}

double hpi_c_strtod(const char *s, char **end)
{
    /* The program's LC_NUMERIC is not ours to change (a Python or GUI host may set it), and
     * under a comma locale strtod stops at the '.' of "77.5". */
    hp_c_numeric c;
    hpi_c_numeric_begin(&c);
    errno = 0;
    double v = strtod(s, end);
    hpi_c_numeric_end(&c);
    return v;
}

const char *hpi_strict_double(const char *s, size_t len, double *out)
{
    char buf[128];
    if (!s || len == 0) return "empty where a number is expected";
    if (len < sizeof buf && plain_decimal(s, len, out)) return NULL;
    if (len >= sizeof buf || !hpi_decimal_syntax(s, len)) return "not a number";
    if (fast_decimal(s, len, out)) return NULL;
    memcpy(buf, s, len);
    buf[len] = '\0';
    char *end = NULL;
    double v = hpi_c_strtod(buf, &end);
    if (end != buf + len) return "not a number";
    if (errno == ERANGE && fabs(v) > 1.0) return "overflows a double";
    if (errno == ERANGE || (v != 0.0 && fabs(v) < DBL_MIN)) return "too small for a double";
    if (!isfinite(v)) return "not finite";
    *out = v;
    return NULL;
}

/* A scan of the JSON text, not of jansson's values: by then 1e-400 is 0, indistinguishable
 * from a written 0, and jansson's own overflow message names no key. */
long hpi_json_out_of_range(const char *s, size_t len, const char **key, size_t *klen,
                           const char **why)
{
    const char *last = "", *str = NULL;
    size_t last_len = 0;
    for (size_t i = 0; i < len; ++i) {
        char c = s[i];
        if (str) { /* inside a string */
            if (c == '\\') ++i;
            else if (c == '"') {
                last = str;
                last_len = (size_t)(s + i - str);
                str = NULL;
            }
        } else if (c == '"') {
            str = s + i + 1;
        } else if (c == '-' || (c >= '0' && c <= '9')) {
            size_t j = i;
            while (j < len && strchr("0123456789+-.eE", s[j]) && s[j]) ++j;
            double v;
            const char *r = hpi_strict_double(s + i, j - i, &v);
            if (r && (strcmp(r, "too small for a double") == 0 ||
                      strcmp(r, "overflows a double") == 0)) {
                *why = r;
                int plain = last_len > 0 && last_len <= 64; /* echoed: printable only */
                for (size_t k = 0; k < last_len && plain; ++k)
                    plain = last[k] >= 0x20 && last[k] < 0x7f;
                *key = plain ? last : "value";
                *klen = plain ? last_len : 5;
                return (long)i;
            }
            i = j - 1;
        }
    }
    return -1;
}
