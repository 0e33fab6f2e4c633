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
    double K[9] = {0}, K2[9];
    int i1 = (k + 1) % 3, i2 = (k + 2) % 3;
    K[i2 * 3 + i1] = 1.0; /* (K v)_i2 = v_i1 */
    K[i1 * 3 + i2] = -1.0;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) K2[i * 3 + j] = (i == k && j == k ? 1.0 : 0.0) - (i == j);
    double id, fk, fk2;
    if (order == 0) {
        id = 1.0; fk = sn; fk2 = 1.0 - cs;
    } else if (order == 1) {
        id = 0.0; fk = cs; fk2 = sn;
    } else {
        id = 0.0; fk = -sn; fk2 = cs;
    }
    for (int i = 0; i < 9; ++i) M[i] = fk * K[i] + fk2 * K2[i];
    for (int i = 0; i < 3; ++i) M[i * 4] += id;
    if (order == 0) {
        /* Written out exactly so that R is orthogonal to rounding and exact at zero. */
        M[k * 4] = 1.0;
        M[i1 * 4] = cs;
        M[i2 * 4] = cs;
    }
}

static void mul3(const double A[9], const double B[9], double C[9])
{
    double T[9];
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            T[i * 3 + j] = A[i * 3] * B[j] + A[i * 3 + 1] * B[3 + j] + A[i * 3 + 2] * B[6 + j];
    memcpy(C, T, sizeof T);
}

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
     * shared (ZY[oz][oy], oz + oy <= 2): 16 matrix products instead of 20, same rounding. */
    double ZY[3][3][9];
    for (int oz = 0; oz <= maxord; ++oz)
        for (int oy = 0; oy + oz <= maxord; ++oy) mul3(F[2][oz], F[1][oy], ZY[oz][oy]);
    mul3(ZY[0][0], F[0][0], R);
    if (dR) {
        mul3(ZY[0][0], F[0][1], dR[0]);
        mul3(ZY[0][1], F[0][0], dR[1]);
        mul3(ZY[1][0], F[0][0], dR[2]);
    }
    if (d2R) {
        int ord[3];
        for (int j = 0; j < 3; ++j)
            for (int k = j; k < 3; ++k) {
                ord[0] = ord[1] = ord[2] = 0;
                ord[j] += 1;
                ord[k] += 1;
                mul3(ZY[ord[2]][ord[1]], F[0][ord[0]], d2R[j][k]);
                if (k != j) memcpy(d2R[k][j], d2R[j][k], sizeof d2R[j][k]);
            }
    }
}

void hp_rotation(double pitch, double roll, double yaw, double R[9])
{
    const double th[3] = {pitch, roll, yaw};
    hp_kin_rotation_derivs(th, R, NULL, NULL);
}
