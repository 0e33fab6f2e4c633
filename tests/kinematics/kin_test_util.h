/* Test helpers for the kinematics tests: random poses from the tests' seeded generator. */
#ifndef HP_KIN_TEST_UTIL_H
#define HP_KIN_TEST_UTIL_H

#include "support/rng.h"

#include <math.h>
#include <stdint.h>

/* A random unit 3-vector scaled to length len. */
static inline void kin_rng_vec3(uint64_t *r, double len, double out[3])
{
    double n = 0.0;
    for (int i = 0; i < 3; ++i) {
        out[i] = test_rng_normal(r);
        n += out[i] * out[i];
    }
    n = sqrt(n);
    for (int i = 0; i < 3; ++i) out[i] *= len / n;
}

/* Random pose with translation norm <= tmax (m) and angle-vector norm <= rmax (rad);
 * on_sphere = 1 puts both exactly on their bounds. */
static inline void kin_rng_pose(uint64_t *r, double tmax, double rmax, int on_sphere, double xi[6])
{
    double ft = on_sphere ? 1.0 : cbrt(test_rng_uniform(r, 0, 1));
    double fr = on_sphere ? 1.0 : cbrt(test_rng_uniform(r, 0, 1));
    kin_rng_vec3(r, tmax * ft, xi);
    kin_rng_vec3(r, rmax * fr, xi + 3);
}

#endif
