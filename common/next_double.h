/* The neighbouring doubles of x: nextafter(x, +inf) and nextafter(x, -inf), bit for bit, by
 * one integer step on the representation. IEEE 754 doubles of one sign are ordered as their
 * bit patterns read as integers, so the next double away from zero is the pattern plus one
 * and the next towards zero the pattern minus one (from the largest finite double, plus one
 * is +inf; from the smallest subnormal, minus one is +0: nextafter's answers). A zero and a
 * non-finite x are left to libm. The window ends and the root finds step a double by an ulp
 * a few dozen times a plan, where libm's call (which also sets errno and raises the
 * floating-point flags) cost about 30 instructions; this costs a handful. */
#ifndef HP_COMMON_NEXT_DOUBLE_H
#define HP_COMMON_NEXT_DOUBLE_H

#include <math.h>
#include <stdint.h>
#include <string.h>

/* The least double above x (nextafter(x, INFINITY)). */
static inline double hpi_next_up(double x)
{
    if (x == 0 || !isfinite(x)) return nextafter(x, INFINITY);
    uint64_t u;
    memcpy(&u, &x, sizeof u);
    if (x > 0) ++u;
    else --u;
    memcpy(&x, &u, sizeof x);
    return x;
}

/* The greatest double below x (nextafter(x, -INFINITY)): the mirror image of hpi_next_up. */
static inline double hpi_next_down(double x) { return -hpi_next_up(-x); }

#endif
