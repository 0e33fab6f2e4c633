/* Internal: the one strict text -> double conversion of every file reader. */
#ifndef HP_SCENE_STRICT_NUMBER_H
#define HP_SCENE_STRICT_NUMBER_H

#include <stddef.h>

/* 1 when s[0..len) is a decimal number: [+-] (digits [. digits*] | . digits)
 * [(e|E) [+-] digits], nothing else (no spaces, "nan", "inf", hex). */
int hpi_decimal_syntax(const char *s, size_t len);

/* Parses s[0..len) as a finite decimal number: optional sign, digits, optional fraction,
 * optional exponent. Refuses empty text, spaces, "nan", "inf", hex, trailing characters and
 * overflow or underflow. Returns NULL on success, else a short reason ("not a number",
 * "overflows a double", ...). */
const char *hpi_strict_double(const char *s, size_t len, double *out);

/* strtod in the C locale, whatever the calling thread's LC_NUMERIC ('.' is the decimal
 * point of every file format here); errno as strtod leaves it. */
double hpi_c_strtod(const char *s, char **end);

/* The first number in the JSON text s[0..len) outside a double's normal range (jansson
 * reads 1e-400 as 0 and keeps subnormals, where hpi_strict_double refuses both as "too small
 * for a double"; jansson refuses 1e400 without naming the key): its 0-based offset, the
 * reason in *why (hpi_strict_double's: "too small for a double" or "overflows a double"), and
 * in *key / *klen the key before it ("value" when that key is not short printable text, so
 * it can be echoed). -1 when there is none. */
long hpi_json_out_of_range(const char *s, size_t len, const char **key, size_t *klen,
                           const char **why);

#endif
