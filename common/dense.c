/* The library's one Cholesky factorisation (see dense.h). */
#include "common/dense.h"

#include <math.h>

/* Each routine's body is written once, for any n, and instantiated for each n from 1 to 6
 * (6, the pose's dimension: what the strict round trip's fit and the planner's QP factor
 * almost always; 1 to 6: the Gram matrix of the QP's warm start, one row per guessed active
 * constraint), where the constant bounds let the compiler unroll the loops and drop their
 * bookkeeping (about half the instructions), and for any other n. All run the same
 * operations in the same order, so the results are the same bits. The unroll pragmas
 * (6: HP_DENSE_FIXED_N) make the unrolling complete for n <= 6; for other n they only
 * unroll the inner loops partially. */
#define HP_DENSE_FIXED_N 6
/* GCC's unroll pragma; clang reads it as a request to unroll completely, cannot for a
 * variable n, and warns (an error here), so clang gets none and unrolls as it sees fit. */
#if defined(__GNUC__) && !defined(__clang__)
#define UNROLL6 _Pragma("GCC unroll 6")
#else
#define UNROLL6
#endif
/* Each fixed-n call site gets its own copy (the compiler would otherwise keep one generic
 * copy of the larger bodies and call it, losing the constant n). */
#if defined(__GNUC__)
#define FIXED_N_INLINE static inline __attribute__((always_inline))
#else
#define FIXED_N_INLINE static inline
#endif

FIXED_N_INLINE int cholesky_n(const double *A, int lda, int n, double min_frac, double *L, int ldl)
{
    UNROLL6
    for (int j = 0; j < n; ++j) {
        double s = A[j * lda + j];
        UNROLL6
        for (int k = 0; k < j; ++k) s -= L[j * ldl + k] * L[j * ldl + k];
        /* Written so that NaN fails. */
        if (!(s > (min_frac > 0 ? min_frac * A[j * lda + j] : 0.0))) return 0;
        double l = sqrt(s);
        L[j * ldl + j] = l;
        UNROLL6
        for (int i = j + 1; i < n; ++i) {
            double t = A[i * lda + j];
            UNROLL6
            for (int k = 0; k < j; ++k) t -= L[i * ldl + k] * L[j * ldl + k];
            L[i * ldl + j] = t / l;
        }
    }
    return 1;
}

int hpi_cholesky(const double *A, int lda, int n, double min_frac, double *L, int ldl)
{
    switch (n) {
    case 1: return cholesky_n(A, lda, 1, min_frac, L, ldl);
    case 2: return cholesky_n(A, lda, 2, min_frac, L, ldl);
    case 3: return cholesky_n(A, lda, 3, min_frac, L, ldl);
    case 4: return cholesky_n(A, lda, 4, min_frac, L, ldl);
    case 5: return cholesky_n(A, lda, 5, min_frac, L, ldl);
    case HP_DENSE_FIXED_N: return cholesky_n(A, lda, HP_DENSE_FIXED_N, min_frac, L, ldl);
    default: return cholesky_n(A, lda, n, min_frac, L, ldl);
    }
}

FIXED_N_INLINE void cholesky_solve_n(const double *L, int ldl, int n, double *b)
{
    UNROLL6
    for (int i = 0; i < n; ++i) {
        double t = b[i];
        UNROLL6
        for (int k = 0; k < i; ++k) t -= L[i * ldl + k] * b[k];
        b[i] = t / L[i * ldl + i];
    }
    UNROLL6
    for (int i = n - 1; i >= 0; --i) {
        double t = b[i];
        UNROLL6
        for (int k = i + 1; k < n; ++k) t -= L[k * ldl + i] * b[k];
        b[i] = t / L[i * ldl + i];
    }
}

void hpi_cholesky_solve(const double *L, int ldl, int n, double *b)
{
    switch (n) {
    case 1: cholesky_solve_n(L, ldl, 1, b); break;
    case 2: cholesky_solve_n(L, ldl, 2, b); break;
    case 3: cholesky_solve_n(L, ldl, 3, b); break;
    case 4: cholesky_solve_n(L, ldl, 4, b); break;
    case 5: cholesky_solve_n(L, ldl, 5, b); break;
    case HP_DENSE_FIXED_N: cholesky_solve_n(L, ldl, HP_DENSE_FIXED_N, b); break;
    default: cholesky_solve_n(L, ldl, n, b); break;
    }
}

FIXED_N_INLINE double inv_frob2_n(const double *L, int ldl, int n)
{
    /* Column j of L⁻¹ by forward substitution on e_j (zero above row j). */
    double x[64], s = 0.0;
    UNROLL6
    for (int j = 0; j < n; ++j) {
        UNROLL6
        for (int i = j; i < n; ++i) {
            double t = i == j ? 1.0 : 0.0;
            UNROLL6
            for (int k = j; k < i; ++k) t -= L[i * ldl + k] * x[k];
            x[i] = t / L[i * ldl + i];
            s += x[i] * x[i];
        }
    }
    return s;
}

double hpi_cholesky_inv_frob2(const double *L, int ldl, int n)
{
    if (n > 64) return INFINITY;
    switch (n) {
    case 1: return inv_frob2_n(L, ldl, 1);
    case 2: return inv_frob2_n(L, ldl, 2);
    case 3: return inv_frob2_n(L, ldl, 3);
    case 4: return inv_frob2_n(L, ldl, 4);
    case 5: return inv_frob2_n(L, ldl, 5);
    case HP_DENSE_FIXED_N: return inv_frob2_n(L, ldl, HP_DENSE_FIXED_N);
    default: return inv_frob2_n(L, ldl, n);
    }
}
