/* Byte-level text checks (see text_check.h). */
#include "scene/text_check.h"

#include <stdint.h>
#include <string.h>

/* Length of the well-formed UTF-8 sequence at s (at most n bytes), or 0 (RFC 3629). */
static size_t utf8_seq(const unsigned char *s, size_t n)
{
    unsigned char c = s[0];
    if (c < 0x80) return 1;
    size_t len;
    unsigned char lo = 0x80, hi = 0xBF; /* allowed range of the second byte */
    if (c >= 0xC2 && c <= 0xDF) len = 2;
    else if (c >= 0xE0 && c <= 0xEF) {
        len = 3;
        if (c == 0xE0) lo = 0xA0; /* no overlong forms */
        if (c == 0xED) hi = 0x9F; /* no surrogates */
    } else if (c >= 0xF0 && c <= 0xF4) {
        len = 4;
        if (c == 0xF0) lo = 0x90;
        if (c == 0xF4) hi = 0x8F; /* nothing above U+10FFFF */
    } else return 0;
    if (n < len || s[1] < lo || s[1] > hi) return 0;
    for (size_t i = 2; i < len; ++i)
        if (s[i] < 0x80 || s[i] > 0xBF) return 0;
    return len;
}

long hpi_text_bad_byte(const char *s, size_t len, int *is_nul)
{
    const unsigned char *u = (const unsigned char *)s;
    const uint64_t ones = 0x0101010101010101u, highs = 0x8080808080808080u;
    for (size_t i = 0; i < len;) {
        if (len - i >= 8) {
            /* Eight bytes at once when all are ASCII (no high bit) and none is 0 ((w − ones)
             * & ~w & highs is non-zero exactly when some byte of w is 0): a trace or scene
             * is almost all such bytes. Otherwise one byte or sequence at a time below. */
            uint64_t w;
            memcpy(&w, u + i, sizeof w);
            if (((w & highs) | ((w - ones) & ~w & highs)) == 0) {
                i += 8;
                continue;
            }
        }
        if (u[i] == 0) {
            *is_nul = 1;
            return (long)i;
        }
        size_t k = utf8_seq(u + i, len - i);
        if (k == 0) {
            *is_nul = 0;
            return (long)i;
        }
        i += k;
    }
    return -1;
}
