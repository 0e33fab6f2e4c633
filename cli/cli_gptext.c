/* Text in a gnuplot script (see cli_gptext.h). */
#include "cli/cli_gptext.h"
#include "scene/text_check.h"

#include <string.h>

static int is_control(unsigned char c) { return c < 0x20 || c == 0x7f; }

long gp_control_byte(const char *s)
{
    for (long i = 0; s[i]; ++i)
        if (is_control((unsigned char)s[i])) return i;
    return -1;
}

/* s[0..n) inside the quotes: an inert byte as it is, any other as "\0ooo"; a control
 * character as '?' (gp_quote has refused it already; gp_label shows it so). */
static void put_bytes(FILE *f, const char *s, size_t n)
{
    static const char inert[] = " _-.,:;+=/()[]<>#%&*~^|?";
    for (size_t k = 0; k < n; ++k) {
        unsigned char c = (unsigned char)s[k];
        if (is_control(c)) fputc('?', f);
        else if ((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                 (c < 0x80 && strchr(inert, c)))
            fputc(c, f);
        else fprintf(f, "\\0%03o", c);
    }
}

int gp_quote(FILE *f, const char *s)
{
    if (gp_control_byte(s) >= 0) return -1;
    fputc('"', f);
    put_bytes(f, s, strlen(s));
    fputc('"', f);
    return 0;
}

int gp_path(FILE *f, const char *path)
{
    if (gp_control_byte(path) >= 0) return -1;
    if (path[0] == '/') return gp_quote(f, path);
    /* "./" inside the quotes: gnuplot looks only at the name's first bytes. */
    fputs("\"./", f);
    put_bytes(f, path, strlen(path));
    fputc('"', f);
    return 0;
}

/* Length of what an SVG picture cannot hold that starts at s[i] (well-formed UTF-8), or 0.
 * gnuplot's SVG terminal writes text as XML with '<' and '&' escaped and nothing else, so
 * "]]>" (not allowed in XML text) and U+FFFE, U+FFFF (no XML characters) would leave a
 * picture no SVG reader opens. s[i - 2..i) are the bytes before: "]]" is shown as it is. */
static size_t svg_unsafe(const char *s, size_t i)
{
    const unsigned char *u = (const unsigned char *)s;
    if (u[i] == 0xef && u[i + 1] == 0xbf && (u[i + 2] == 0xbe || u[i + 2] == 0xbf)) return 3;
    if (u[i] == '>' && i >= 2 && u[i - 1] == ']' && u[i - 2] == ']') return 1;
    return 0;
}

void gp_label(FILE *f, const char *s)
{
    size_t len = strlen(s);
    fputc('"', f);
    for (size_t i = 0; i < len;) {
        int nul = 0;
        long bad = hpi_text_bad_byte(s + i, len - i, &nul);
        size_t end = bad < 0 ? len : i + (size_t)bad;
        while (i < end) {
            size_t k = i, n = 0;
            while (k < end && (n = svg_unsafe(s, k)) == 0) ++k;
            put_bytes(f, s + i, k - i);
            if (k < end) fputc('?', f);
            i = k + n;
        }
        if (i < len) { /* a byte that is not part of well-formed UTF-8 */
            fputc('?', f);
            ++i;
        }
    }
    fputc('"', f);
}
