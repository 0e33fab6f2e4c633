/* For the tests that run under a host's comma locale: LC_NUMERIC switched to a locale whose
 * decimal point is ',', the system's when installed, else built with localedef into a
 * temporary LOCPATH. Tests skip only when neither works. */
#ifndef HP_TESTS_COMMA_LOCALE_H
#define HP_TESTS_COMMA_LOCALE_H

#include <locale.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int is_comma(void) { return strcmp(localeconv()->decimal_point, ",") == 0; }

/* Switches LC_NUMERIC to a locale whose decimal point is ','; 1 on success. */
static int comma_locale(void)
{
    static const char *const names[] = {"de_DE.UTF-8", "de_DE.utf8", "fr_FR.UTF-8", "de_DE"};
    for (int i = 0; i < 4; ++i)
        if (setlocale(LC_NUMERIC, names[i]) && is_comma()) return 1;
    static char dir[] = "/tmp/hp_locale_XXXXXX";
    if (!mkdtemp(dir)) return 0;
    char cmd[256];
    snprintf(cmd, sizeof cmd, "localedef -i de_DE -f UTF-8 %s/de_DE.UTF-8 >/dev/null 2>&1", dir);
    int built = system(cmd) == 0;
    if (built) setenv("LOCPATH", dir, 1); /* glibc reads it at every setlocale */
    int ok = built && setlocale(LC_NUMERIC, "de_DE.UTF-8") && is_comma();
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    if (system(cmd) != 0) fprintf(stderr, "could not remove %s\n", dir);
    return ok;
}

#endif
