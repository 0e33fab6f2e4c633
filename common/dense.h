/* The one Cholesky factorisation of the library (small dense matrices, no allocation): the
 * realtime QP, its convexity test and the NLopt optimality check all use it. Larger or
 * rank-revealing decompositions (SVD, QR) go through Eigen behind kinematics/linalg.h. */
#ifndef HP_COMMON_DENSE_H
#define HP_COMMON_DENSE_H

/* Factors the symmetric n×n matrix A (row-major, leading dimension lda; only its lower
 * triangle is read) as L·Lᵀ into the lower triangle of L (leading dimension ldl; the strict
 * upper triangle of L is not written). L may be A itself (in place). Returns 1 when every
 * pivot s_j exceeds min_frac·A_jj (min_frac = 0: A is positive definite), else 0 (L then
 * holds a partial factor). Allocation-free; the same operations in the same order for
 * every caller, so results agree to the bit. */
int hpi_cholesky(const double *A, int lda, int n, double min_frac, double *L, int ldl);

/* Solves L·Lᵀ·y = b in place for the factor of hpi_cholesky. */
void hpi_cholesky_solve(const double *L, int ldl, int n, double *b);

/* ‖L⁻¹‖_F² for the factor of hpi_cholesky (nonzero diagonal): an upper bound on ‖A⁻¹‖₂,
 * so trace(A)·hpi_cholesky_inv_frob2 bounds A's 2-norm condition number from above (to
 * rounding). About n³/6 multiply-adds; allocation-free; n <= 64 (else +inf). */
double hpi_cholesky_inv_frob2(const double *L, int ldl, int n);

#endif
