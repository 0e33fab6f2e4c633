/* Pose units and the rotation convention: the one place where clinical units (mm, degrees)
 * meet SI (m, rad), and where R = Rz(yaw)·Ry(roll)·Rx(pitch) is built. */
#include "kin_internal.h"
#include "common/units.h"

#include <math.h>
#include <stddef.h>
#include <string.h>

#define MM_PER_M 1000.0
#define DEG_PER_RAD HP_DEG_PER_RAD

void hp_pose_from_clinical(const double mm_deg[6], double xi[6])
{
    for (int i = 0; i < 3; ++i) xi[i] = mm_deg[i] / MM_PER_M;
    for (int i = 3; i < 6; ++i) xi[i] = mm_deg[i] / DEG_PER_RAD;
}

void hp_pose_to_clinical(const double xi[6], double mm_deg[6])
{
    for (int i = 0; i < 3; ++i) mm_deg[i] = xi[i] * MM_PER_M;
    for (int i = 3; i < 6; ++i) mm_deg[i] = xi[i] * DEG_PER_RAD;
}

const char *hp_pose_key(int i)
{
    static const char *const keys[HP_DOF] = {"x_mm",      "y_mm",     "z_mm",
                                             "pitch_deg", "roll_deg", "yaw_deg"};
    if (i < 0 || i >= HP_DOF) return "unknown";
    return keys[i];
}

int hp_kin_finite3(const double v[3])
{
    return isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]);
}

/* One elementary rotation about axis k by an angle with sine sn and cosine cs, or its first
 * or second derivative in the angle:
 * Rk = I + sin·K + (1 − cos)·K², K = [e_k]×, K² = e_k e_kᵀ − I. */
static void elementary(int k, double sn, double cs, int order, double M[9])
{
    /* The entries of I + sin·K + (1 − cos)·K² (order 0), cos·K + sin·K² (order 1) and
     * −sin·K + cos·K² (order 2), written out: the (k, k) entry, the diagonal of the 2×2
     * block on the other axes, and its lower (i2, i1) entry (the upper is its negative).
     * Order 0 is exact at zero and orthogonal to rounding. */
    int i1 = (k + 1) % 3, i2 = (k + 2) % 3;
    double dk = order == 0 ? 1.0 : 0.0;
    double cd = order == 0 ? cs : order == 1 ? -sn : -cs;
    double sl = order == 0 ? sn : order == 1 ? cs : -sn;
    for (int i = 0; i < 9; ++i) M[i] = 0.0;
    M[k * 4] = dk;
    M[i1 * 4] = cd;
    M[i2 * 4] = cd;
    M[i2 * 3 + i1] = sl;
    M[i1 * 3 + i2] = -sl;
}

/* C = A·M for an elementary factor M of axis k (elementary): M's only non-zeros are its
 * (k, k) entry and the 2×2 block on the other two axes, so each entry of C is one product
 * or two, summed in index order as the full product sums them; the full product only adds
 * exact zeros to that, so C is the same to the bit (up to the sign of a zero). */
static inline void mul_elem(const double A[9], const double M[9], int k, double C[9])
{
    int i1 = (k + 1) % 3, i2 = (k + 2) % 3;
    int lo = i1 < i2 ? i1 : i2, hi = i1 < i2 ? i2 : i1;
    double T[9];
    for (int i = 0; i < 3; ++i) {
        const double *a = A + 3 * i;
        T[3 * i + k] = a[k] * M[4 * k];
        T[3 * i + lo] = a[lo] * M[3 * lo + lo] + a[hi] * M[3 * hi + lo];
        T[3 * i + hi] = a[lo] * M[3 * lo + hi] + a[hi] * M[3 * hi + hi];
    }
    memcpy(C, T, sizeof T);
}

/* The two factors used, each with its axis a constant (the index arithmetic folds away). */
static void mul_x(const double A[9], const double M[9], double C[9]) { mul_elem(A, M, 0, C); }
static void mul_y(const double A[9], const double M[9], double C[9]) { mul_elem(A, M, 1, C); }

void hp_kin_rotation_derivs(const double th[3], double R[9], double dR[3][9],
                            double d2R[3][3][9])
{
    double F[3][3][9]; /* [axis][order] */
    int maxord = d2R ? 2 : dR ? 1 : 0;
    for (int k = 0; k < 3; ++k) {
        double sn = sin(th[k]), cs = cos(th[k]);
        for (int o = 0; o <= maxord; ++o) elementary(k, sn, cs, o, F[k][o]);
    }
    /* Every factor is (Z·Y)·X with the orders of yaw, roll and pitch; the products Z·Y are
     * shared (ZY[oz][oy], oz + oy <= 2): 16 products instead of 20, each by a sparse
     * elementary factor (mul_elem), with the rounding of the full matrix products. */
    double ZY[3][3][9];
    for (int oz = 0; oz <= maxord; ++oz)
        for (int oy = 0; oy + oz <= maxord; ++oy) mul_y(F[2][oz], F[1][oy], ZY[oz][oy]);
    mul_x(ZY[0][0], F[0][0], R);
    if (dR) {
        mul_x(ZY[0][0], F[0][1], dR[0]);
        mul_x(ZY[0][1], F[0][0], dR[1]);
        mul_x(ZY[1][0], F[0][0], dR[2]);
    }
    if (d2R) {
        int ord[3];
        for (int j = 0; j < 3; ++j)
            for (int k = j; k < 3; ++k) {
                ord[0] = ord[1] = ord[2] = 0;
                ord[j] += 1;
                ord[k] += 1;
                mul_x(ZY[ord[2]][ord[1]], F[0][ord[0]], d2R[j][k]);
                if (k != j) memcpy(d2R[k][j], d2R[j][k], sizeof d2R[j][k]);
            }
    }
}

void hp_rotation(double pitch, double roll, double yaw, double R[9])
{
    const double th[3] = {pitch, roll, yaw};
    hp_kin_rotation_derivs(th, R, NULL, NULL);
}
