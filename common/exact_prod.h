/* The product of two doubles rounded in a chosen direction, exactly: the one home of the
 * radius bounds a stretch limit gives (ri >= stretch_min · Ri and ri <= stretch_max · Ri
 * must hold for the exact product, not only for the rounded one, which lies below the
 * exact product for about four (stretch, Ri) pairs in ten).
 *
 * The rounding error of p = a·b comes from Dekker's error-free product (Veltkamp's split),
 * written without fma: -ffp-contract=off keeps the compiler from fusing it, and no fma
 * (hardware or emulated) is needed. Exact for finite a, b whose product neither overflows
 * nor falls within 2^-969 of underflow (radii and stretches are nowhere near either). */
#ifndef HP_COMMON_EXACT_PROD_H
#define HP_COMMON_EXACT_PROD_H

#include "common/next_double.h"

#include <math.h>

/* a·b − p exactly, for p = a·b rounded to nearest. */
static inline double hpi_prod_err(double a, double b, double p)
{
    const double split = 134217729.0; /* 2^27 + 1 */
    double ca = split * a, cb = split * b;
    double ah = ca - (ca - a), al = a - ah;
    double bh = cb - (cb - b), bl = b - bh;
    return ((ah * bh - p) + ah * bl + al * bh) + al * bl;
}

/* The smallest double r with r >= a·b exactly. */
static inline double hpi_prod_up(double a, double b)
{
    double p = a * b;
    return hpi_prod_err(a, b, p) > 0.0 ? hpi_next_up(p) : p;
}

/* The largest double r with r <= a·b exactly. */
static inline double hpi_prod_down(double a, double b)
{
    double p = a * b;
    return hpi_prod_err(a, b, p) < 0.0 ? hpi_next_down(p) : p;
}

#endif
