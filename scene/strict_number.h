/* Internal: the one strict text -> double conversion of every file reader. */
#ifndef HP_SCENE_STRICT_NUMBER_H
#define HP_SCENE_STRICT_NUMBER_H

#include <stddef.h>

/* Parses s[0..len) as a finite decimal number: optional sign, digits, optional fraction,
 * optional exponent. Refuses empty text, spaces, "nan", "inf", hex, trailing characters and
 * overflow. Returns NULL on success, else a short reason ("not a number", "overflows a
 * double", ...). Underflow to a subnormal or zero is accepted. */
const char *hp_strict_double(const char *s, size_t len, double *out);

#endif
