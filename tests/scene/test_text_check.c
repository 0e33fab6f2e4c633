/* hpi_text_bad_byte (scene/text_check.c), whose clean ASCII goes eight bytes at a time: a
 * NUL, a stray byte, a broken or disallowed sequence at every offset of a line longer than
 * several words (first, inside and last byte of a word, in the tail after the last whole
 * word) is found at its own offset with its kind; well-formed multi-byte characters at every
 * offset are not. */
#include "support/test_util.h"
#include "scene/text_check.h"

#include <string.h>

enum { LEN = 45 }; /* five words of eight and a tail of five */

/* An ASCII line of LEN bytes with the len bytes of seq at offset at. */
static void line_with(char *buf, size_t at, const char *seq, size_t len)
{
    for (size_t i = 0; i < LEN; ++i) buf[i] = (char)('a' + i % 26);
    memcpy(buf + at, seq, len);
}

static void expect(const char *buf, size_t len, long want, int want_nul, const char *what,
                   size_t at)
{
    int nul = -1;
    long got = hpi_text_bad_byte(buf, len, &nul);
    if (got != want) fail_msg("%s at %zu: found at %ld, want %ld", what, at, got, want);
    if (want >= 0 && nul != want_nul) fail_msg("%s at %zu: is_nul %d", what, at, nul);
}

static void test_every_offset(void **state)
{
    (void)state;
    char buf[LEN];
    for (size_t i = 0; i < LEN; ++i) buf[i] = (char)('a' + i % 26);
    expect(buf, LEN, -1, 0, "clean", 0);
    for (size_t at = 0; at < LEN; ++at) {
        line_with(buf, at, "\0", 1);
        expect(buf, LEN, (long)at, 1, "NUL", at);
        line_with(buf, at, "\xff", 1);
        expect(buf, LEN, (long)at, 0, "0xFF", at);
        line_with(buf, at, "\x80", 1); /* a continuation byte on its own */
        expect(buf, LEN, (long)at, 0, "0x80", at);
        line_with(buf, at, "\x7f", 1); /* DEL is ASCII and allowed */
        expect(buf, LEN, -1, 0, "DEL", at);
        if (at + 2 <= LEN) {
            line_with(buf, at, "\xc3\xa9", 2); /* é */
            expect(buf, LEN, -1, 0, "U+00E9", at);
            line_with(buf, at, "\xc0\xaf", 2); /* overlong '/' */
            expect(buf, LEN, (long)at, 0, "overlong", at);
            line_with(buf, at, "\xc3\x28", 2); /* lead byte without its continuation */
            expect(buf, LEN, (long)at, 0, "broken pair", at);
        }
        if (at + 3 <= LEN) {
            line_with(buf, at, "\xe2\x82\xac", 3); /* € */
            expect(buf, LEN, -1, 0, "U+20AC", at);
            line_with(buf, at, "\xed\xa0\x80", 3); /* a surrogate */
            expect(buf, LEN, (long)at, 0, "surrogate", at);
        }
        if (at + 4 <= LEN) {
            line_with(buf, at, "\xf0\x9f\x98\x80", 4); /* U+1F600 */
            expect(buf, LEN, -1, 0, "U+1F600", at);
            line_with(buf, at, "\xf4\x90\x80\x80", 4); /* above U+10FFFF */
            expect(buf, LEN, (long)at, 0, "above U+10FFFF", at);
        }
    }
    /* A sequence cut by the end of the text. */
    line_with(buf, LEN - 2, "\xe2\x82", 2);
    expect(buf, LEN, LEN - 2, 0, "cut sequence", LEN - 2);
    /* The first of two problems is the one reported. */
    line_with(buf, 20, "\xff", 1);
    buf[9] = '\0';
    expect(buf, LEN, 9, 1, "first of two", 9);
}

int main(void)
{
    const struct CMUnitTest tests[] = {cmocka_unit_test(test_every_offset)};
    return cmocka_run_group_tests(tests, NULL, NULL);
}
