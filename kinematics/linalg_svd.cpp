// Singular value decomposition of a matrix of any size (Eigen behind a C interface), for
// offline callers such as the calibration fits; allocates, unlike linalg_eigen.cpp.
#include "linalg.h"

#include <Eigen/Dense>
#include <cmath>
#include <new>

extern "C" int hpi_kin_svd(int m, int n, const double *A, double *sv, double *V)
{
    if (m < 1 || n < 1 || !A || !sv || !V) return -1;
    try {
        Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> M(
            A, m, n);
        Eigen::JacobiSVD<Eigen::MatrixXd> svd(M, Eigen::ComputeFullV);
        const Eigen::VectorXd &s = svd.singularValues();
        const Eigen::MatrixXd &v = svd.matrixV();
        for (int j = 0; j < n; ++j) sv[j] = j < s.size() ? s(j) : 0.0;
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < n; ++j) V[i * n + j] = v(i, j);
    } catch (const std::bad_alloc &) {
        return -1;
    }
    for (int j = 0; j < n; ++j)
        if (!std::isfinite(sv[j])) return -1;
    return 0;
}
