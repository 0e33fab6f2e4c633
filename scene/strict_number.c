/* Strict decimal number parsing (see strict_number.h). */
#define _POSIX_C_SOURCE 200809L
#include "scene/strict_number.h"

#include <errno.h>
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Grammar check first: strtod alone would accept "nan", "inf", "0x1p3" and leading spaces. */
int hp_decimal_syntax(const char *s, size_t len)
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

const char *hp_strict_double(const char *s, size_t len, double *out)
{
    char buf[128];
    if (!s || len == 0) return "empty where a number is expected";
    if (len >= sizeof buf || !hp_decimal_syntax(s, len)) return "not a number";
    memcpy(buf, s, len);
    buf[len] = '\0';
    errno = 0;
    char *end = NULL;
    double v = strtod(buf, &end);
    if (end != buf + len) return "not a number";
    if (errno == ERANGE && fabs(v) > 1.0) return "overflows a double";
    if (errno == ERANGE || (v != 0.0 && fabs(v) < DBL_MIN)) return "too small for a double";
    if (!isfinite(v)) return "not finite";
    *out = v;
    return NULL;
}
