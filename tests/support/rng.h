/* The tests' one random generator: splitmix64 (Steele, Lea, Flood 2014) on a 64-bit state the
 * test seeds itself, so every run and machine draws the same numbers (no test reads the
 * clock). Uniform doubles take the top 53 bits; normal deviates are Box–Muller. */
#ifndef HP_TEST_SUPPORT_RNG_H
#define HP_TEST_SUPPORT_RNG_H

#include <math.h>
#include <stdint.h>

static inline uint64_t test_rng_next(uint64_t *s)
{
    uint64_t z = (*s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

/* Uniform in [0, 1), a multiple of 2⁻⁵³. */
static inline double test_rng_unit(uint64_t *s)
{
    return (double)(test_rng_next(s) >> 11) * 0x1.0p-53;
}

/* Uniform in [lo, hi). */
static inline double test_rng_uniform(uint64_t *s, double lo, double hi)
{
    return lo + (hi - lo) * test_rng_unit(s);
}

/* Standard normal (Box–Muller; a first draw of exactly 0 counts as 1e-300). */
static inline double test_rng_normal(uint64_t *s)
{
    double u = test_rng_unit(s), v = test_rng_unit(s);
    if (u < 1e-300) u = 1e-300;
    return sqrt(-2.0 * log(u)) * cos(6.283185307179586 * v);
}

#endif
