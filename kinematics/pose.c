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

int hpi_kin_finite3(const double v[3])
{
    return isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]);
}

/* The rotation derivatives in closed form. With P = Rz·Ry (entries cz·cy, −sz, cz·sy /
 * sz·cy, cz, sz·sy / −sy, 0, cy), R = P·Rx has the columns P₀, cx·P₁ + sx·P₂ and
 * cx·P₂ − sx·P₁. A derivative turns one factor's (cos, sin) by a quarter turn per order, so
 * almost every derivative is a signed copy of entries already formed:
 *   ∂R/∂pitch = R·[e_x]× (columns 0, R₂, −R₁), ∂²/∂pitch² = (0, −R₁, −R₂);
 *   ∂R/∂yaw = [e_z]×·R (rows −R₁, R₀, 0),       ∂²/∂yaw² = (−R₀, −R₁, 0);
 *   ∂R/∂roll = Rz·∂Ry·Rx: rows (−cz·sy, cz·cy·sx, cz·cy·cx), (−sz·sy, sz·cy·sx, sz·cy·cx),
 *   (−cy, −sy·sx, −sy·cx); ∂²/∂roll²: (−cz·cy, −cz·sy·sx, −cz·sy·cx), (−sz·cy, −sz·sy·sx,
 *   −sz·sy·cx), (sy, −cy·sx, −cy·cx); the mixed ones apply [e_z]× on the left (yaw) or
 *   [e_x]× on the right (pitch) to the roll derivative or to each other.
 * Each entry is the very product or sum (same factors, same order, same rounding) that the
 * full matrix product Rz·Ry·Rx of the elementary factors and their derivatives sums, once
 * its exact zero terms are dropped and an exact negation is moved out: 24 products and 4
 * sums for all 90 entries instead of 16 sparse 3×3 products, equal to the product form to
 * the bit (up to the sign of a zero; tests/kinematics/test_pose.c). */

/* C = A·[e_x]× (pitch derivative on the right): columns 0, A₂, −A₁. */
static void right_x(const double A[9], double C[9])
{
    for (int i = 0; i < 3; ++i) {
        C[3 * i] = 0.0;
        C[3 * i + 1] = A[3 * i + 2];
        C[3 * i + 2] = -A[3 * i + 1];
    }
}

/* C = [e_z]×·A (yaw derivative on the left): rows −A₁, A₀, 0. */
static void left_z(const double A[9], double C[9])
{
    for (int j = 0; j < 3; ++j) {
        C[j] = -A[3 + j];
        C[3 + j] = A[j];
        C[6 + j] = 0.0;
    }
}

void hpi_kin_rotation_roll(const double th[3], double R[9], double Dr[9], double Drr[9])
{
    double sx = sin(th[0]), cx = cos(th[0]);
    double sy = sin(th[1]), cy = cos(th[1]);
    double sz = sin(th[2]), cz = cos(th[2]);
    double p00 = cz * cy, p02 = cz * sy, p10 = sz * cy, p12 = sz * sy;
    /* R = P·Rx; row 2 of P is (−sy, 0, cy). */
    R[0] = p00;
    R[1] = -sz * cx + p02 * sx;
    R[2] = sz * sx + p02 * cx; /* the product form's (−sz)·(−sx): the same bits */
    R[3] = p10;
    R[4] = cz * cx + p12 * sx;
    R[5] = -(cz * sx) + p12 * cx;
    R[6] = -sy;
    R[7] = cy * sx;
    R[8] = cy * cx;
    if (Dr) {
        Dr[0] = -p02;
        Dr[1] = p00 * sx;
        Dr[2] = p00 * cx;
        Dr[3] = -p12;
        Dr[4] = p10 * sx;
        Dr[5] = p10 * cx;
        Dr[6] = -cy;
        Dr[7] = -(sy * sx);
        Dr[8] = -(sy * cx);
    }
    if (Drr) {
        Drr[0] = -p00;
        Drr[1] = -(p02 * sx);
        Drr[2] = -(p02 * cx);
        Drr[3] = -p10;
        Drr[4] = -(p12 * sx);
        Drr[5] = -(p12 * cx);
        Drr[6] = sy;
        Drr[7] = -R[7];
        Drr[8] = -R[8];
    }
}

void hpi_kin_rotation_derivs(const double th[3], double R[9], double dR[3][9], double d2R[3][3][9])
{
    if (!dR) {
        hpi_kin_rotation_roll(th, R, NULL, NULL);
        return;
    }
    double *Dr = dR[1];
    hpi_kin_rotation_roll(th, R, Dr, d2R ? d2R[1][1] : NULL);
    right_x(R, dR[0]);
    left_z(R, dR[2]);
    if (!d2R) return;
    for (int i = 0; i < 3; ++i) {
        d2R[0][0][3 * i] = 0.0;
        d2R[0][0][3 * i + 1] = -R[3 * i + 1];
        d2R[0][0][3 * i + 2] = -R[3 * i + 2];
    }
    right_x(Dr, d2R[0][1]);
    right_x(dR[2], d2R[0][2]);
    left_z(Dr, d2R[1][2]);
    for (int j = 0; j < 6; ++j) d2R[2][2][j] = -R[j];
    for (int j = 6; j < 9; ++j) d2R[2][2][j] = 0.0;
    memcpy(d2R[1][0], d2R[0][1], sizeof d2R[0][1]);
    memcpy(d2R[2][0], d2R[0][2], sizeof d2R[0][2]);
    memcpy(d2R[2][1], d2R[1][2], sizeof d2R[1][2]);
}

void hp_rotation(double pitch, double roll, double yaw, double R[9])
{
    const double th[3] = {pitch, roll, yaw};
    hpi_kin_rotation_derivs(th, R, NULL, NULL);
}
