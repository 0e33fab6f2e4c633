/* Dense linear algebra of the kinematics module (Eigen behind a C interface). */
#ifndef HP_KIN_LINALG_H
#define HP_KIN_LINALG_H

#ifdef __cplusplus
extern "C" {
#endif

/* Largest row count the routines accept (bladders plus damping rows). */
#define HP_KIN_LINALG_MAX_ROWS 32

/* Solves min |J·dx + r|² + lambda·|diag(D)·dx|² for dx (ncol unknowns, 1..6) with a
 * column-pivoting Householder QR of the stacked system; J is m×ncol row-major,
 * m + ncol <= HP_KIN_LINALG_MAX_ROWS. Returns 0 on success, -1 on bad sizes or a
 * non-finite result. Allocates nothing. */
int hpi_kin_damped_lstsq(int m, int ncol, const double *J, const double *r, const double *D,
                         double lambda, double *dx);

/* Singular value decomposition of A (m×6 row-major, 1 <= m <= HP_KIN_LINALG_MAX_ROWS):
 * sv[0..5] descending (zeros past min(m, 6)), V 6×6 row-major whose column j is the right
 * singular vector of sv[j]. Returns 0 on success. */
int hpi_kin_svd6(int m, const double *A, double sv[6], double V[36]);

/* The same for any m×n row-major A (m, n >= 1): sv[0..n-1] descending (zeros past
 * min(m, n)), V n×n row-major. Allocates (for offline use: calibration). 0 on success. */
int hpi_kin_svd(int m, int n, const double *A, double *sv, double *V);

/* Eigen-decomposition of a symmetric 6×6 A (row-major; only its lower triangle is read):
 * lam[0..5] ascending, V 6×6 row-major whose column j is the unit eigenvector of lam[j].
 * Returns 0 on success, -1 on a non-finite result. Allocates nothing. */
int hpi_kin_symeig6(const double *A, double lam[6], double V[36]);

#ifdef __cplusplus
}
#endif
#endif
