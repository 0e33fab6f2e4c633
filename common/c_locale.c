/* Locale-independent number text (see c_locale.h). */
#define _POSIX_C_SOURCE 200809L
#include "common/c_locale.h"

#include <errno.h>

void hp_c_numeric_begin(hp_c_numeric *s)
{
    s->c = newlocale(LC_NUMERIC_MASK, "C", (locale_t)0);
    s->old = s->c ? uselocale(s->c) : (locale_t)0;
}

void hp_c_numeric_end(hp_c_numeric *s)
{
    if (!s->c) return;
    int er = errno;
    uselocale(s->old);
    freelocale(s->c);
    s->c = (locale_t)0;
    errno = er;
}
