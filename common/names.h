/* Name tables: each public enum's words, in value order and NULL-terminated, written once in
 * the module that owns the enum. Its name and parse functions, the scene reader's word
 * checks, and the lists in messages and --help are all made from that one table, so adding a
 * value is one word in one table. Internal. */
#ifndef HP_COMMON_NAMES_H
#define HP_COMMON_NAMES_H

#include "headplan/hp_common.h"

#include <stddef.h>

/* hp_error's table (hp_error_name), in common/hp_common.c beside the messages. */
extern const char *const hpi_error_words[];

/* The word of value v, or "unknown" for a value outside the table. */
const char *hpi_names_word(const char *const *words, int v);

/* The value whose word is s (exact, case-sensitive) into *out. HP_ERR_NULL for a NULL s or
 * out, HP_ERR_INVALID for any other text (*out unchanged). */
hp_error hpi_names_parse(const char *const *words, const char *s, int *out);

/* The words joined as "a, b, c" into buf (len bytes, always terminated; cut short when too
 * small), the last separator `last` instead of ", " when not NULL (" or "). Returns buf. */
const char *hpi_names_join(const char *const *words, const char *last, char *buf, size_t len);

/* Number of words in a table. */
int hpi_names_count(const char *const *words);

/* The value of s in words into *out, for a parse call: HP_ERR_NULL when out is NULL too. */
hp_error hpi_names_parse_to(const char *const *words, const char *s, int *out, int null_out);

/* Defines an enum's public name call `const char *NAME(T)` from its table WORDS. */
#define HP_NAMES_NAME_CALL(T, WORDS, NAME)                                                         \
    const char *NAME(T v) { return hpi_names_word(WORDS, (int)v); }

/* Defines both its name call and its parse call `hp_error PARSE(const char *, T *)`
 * (HP_ERR_NULL, HP_ERR_INVALID; *out unchanged on error). */
#define HP_NAMES_CALLS(T, WORDS, NAME, PARSE)                                                      \
    HP_NAMES_NAME_CALL(T, WORDS, NAME)                                                             \
    hp_error PARSE(const char *s, T *out)                                                          \
    {                                                                                              \
        int v = 0;                                                                                 \
        hp_error e = hpi_names_parse_to(WORDS, s, &v, out == NULL);                                \
        if (e == HP_OK) *out = (T)v;                                                               \
        return e;                                                                                  \
    }

#endif
