/* Locale-independent number text (see c_locale.h). */
#define _POSIX_C_SOURCE 200809L
#include "common/c_locale.h"

#include <errno.h>
#include <pthread.h>

/* One C locale object for the process, made at first use: a trace's numbers are parsed one
 * by one, and a newlocale/freelocale pair per number was an allocation per number. */
static locale_t c_numeric;
static pthread_once_t c_numeric_once = PTHREAD_ONCE_INIT;

static void make_c_numeric(void) { c_numeric = newlocale(LC_NUMERIC_MASK, "C", (locale_t)0); }

void hpi_c_numeric_begin(hp_c_numeric *s)
{
    pthread_once(&c_numeric_once, make_c_numeric);
    s->c = c_numeric;
    s->old = s->c ? uselocale(s->c) : (locale_t)0;
}

void hpi_c_numeric_end(hp_c_numeric *s)
{
    if (!s->c) return;
    int er = errno;
    uselocale(s->old);
    s->c = (locale_t)0;
    errno = er;
}
