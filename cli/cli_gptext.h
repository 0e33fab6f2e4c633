/* Text in a gnuplot script: the one way a string that comes from a file, a name or an option
 * enters the program text of headplan render, plot, fit layout --plot and the benchmark
 * lab's charts. Everything else in those scripts is fixed text or a number printed by a
 * fixed format; data travel in data blocks of numbers.
 *
 * The form: a double-quoted gnuplot string in which every byte but letters, digits, the
 * space and a few inert punctuation marks is written as an octal escape "\0ooo" (gnuplot
 * reads "\0" and then at most three octal digits, so a digit that follows is not taken in).
 * So the script holds no quote, backslash, backquote (command substitution in a
 * double-quoted string), '@' (a macro), '!', '$' or brace of the text, and no byte of a
 * multibyte character: the text cannot end the string or run anything, whatever it holds.
 * Single quotes cannot do this: gnuplot 5.4 reads '' as a quote only after another
 * character, so a text that starts with a quote or holds two ('''x', 'a''''b') splits
 * into tokens (tests/cli/test_gptext.c prints every form back through gnuplot itself).
 * A control character (a byte below 0x20, or 0x7f) is never written at all: a name that
 * must be exact (a picture's) holding one is refused, a text to show has it shown as '?'.
 * A file name gnuplot opens goes through gp_path, never gp_quote alone. */
#ifndef CLI_GPTEXT_H
#define CLI_GPTEXT_H

#include <stdio.h>

/* Offset of the first control character (a byte below 0x20, or 0x7f) of s, or -1. */
long gp_control_byte(const char *s);

/* Writes s as a gnuplot string, byte for byte (a file name: bytes that are not UTF-8 stay as
 * they are). Returns 0, or -1 and writes nothing when s holds a control character: the
 * caller refuses such a name before it draws (gp_check_name). */
int gp_quote(FILE *f, const char *s);

/* Writes the file name path as a gnuplot string (gp_quote) for `set output` or `plot`, which
 * open some names their own way: a name starting with '|' is a pipe into a shell, '<' a
 * shell command's output, "~/" the home folder, '-' and '+' special files. A relative name
 * is written "./path", the same file, so none of that applies. Returns gp_quote's value. */
int gp_path(FILE *f, const char *path);

/* Writes s as a gnuplot string to show (a title, a label, a key entry) that is never
 * refused: every control character and every byte that is not part of well-formed UTF-8
 * is shown as '?' (gnuplot would warn on our stderr that it cannot convert the text), and
 * so are U+FFFE, U+FFFF and the '>' of "]]>", which gnuplot would write into an SVG picture
 * as they are, leaving it no well-formed XML. */
void gp_label(FILE *f, const char *s);

#endif
