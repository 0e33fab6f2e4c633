/* The library's one Cholesky factorisation (see dense.h). */
#include "common/dense.h"

#include <math.h>

int hp_cholesky(const double *A, int lda, int n, double min_frac, double *L, int ldl)
{
    for (int j = 0; j < n; ++j) {
        double s = A[j * lda + j];
        for (int k = 0; k < j; ++k) s -= L[j * ldl + k] * L[j * ldl + k];
        /* Written so that NaN fails. */
        if (!(s > (min_frac > 0 ? min_frac * A[j * lda + j] : 0.0))) return 0;
        double l = sqrt(s);
        L[j * ldl + j] = l;
        for (int i = j + 1; i < n; ++i) {
            double t = A[i * lda + j];
            for (int k = 0; k < j; ++k) t -= L[i * ldl + k] * L[j * ldl + k];
            L[i * ldl + j] = t / l;
        }
    }
    return 1;
}

void hp_cholesky_solve(const double *L, int ldl, int n, double *b)
{
    for (int i = 0; i < n; ++i) {
        double t = b[i];
        for (int k = 0; k < i; ++k) t -= L[i * ldl + k] * b[k];
        b[i] = t / L[i * ldl + i];
    }
    for (int i = n - 1; i >= 0; --i) {
        double t = b[i];
        for (int k = i + 1; k < n; ++k) t -= L[k * ldl + i] * b[k];
        b[i] = t / L[i * ldl + i];
    }
}

double hp_cholesky_inv_frob2(const double *L, int ldl, int n)
{
    /* Column j of L⁻¹ by forward substitution on e_j (zero above row j). */
    double x[64], s = 0.0;
    if (n > 64) return INFINITY;
    for (int j = 0; j < n; ++j) {
        for (int i = j; i < n; ++i) {
            double t = i == j ? 1.0 : 0.0;
            for (int k = j; k < i; ++k) t -= L[i * ldl + k] * x[k];
            x[i] = t / L[i * ldl + i];
            s += x[i] * x[i];
        }
    }
    return s;
}
