/* Text in a gnuplot script: the one way a string that comes from a file, a name or an option
 * enters the program text of headplan render, plot, fit layout --plot and the benchmark
 * lab's charts. Everything else in those scripts is fixed text or a number printed by a
 * fixed format; data travel in data blocks of numbers.
 *
 * Why single quotes: in a gnuplot single-quoted string '' is the only escape; a backslash,
 * a backquote (command substitution), '@' (macros) and '!' are plain characters there, while
 * double-quoted strings run `...` as a shell command. What a quoted string cannot survive is
 * a line break: gnuplot reads its script line by line, and a line that starts with '!' runs
 * a shell command. So a control character (a byte below 0x20, or 0x7f) is never written. */
#ifndef CLI_GPTEXT_H
#define CLI_GPTEXT_H

#include <stdio.h>

/* Offset of the first control character (a byte below 0x20, or 0x7f) of s, or -1. */
long gp_control_byte(const char *s);

/* Writes s as a gnuplot single-quoted string, byte for byte (a file name: bytes that are not
 * UTF-8 stay as they are). Returns 0, or -1 and writes nothing when s holds a control
 * character: the caller refuses such a name before it draws (gp_check_name). */
int gp_quote(FILE *f, const char *s);

/* Writes s as a quoted text to show (a title, a label, a key entry) that is never refused:
 * every control character and every byte that is not part of well-formed UTF-8 is shown as
 * '?' (gnuplot would warn on our stderr that it cannot convert the text). */
void gp_label(FILE *f, const char *s);

#endif
