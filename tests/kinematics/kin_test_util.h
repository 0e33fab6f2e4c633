/* Test helpers for the kinematics tests: a seeded generator and random poses. */
#ifndef HP_KIN_TEST_UTIL_H
#define HP_KIN_TEST_UTIL_H

#include <math.h>
#include <stdint.h>

/* splitmix64: a fixed, seeded sequence (the tests never use the clock). */
typedef struct kin_rng {
    uint64_t s;
} kin_rng;

static inline uint64_t kin_rng_next(kin_rng *r)
{
    uint64_t z = (r->s += 0x9E3779B97F4A7C15ULL);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
}

/* Uniform in [lo, hi). */
static inline double kin_rng_uniform(kin_rng *r, double lo, double hi)
{
    return lo + (hi - lo) * ((double)(kin_rng_next(r) >> 11) * 0x1.0p-53);
}

/* Standard normal (Box–Muller). */
static inline double kin_rng_normal(kin_rng *r)
{
    double u = kin_rng_uniform(r, 1e-300, 1.0), v = kin_rng_uniform(r, 0.0, 1.0);
    return sqrt(-2.0 * log(u)) * cos(6.283185307179586 * v);
}

/* A random unit 3-vector scaled to length len. */
static inline void kin_rng_vec3(kin_rng *r, double len, double out[3])
{
    double n = 0.0;
    for (int i = 0; i < 3; ++i) {
        out[i] = kin_rng_normal(r);
        n += out[i] * out[i];
    }
    n = sqrt(n);
    for (int i = 0; i < 3; ++i) out[i] *= len / n;
}

/* Random pose with translation norm <= tmax (m) and angle-vector norm <= rmax (rad);
 * on_sphere = 1 puts both exactly on their bounds. */
static inline void kin_rng_pose(kin_rng *r, double tmax, double rmax, int on_sphere,
                                double xi[6])
{
    double ft = on_sphere ? 1.0 : cbrt(kin_rng_uniform(r, 0, 1));
    double fr = on_sphere ? 1.0 : cbrt(kin_rng_uniform(r, 0, 1));
    kin_rng_vec3(r, tmax * ft, xi);
    kin_rng_vec3(r, rmax * fr, xi + 3);
}

#endif
