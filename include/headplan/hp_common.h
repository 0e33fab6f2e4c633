/* Error codes, diagnostics and limits shared by every headplan module. */
#ifndef HP_COMMON_H
#define HP_COMMON_H

#include <stddef.h>

/* Marks a function of the public API: the shared library is built with hidden visibility,
 * so only what carries HP_API is exported (scripts/hp_api.py annotates and lists them). */
#if defined(__GNUC__) || defined(__clang__)
#define HP_API __attribute__((visibility("default")))
#else
#define HP_API
#endif

#ifdef __cplusplus
extern "C" {
#endif

/* The most bladders a layout may hold (the robot has eight). */
#define HP_MAX_BLADDERS 16
/* Longest bladder name, including the terminating NUL. */
#define HP_NAME_MAX 32
/* Size of a diagnostic message buffer. */
#define HP_DIAG_MAX 512

/* What every fallible call returns. A call that returns anything but HP_OK has left its
 * outputs either untouched or set to NaN; it never returns a partial answer as valid. */
typedef enum hp_error {
    HP_OK = 0,
    HP_ERR_NULL,           /* a required pointer argument was NULL */
    HP_ERR_INVALID,        /* an argument is NaN, infinite, of the wrong sign or out of range */
    HP_ERR_DOMAIN,         /* outside the model's domain (ri <= 0, Ri >= Ro, collapsed cavity) */
    HP_ERR_NO_STABLE,      /* no stable radius: pressure above the bladder's limit point */
    HP_ERR_NO_CONVERGENCE, /* an iteration did not meet its tolerance within its budget */
    HP_ERR_PARSE,          /* a file or string is malformed */
    HP_ERR_IO,             /* a file could not be read or written */
    HP_ERR_NOMEM,          /* memory allocation failed */
    HP_ERR_SOLVER,         /* a solver backend failed in a way it could not label */
    HP_ERR_STATE,          /* a call out of order, or on an object that failed to build */
    HP_END,                /* not an error: the end of a stream (hp_trace_next) */
    HP_ERR_COUNT_          /* number of codes; not an error */
} hp_error;

/* A diagnostic: the message of the last failure of a stateless call. Pass NULL where the
 * message is not wanted. */
typedef struct hp_diag {
    char text[HP_DIAG_MAX];
} hp_diag;

/* Stable lower-case name of an error code ("ok", "invalid-argument", ...); "unknown" for a
 * value outside the enum. Never NULL. */
HP_API const char *hp_error_name(hp_error e);

/* One-line English description of an error code; safe for unknown codes. Never NULL. */
HP_API const char *hp_error_message(hp_error e);

/* Writes a printf-style message into diag (if diag is not NULL) and returns code, so that
 * a failing path reads `return hp_diag_set(d, HP_ERR_INVALID, "Ri_mm: must be > 0");`.
 * Numbers are written in the C locale ("0.5"), whatever LC_NUMERIC the host set; the
 * calling thread's locale is restored before it returns. */
HP_API hp_error hp_diag_set(hp_diag *diag, hp_error code, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

/* The library version as "MAJOR.MINOR.PATCH". */
HP_API const char *hp_version(void);

#ifdef __cplusplus
}
#endif
#endif
