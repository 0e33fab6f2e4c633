/* Allocation-free message building for the planner's two text channels (hp_planner_error,
 * hp_planner_note): hp_plan must not allocate, and printf's float formatting may. */
#include "planner/text.h"

#include <math.h>
#include <string.h>

void hpi_text_set(char *buf, const char *s)
{
    size_t n = strlen(s);
    if (n >= HP_DIAG_MAX) n = HP_DIAG_MAX - 1;
    memcpy(buf, s, n);
    buf[n] = '\0';
}

void hpi_text_add(char *buf, const char *s)
{
    size_t have = strlen(buf), n = strlen(s);
    if (have + n >= HP_DIAG_MAX) n = HP_DIAG_MAX - 1 - have;
    memcpy(buf + have, s, n);
    buf[have + n] = '\0';
}

void hpi_text_add_int(char *buf, long long v)
{
    char tmp[32], *q = tmp + sizeof tmp - 1;
    unsigned long long u = v < 0 ? 0ull - (unsigned long long)v : (unsigned long long)v;
    *q = '\0';
    do {
        *--q = (char)('0' + u % 10u);
        u /= 10u;
    } while (u);
    if (v < 0) *--q = '-';
    hpi_text_add(buf, q);
}

void hpi_text_add_num(char *buf, double v, int dec)
{
    /* The fraction's digits go into a 16-byte buffer below; no double has more than 15
     * significant decimals to print there anyway. */
    if (dec > 15) dec = 15;
    double scale = 1.0;
    for (int i = 0; i < dec; ++i) scale *= 10.0;
    if (!(fabs(v) * scale < 1e15)) {
        hpi_text_add(buf, v != v ? "nan" : "huge");
        return;
    }
    long long q = llround(fabs(v) * scale);
    if (v < 0 && q != 0) hpi_text_add(buf, "-");
    long long ip = q;
    for (int i = 0; i < dec; ++i) ip /= 10;
    hpi_text_add_int(buf, ip);
    if (dec > 0) {
        char frac[16];
        long long f = q;
        for (int i = dec - 1; i >= 0; --i) {
            frac[i] = (char)('0' + f % 10);
            f /= 10;
        }
        /* dec <= 15 (clamped above), which cppcheck does not follow. */
        // cppcheck-suppress arrayIndexOutOfBoundsCond
        frac[dec] = '\0';
        hpi_text_add(buf, ".");
        hpi_text_add(buf, frac);
    }
}
