/* A small deterministic generator for the calibration tests: splitmix64 (Steele, Lea, Flood
 * 2014) for uniforms, Box–Muller for normal deviates. Same numbers on every machine. */
#ifndef HP_TEST_CALIB_RNG_H
#define HP_TEST_CALIB_RNG_H

#include <math.h>
#include <stdint.h>

typedef struct { uint64_t s; } calib_rng;

static inline double rng_uniform(calib_rng *r) /* in [0, 1) */
{
    uint64_t z = (r->s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
    return (double)(z >> 11) * 0x1.0p-53;
}

static inline double rng_normal(calib_rng *r)
{
    double u = rng_uniform(r), v = rng_uniform(r);
    if (u < 1e-300) u = 1e-300;
    return sqrt(-2.0 * log(u)) * cos(2.0 * 3.14159265358979323846 * v);
}

#endif
