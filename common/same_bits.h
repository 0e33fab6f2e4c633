/* Bitwise equality of doubles, for the caches that reuse a result only when its inputs are
 * the same bits. */
#ifndef HP_COMMON_SAME_BITS_H
#define HP_COMMON_SAME_BITS_H

#include <stdint.h>
#include <string.h>

/* 1 when the n doubles at a and b have the same bits (memcmp's answer: −0 is not 0, a NaN
 * is itself). Inline: the callers compare a few to a few dozen numbers on a plan's hot path,
 * where a library memcmp's call cost more than the comparison (~1 % of a plan, perf). */
static inline int hpi_same_bits(const double *a, const double *b, int n)
{
    uint64_t d = 0;
    for (int i = 0; i < n; ++i) {
        uint64_t u, v;
        memcpy(&u, &a[i], sizeof u);
        memcpy(&v, &b[i], sizeof v);
        d |= u ^ v;
    }
    return d == 0;
}

#endif
