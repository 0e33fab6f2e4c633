/* cli_gptext: the one way text enters a gnuplot script, checked against gnuplot itself.
 * test_quote_round_trip: 3000 seeded random strings of every byte but the control
 * characters, each salted with what gnuplot treats specially (quotes, runs of them and a
 * leading one, backslash, backquote, '@', '!', '$(', "system(", "EOD"), are written by
 * gp_quote into one script of `print` lines; gnuplot must print every one back byte for
 * byte, and the payloads `touch CANARY` inside them must not run. Skipped (not failed)
 * when gnuplot is not installed, as the command-line tests of render and plot are.
 * test_quote_refuses_control: every control byte at every place of a string is refused, and
 * nothing is written. test_label: every single byte and a few sequences against the
 * expected script text, written out here by hand. test_path: file names, relative ones
 * behind "./". */
#define _POSIX_C_SOURCE 200809L
#include "support/test_util.h"

#include "cli/cli_gptext.h"

#include <ctype.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static uint64_t rng = 0x2545F4914F6CDD1Du;
static uint64_t next(void)
{
    rng ^= rng << 13;
    rng ^= rng >> 7;
    rng ^= rng << 17;
    return rng;
}

/* What f received, as a NUL-terminated string (the caller frees it). */
static char *written(void (*put)(FILE *, const char *), int (*quote)(FILE *, const char *),
                     const char *s, int *rc)
{
    char *buf = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&buf, &len);
    assert_non_null(f);
    *rc = 0;
    if (put) put(f, s);
    else *rc = quote(f, s);
    fclose(f);
    return buf;
}

enum { N_STRINGS = 3000 };

static void test_quote_round_trip(void **state)
{
    (void)state;
    if (system("gnuplot --version >/dev/null 2>&1") != 0) {
        print_message("gnuplot not installed: the round trip is not checked\n");
        skip();
    }
    static const char *const salt[] = {"'",
                                       "''",
                                       "\\",
                                       "`touch CANARY`",
                                       "@x",
                                       "!touch CANARY",
                                       "system(\"touch CANARY\")",
                                       "EOD",
                                       "\"",
                                       "$(",
                                       "'''x",
                                       "a''''b",
                                       "{}"};
    char dir[] = "/tmp/hp_gptext_XXXXXX";
    assert_non_null(mkdtemp(dir));
    char script[256], out[256], canary[256], cmd[1024];
    snprintf(script, sizeof script, "%s/q.gp", dir);
    snprintf(out, sizeof out, "%s/out", dir);
    snprintf(canary, sizeof canary, "%s/CANARY", dir);
    char(*s)[64] = calloc(N_STRINGS, sizeof *s);
    assert_non_null(s);
    FILE *f = fopen(script, "w");
    assert_non_null(f);
    fprintf(f, "set print '-'\n");
    for (int i = 0; i < N_STRINGS; ++i) {
        size_t n = 0;
        int len = (int)(next() % 24);
        for (int k = 0; k < len; ++k) {
            if (next() % 4 == 0) {
                const char *x = salt[next() % (sizeof salt / sizeof *salt)];
                if (n + strlen(x) < sizeof s[i] - 1 && !strchr(x, '\n')) {
                    memcpy(s[i] + n, x, strlen(x));
                    n += strlen(x);
                }
            } else {
                unsigned char c = (unsigned char)(0x20 + next() % (0x100 - 0x20));
                if (c != 0x7f && n < sizeof s[i] - 1) s[i][n++] = (char)c;
            }
        }
        s[i][n] = '\0';
        fprintf(f, "print ");
        assert_int_equal(gp_quote(f, s[i]), 0);
        fprintf(f, "\n");
    }
    assert_int_equal(fclose(f), 0);
    /* In the folder of the canary: a payload that ran would create it there. */
    snprintf(cmd, sizeof cmd, "cd '%s' && LC_ALL=C gnuplot q.gp >out 2>err", dir);
    assert_int_equal(system(cmd), 0);
    struct stat st;
    assert_int_not_equal(stat(canary, &st), 0); /* no payload ran */
    FILE *in = fopen(out, "rb");
    assert_non_null(in);
    char line[256];
    for (int i = 0; i < N_STRINGS; ++i) {
        assert_non_null(fgets(line, sizeof line, in));
        line[strcspn(line, "\n")] = '\0';
        if (strcmp(line, s[i]) != 0)
            fail_msg("string %d printed back as '%s', not '%s'", i, line, s[i]);
    }
    assert_null(fgets(line, sizeof line, in)); /* nothing more */
    fclose(in);
    free(s);
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    assert_int_equal(system(cmd), 0);
}

static void test_quote_refuses_control(void **state)
{
    (void)state;
    for (int c = 1; c < 0x100; ++c) {
        int control = c < 0x20 || c == 0x7f;
        for (int at = 0; at < 3; ++at) {
            char s[4] = "ab";
            memmove(s + at + 1, s + at, strlen(s + at) + 1);
            s[at] = (char)c;
            int rc;
            char *w = written(NULL, gp_quote, s, &rc);
            assert_int_equal(gp_control_byte(s), control ? at : -1);
            assert_int_equal(rc, control ? -1 : 0);
            if (control) assert_string_equal(w, ""); /* nothing written */
            free(w);
        }
    }
}

static void test_label(void **state)
{
    (void)state;
    static const struct {
        const char *in, *out;
    } cases[] = {
        {"plain_name-1.png", "\"plain_name-1.png\""},
        {"it's", "\"it\\0047s\""},
        {"'1", "\"\\00471\""}, /* a digit after an escape is not read into it */
        {"a\nb\rc\td\x7f"
         "e",
         "\"a?b?c?d?e\""},
        {"\xff\xfe", "\"?"
                     "?\""},
        {"caf\xc3\xa9", "\"caf\\0303\\0251\""}, /* é: well-formed, kept */
        {"\xc3(", "\"?(\""},                    /* a cut sequence */
        {"\xed\xa0\x80", "\"?"
                         "?"
                         "?\""}, /* a surrogate is not well formed */
        {"\xc0\xaf", "\"?"
                     "?\""}, /* overlong '/' */
        {"\xe0\x80\xaf", "\"?"
                         "?"
                         "?\""}, /* overlong, 3 bytes */
        {"\xf4\x90\x80\x80", "\"?"
                             "?"
                             "?"
                             "?\""}, /* beyond U+10FFFF */
        {"\xf8\x88\x80\x80\x80", "\"?"
                                 "?"
                                 "?"
                                 "?"
                                 "?\""},                             /* a 5-byte form */
        {"\xf0\x9f\x98\x80!", "\"\\0360\\0237\\0230\\0200\\0041\""}, /* U+1F600, kept */
        {"EOD", "\"EOD\""}, /* only ever inside quotes, never a line of a data block */
        /* What an SVG cannot hold (gnuplot escapes only '<' and '&' there): "]]>", U+FFFE
         * and U+FFFF are shown as '?'; U+FFFD and a lone "]>" are kept. */
        {"a]]>b", "\"a]]?b\""},
        {"]>]]]>", "\"]>]]]?\""},
        {"x\xef\xbf\xbfy\xef\xbf\xbe", "\"x?y?\""},
        {"\xef\xbf\xbd", "\"\\0357\\0277\\0275\""},
        {"back\\slash`x`@y!z\"$", "\"back\\0134slash\\0140x\\0140\\0100y\\0041z\\0042\\0044\""},
        {"{}", "\"\\0173\\0175\""},
        {"", "\"\""},
    };
    for (size_t i = 0; i < sizeof cases / sizeof *cases; ++i) {
        int rc;
        char *w = written(gp_label, NULL, cases[i].in, &rc);
        assert_string_equal(w, cases[i].out);
        free(w);
    }
    /* Every single byte: a control byte or a lone byte >= 0x80 shows as '?', a letter, digit
     * or inert mark as itself, any other byte as its octal escape. */
    for (int c = 1; c < 0x100; ++c) {
        char s[2] = {(char)c, 0}, want[16];
        if (c < 0x20 || c >= 0x7f) snprintf(want, sizeof want, "\"?\"");
        else if (isalnum(c) || strchr(" _-.,:;+=/()[]<>#%&*~^|?", c))
            snprintf(want, sizeof want, "\"%c\"", c);
        else snprintf(want, sizeof want, "\"\\0%03o\"", (unsigned)c);
        int rc;
        char *w = written(gp_label, NULL, s, &rc);
        assert_string_equal(w, want);
        free(w);
    }
}

/* A file name: relative ones get "./" (gnuplot opens "|...", "<...", "~/...", "-" and "+"
 * its own way), absolute ones are left as they are, control characters are refused. */
static void test_path(void **state)
{
    (void)state;
    static const struct {
        const char *in, *out;
    } cases[] = {
        {"|touch CANARY;x.png", "\"./|touch CANARY;x.png\""},
        {"<y.png", "\"./<y.png\""},
        {"~/h.png", "\"./~/h.png\""},
        {"-", "\"./-\""},
        {"+", "\"./+\""},
        {"a/b.svg", "\"./a/b.svg\""},
        {"/abs/|x.png", "\"/abs/|x.png\""},
        {"it's.png", "\"./it\\0047s.png\""},
    };
    for (size_t i = 0; i < sizeof cases / sizeof *cases; ++i) {
        int rc;
        char *w = written(NULL, gp_path, cases[i].in, &rc);
        assert_int_equal(rc, 0);
        assert_string_equal(w, cases[i].out);
        free(w);
    }
    int rc;
    char *w = written(NULL, gp_path, "|a\nb.png", &rc);
    assert_int_equal(rc, -1);
    assert_string_equal(w, "");
    free(w);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_quote_round_trip),
        cmocka_unit_test(test_quote_refuses_control),
        cmocka_unit_test(test_label),
        cmocka_unit_test(test_path),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
