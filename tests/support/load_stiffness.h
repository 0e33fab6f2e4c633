/* The smallest eigenvalue of a load-level hold's stiffness, assembled by the tests from
 * hp_load_eval's Jacobian (not from the planner's load_stiffness.c): the tests' reference for
 * how stable a hold is, in the planner's units (N/mm, 1 mm weighs as 1 degree). */
#ifndef HP_TEST_SUPPORT_LOAD_STIFFNESS_H
#define HP_TEST_SUPPORT_LOAD_STIFFNESS_H

#include "headplan/hp_load.h"
#include "kinematics/linalg.h"
#include "kinematics/load_internal.h"

#include <math.h>

/* K = −dQ/dxi at xi under P, symmetrised, in mm/degree units [N/mm] (K, 36 row-major);
 * 0, or −1 when the model fails. */
static inline int test_load_stiffness(const hp_load_model *M, const double xi[6], const double *P,
                                      double K[36])
{
    double Q[6], dQ[36];
    if (hp_load_eval(M, xi, P, Q, dQ, NULL, NULL, NULL) != HP_OK) return -1;
    for (int i = 0; i < 6; ++i)
        for (int j = 0; j < 6; ++j)
            K[i * 6 + j] = -0.5 * (dQ[i * 6 + j] + dQ[j * 6 + i]) * hpi_load_unit(i) *
                           hpi_load_unit(j) * 1e3;
    return 0;
}

/* K's smallest eigenvalue [N/mm]; NaN when the model or the decomposition fails. */
static inline double test_load_smallest_stiffness(const hp_load_model *M, const double xi[6],
                                                  const double *P)
{
    double K[36], ev[6], V[36];
    if (test_load_stiffness(M, xi, P, K) != 0 || hpi_kin_symeig6(K, ev, V) != 0) return NAN;
    return ev[0];
}

#endif
