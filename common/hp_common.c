/* Error names, diagnostics and the version string (shared by every module). */
#define _POSIX_C_SOURCE 200809L
#include "headplan/hp_common.h"
#include "headplan/hp_version.h"

#include "common/c_locale.h"
#include "common/names.h"

#include <errno.h>
#include <stdarg.h>
#include <stdio.h>

const char *const hpi_error_words[] = {"ok",
                                       "null-argument",
                                       "invalid-argument",
                                       "domain",
                                       "no-stable-radius",
                                       "no-convergence",
                                       "parse",
                                       "io",
                                       "out-of-memory",
                                       "solver",
                                       "state",
                                       "end",
                                       NULL};
_Static_assert(sizeof hpi_error_words / sizeof *hpi_error_words == HP_ERR_COUNT_ + 1,
               "one word per error code");

static const char *const error_messages[HP_ERR_COUNT_] = {
    "success",
    "a required pointer argument was NULL",
    "an argument is NaN, infinite, of the wrong sign or out of range",
    "outside the model's domain",
    "no stable radius: pressure above the bladder's limit point",
    "an iteration did not converge within its budget",
    "malformed input",
    "a file could not be read or written",
    "out of memory",
    "solver failure",
    "call out of order or on an object that failed to build",
    "end of input",
};

HP_NAMES_NAME_CALL(hp_error, hpi_error_words, hp_error_name)

const char *hp_error_message(hp_error e)
{
    if ((int)e < 0 || e >= HP_ERR_COUNT_) return "unknown error code";
    return error_messages[e];
}

hp_error hp_diag_set(hp_diag *diag, hp_error code, const char *fmt, ...)
{
    if (diag) {
        /* The C numeric locale: a host that set LC_NUMERIC to de_DE would otherwise read
         * "0,5" where the command line (which runs in C) reads "0.5" for the same failure. */
        int er = errno; /* a caller may still report errno after setting the message */
        hp_c_numeric c;
        hpi_c_numeric_begin(&c);
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(diag->text, sizeof diag->text, fmt, ap);
        va_end(ap);
        hpi_c_numeric_end(&c);
        errno = er;
    }
    return code;
}

const char *hp_version(void) { return HP_VERSION_STRING; }
