/* Positive definiteness of a symmetric 6×6 matrix by Cholesky: the tests' reference for a
 * stable hold (the load planner's hp_load_holding uses its own factorisation). */
#ifndef HP_TEST_SUPPORT_SPD_H
#define HP_TEST_SUPPORT_SPD_H

#include <math.h>

/* 1 when A (row-major, symmetric) is positive definite; A is overwritten by its factor. */
static inline int test_positive_definite6(double A[36])
{
    for (int j = 0; j < 6; ++j) {
        double s = A[j * 6 + j];
        for (int k = 0; k < j; ++k) s -= A[j * 6 + k] * A[j * 6 + k];
        if (!(s > 0)) return 0;
        A[j * 6 + j] = sqrt(s);
        for (int i = j + 1; i < 6; ++i) {
            double t = A[i * 6 + j];
            for (int k = 0; k < j; ++k) t -= A[i * 6 + k] * A[j * 6 + k];
            A[i * 6 + j] = t / A[j * 6 + j];
        }
    }
    return 1;
}

#endif
