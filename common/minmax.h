/* Larger and smaller of two numbers where both are known to be finite (or where a NaN is
 * ruled out before): a compare and a select, where fmax and fmin are library calls that
 * also order NaNs and signed zeros. Hot loops only; elsewhere fmax/fmin say it plainly. */
#ifndef HP_COMMON_MINMAX_H
#define HP_COMMON_MINMAX_H

static inline double hpi_max2(double a, double b) { return a > b ? a : b; }
static inline double hpi_min2(double a, double b) { return a < b ? a : b; }

#endif
