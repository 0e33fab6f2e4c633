/* Internal: byte-level checks of text read from files (UTF-8 validity). */
#ifndef HP_SCENE_TEXT_CHECK_H
#define HP_SCENE_TEXT_CHECK_H

#include <stddef.h>

/* Offset of the first byte of s[0..len) that is a NUL or not part of well-formed UTF-8
 * (overlong forms, surrogates and code points above U+10FFFF are not well formed), or -1
 * when the text is clean. *is_nul says which of the two it was. */
long hpi_text_bad_byte(const char *s, size_t len, int *is_nul);

#endif
