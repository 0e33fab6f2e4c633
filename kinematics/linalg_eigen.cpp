// Eigen-backed least squares and SVD for the kinematics module (see linalg.h).
// Fixed maximum sizes keep every matrix on the stack: nothing is allocated.
#include "linalg.h"

#include <Eigen/Dense>
#include <cmath>

namespace
{
constexpr int kMax = HP_KIN_LINALG_MAX_ROWS;
using Mat = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::ColMajor, kMax, 6>;
using Vec = Eigen::Matrix<double, Eigen::Dynamic, 1, Eigen::ColMajor, kMax, 1>;
using Mat6 = Eigen::Matrix<double, Eigen::Dynamic, 6, Eigen::ColMajor, kMax, 6>;
} // namespace

extern "C" int hpi_kin_damped_lstsq(int m, int ncol, const double *J, const double *r,
                                    const double *D, double lambda, double *dx)
{
    if (m < 0 || ncol < 1 || ncol > 6 || m + ncol > kMax || !(lambda >= 0)) return -1;
    Mat A(m + ncol, ncol);
    Vec b(m + ncol);
    A.setZero();
    b.setZero();
    for (int i = 0; i < m; ++i) {
        for (int j = 0; j < ncol; ++j) A(i, j) = J[i * ncol + j];
        b(i) = -r[i];
    }
    double sl = std::sqrt(lambda);
    for (int j = 0; j < ncol; ++j) A(m + j, j) = sl * D[j];
    Eigen::ColPivHouseholderQR<Mat> qr(A);
    Eigen::Matrix<double, Eigen::Dynamic, 1, Eigen::ColMajor, 6, 1> x = qr.solve(b);
    for (int j = 0; j < ncol; ++j) {
        if (!std::isfinite(x(j))) return -1;
        dx[j] = x(j);
    }
    return 0;
}

extern "C" int hpi_kin_svd6(int m, const double *A, double sv[6], double V[36])
{
    if (m < 1 || m > kMax) return -1;
    Mat6 M(m, 6);
    for (int i = 0; i < m; ++i)
        for (int j = 0; j < 6; ++j) M(i, j) = A[i * 6 + j];
    Eigen::JacobiSVD<Mat6> svd(M, Eigen::ComputeFullV);
    const auto &s = svd.singularValues();
    const auto &v = svd.matrixV();
    for (int j = 0; j < 6; ++j) sv[j] = j < s.size() ? s(j) : 0.0;
    for (int i = 0; i < 6; ++i)
        for (int j = 0; j < 6; ++j) V[i * 6 + j] = v(i, j);
    for (int j = 0; j < 6; ++j)
        if (!std::isfinite(sv[j])) return -1;
    return 0;
}

extern "C" int hpi_kin_symeig6(const double *A, double lam[6], double V[36])
{
    Eigen::Matrix<double, 6, 6> M;
    for (int i = 0; i < 6; ++i)
        for (int j = 0; j <= i; ++j) M(i, j) = M(j, i) = A[i * 6 + j];
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> es(M);
    if (es.info() != Eigen::Success) return -1;
    for (int j = 0; j < 6; ++j) {
        lam[j] = es.eigenvalues()(j);
        if (!std::isfinite(lam[j])) return -1;
        for (int i = 0; i < 6; ++i) V[i * 6 + j] = es.eigenvectors()(i, j);
    }
    return 0;
}
