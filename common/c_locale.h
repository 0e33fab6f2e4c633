/* Internal: numbers in the C locale ('.' as the decimal point of every file format here),
 * whatever LC_NUMERIC the host program set (a Python or GUI host calling
 * setlocale(LC_ALL, "") in Germany makes printf write "1,5" and strtod stop at "1.5"). */
#ifndef HP_COMMON_C_LOCALE_H
#define HP_COMMON_C_LOCALE_H

#include <locale.h>

typedef struct hp_c_numeric {
    locale_t c, old;
} hp_c_numeric;

/* Switches the calling thread to the C locale until hpi_c_numeric_end (uselocale: the
 * program's locale, the host's, is not touched, nor are other threads). Every printf and
 * strtod in between reads and writes numbers with '.'. The C locale object is made once per
 * process (newlocale, at first use) and never freed; if that fails, the thread's locale is
 * left as it is. */
void hpi_c_numeric_begin(hp_c_numeric *s);
/* Restores the thread's locale from before hpi_c_numeric_begin; errno is kept. */
void hpi_c_numeric_end(hp_c_numeric *s);

#endif
