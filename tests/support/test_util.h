/* Helpers shared by the cmocka tests: closeness checks that print both numbers. */
#ifndef HP_TEST_UTIL_H
#define HP_TEST_UTIL_H

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

/* The sanitizer build (ASan + UBSan, .ci/run's second pass, on a machine it loads on
 * purpose) runs the suite ten to forty times slower than the plain one: there the heaviest
 * sweeps take the first cases of the same seeded sequences, HP_TEST_SMALL(plain, small);
 * the plain build runs them whole. The sanitizers look for memory and undefined-behaviour
 * errors, which the first cases' paths show as well; the statistics are the plain run's.
 * Compiling a plain build with -DHP_TEST_FORCE_SMALL checks that every assertion still
 * holds on the small sizes. */
#if defined(__SANITIZE_ADDRESS__) || defined(HP_TEST_FORCE_SMALL)
#define HP_TEST_IS_SMALL 1
#else
#define HP_TEST_IS_SMALL 0
#endif
#define HP_TEST_SMALL(plain, small) (HP_TEST_IS_SMALL ? (small) : (plain))

/* Fails unless |got − want| <= abs_tol + rel_tol·|want|, printing both and the excess. */
#define hp_assert_close(got, want, rel_tol, abs_tol)                                               \
    do {                                                                                           \
        double g_ = (got), w_ = (want);                                                            \
        double lim_ = (abs_tol) + (rel_tol)*fabs(w_);                                              \
        if (!(fabs(g_ - w_) <= lim_)) {                                                            \
            print_error("%s = %.17g, want %.17g (|diff| %.3g > %.3g)\n", #got, g_, w_,             \
                        fabs(g_ - w_), lim_);                                                      \
            fail();                                                                                \
        }                                                                                          \
    } while (0)

/* Solves the 6×6 system A x = b in place (b becomes x) by Gaussian elimination without
 * pivoting: for the symmetric positive definite matrices the tests build (stiffnesses,
 * normal equations). A is overwritten. */
static inline void hp_test_solve6(double A[36], double b[6])
{
    for (int c = 0; c < 6; ++c)
        for (int r = c + 1; r < 6; ++r) {
            double f = A[r * 6 + c] / A[c * 6 + c];
            for (int j = c; j < 6; ++j) A[r * 6 + j] -= f * A[c * 6 + j];
            b[r] -= f * b[c];
        }
    for (int r = 5; r >= 0; --r) {
        for (int j = r + 1; j < 6; ++j) b[r] -= A[r * 6 + j] * b[j];
        b[r] /= A[r * 6 + r];
    }
}

/* A whole small file (below 64 KiB) in a malloc'ed buffer, its length in *len. */
static inline char *hp_test_read_all(const char *path, size_t *len)
{
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    char *buf = malloc(1 << 16);
    assert_non_null(buf);
    *len = fread(buf, 1, (1 << 16) - 1, f);
    fclose(f);
    return buf;
}

/* A small text file (below 64 KiB) with the first occurrence of `from` replaced by `to`
 * (`to` NULL: the line holding `from` removed; a `from` starting with a newline matches at
 * a line's start), NUL-terminated in a malloc'ed buffer: a
 * shipped scene changed in one place, so a test states only what it changes. */
static inline char *hp_test_edit_file(const char *path, const char *from, const char *to)
{
    size_t n;
    char *text = hp_test_read_all(path, &n);
    text[n] = '\0';
    char *at = strstr(text, from);
    assert_non_null(at);
    size_t cut = strlen(from);
    if (!to) { /* the whole line */
        if (*at == '\n') ++at;
        while (at > text && at[-1] != '\n') --at;
        char *eol = strchr(at, '\n');
        cut = eol ? (size_t)(eol + 1 - at) : strlen(at);
        to = "";
    }
    size_t head = (size_t)(at - text), tail = strlen(at + cut);
    char *out = malloc(head + strlen(to) + tail + 1);
    assert_non_null(out);
    memcpy(out, text, head);
    memcpy(out + head, to, strlen(to));
    memcpy(out + head + strlen(to), at + cut, tail + 1);
    free(text);
    return out;
}

/* How many doubles lie between two positive finite doubles (their bit patterns are ordered
 * as the values are). */
static inline long hp_test_ulps_apart(double a, double b)
{
    int64_t ia, ib;
    memcpy(&ia, &a, sizeof ia);
    memcpy(&ib, &b, sizeof ib);
    return (long)(ia > ib ? ia - ib : ib - ia);
}

#endif
