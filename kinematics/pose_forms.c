/* Other forms of a pose: rotation matrix angles, the exact inverse rigid motion, quaternions,
 * 4×4 rigid transforms and ROS REP 103 roll/pitch/yaw (see hp_pose.h and
 * docs/kinematics.md, "Other pose forms"). */
#include "kin_internal.h"

#include <math.h>
#include <string.h>

/* How far a given matrix may be from orthonormal before we refuse it: trackers print 6-9
 * significant digits, so 1e-6 accepts their rounding and still rejects a wrong column order
 * or a scaled block. */
#define FORM_TOL 1e-6
/* A quaternion's norm is checked more loosely: trackers print quaternions with 4-5
 * decimals, which puts the norm up to 2e-4 (4 decimals: 4 components off by 5e-5, |q|_1 <= 2)
 * from 1. The norm only says whether q is meant as a rotation (what is not: an unnormalised
 * or mis-ordered quaternion, a rotation vector, is off by far more than 1e-3); the
 * normalisation that follows removes its size exactly, so accepting 1e-3 costs no accuracy
 * beyond the digits given. */
#define QUAT_NORM_TOL 1e-3

void hp_rotation_angles(const double R[9], double *pitch, double *roll, double *yaw)
{
    /* R20 = −sin(roll), R21 = cos(roll)·sin(pitch), R22 = cos(roll)·cos(pitch),
     * R10 = sin(yaw)·cos(roll), R00 = cos(yaw)·cos(roll). atan2 of the hypot keeps full
     * precision near roll = ±90°, where asin would not. */
    *roll = atan2(-R[6], hypot(R[7], R[8]));
    *pitch = atan2(R[7], R[8]);
    *yaw = atan2(R[3], R[0]);
}

static void angles_into(const double R[9], double xi[6])
{
    hp_rotation_angles(R, &xi[HP_PITCH], &xi[HP_ROLL], &xi[HP_YAW]);
}

static void transpose_apply(const double R[9], const double v[3], double out[3])
{
    for (int i = 0; i < 3; ++i) out[i] = R[i] * v[0] + R[3 + i] * v[1] + R[6 + i] * v[2];
}

void hp_pose_inverse(const double xi[6], double inv[6])
{
    double R[9], Rt[9], t[3];
    hp_rotation(xi[HP_PITCH], xi[HP_ROLL], xi[HP_YAW], R);
    transpose_apply(R, xi, t);
    for (int i = 0; i < 3; ++i) {
        inv[i] = -t[i];
        for (int j = 0; j < 3; ++j) Rt[i * 3 + j] = R[j * 3 + i];
    }
    angles_into(Rt, inv);
    for (int i = 0; i < 6; ++i)
        if (inv[i] == 0.0) inv[i] = 0.0; /* no −0 in outputs */
}

hp_error hp_pose_from_quaternion(const double t[3], const double q[4], double xi[6], hp_diag *diag)
{
    for (int i = 0; i < 4; ++i)
        if (!isfinite(q[i])) return hp_diag_set(diag, HP_ERR_INVALID, "quaternion: not finite");
    if (!hpi_kin_finite3(t)) return hp_diag_set(diag, HP_ERR_INVALID, "translation: not finite");
    double norm = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    if (!(fabs(norm - 1.0) <= QUAT_NORM_TOL))
        return hp_diag_set(diag, HP_ERR_INVALID,
                           "quaternion: norm %.9g is not 1 (within %g): not a rotation", norm,
                           QUAT_NORM_TOL);
    double w = q[0] / norm, x = q[1] / norm, y = q[2] / norm, z = q[3] / norm;
    const double R[9] = {1 - 2 * (y * y + z * z), 2 * (x * y - w * z),     2 * (x * z + w * y),
                         2 * (x * y + w * z),     1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
                         2 * (x * z - w * y),     2 * (y * z + w * x),     1 - 2 * (x * x + y * y)};
    memcpy(xi, t, 3 * sizeof *xi);
    angles_into(R, xi);
    return HP_OK;
}

hp_error hp_pose_from_matrix(const double M[16], double xi[6], hp_diag *diag)
{
    for (int i = 0; i < 16; ++i)
        if (!isfinite(M[i])) return hp_diag_set(diag, HP_ERR_INVALID, "matrix: not finite");
    if (M[12] != 0.0 || M[13] != 0.0 || M[14] != 0.0 || M[15] != 1.0)
        return hp_diag_set(diag, HP_ERR_INVALID, "matrix: last row must be 0 0 0 1");
    double R[9];
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) R[i * 3 + j] = M[i * 4 + j];
    /* RᵀR = I and det R = +1: a rotation, not a reflection or a scaled matrix. */
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            double d = R[i] * R[j] + R[3 + i] * R[3 + j] + R[6 + i] * R[6 + j];
            if (!(fabs(d - (i == j)) <= FORM_TOL))
                return hp_diag_set(diag, HP_ERR_INVALID,
                                   "matrix: the 3x3 block is not orthonormal (within %g)",
                                   FORM_TOL);
        }
    double det = R[0] * (R[4] * R[8] - R[5] * R[7]) - R[1] * (R[3] * R[8] - R[5] * R[6]) +
                 R[2] * (R[3] * R[7] - R[4] * R[6]);
    if (det < 0)
        return hp_diag_set(diag, HP_ERR_INVALID, "matrix: a reflection (det -1), not a rotation");
    xi[0] = M[3];
    xi[1] = M[7];
    xi[2] = M[11];
    angles_into(R, xi);
    return HP_OK;
}

void hp_pose_to_matrix(const double xi[6], double M[16])
{
    double R[9];
    hp_rotation(xi[HP_PITCH], xi[HP_ROLL], xi[HP_YAW], R);
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) M[i * 4 + j] = R[i * 3 + j];
        M[i * 4 + 3] = xi[i];
    }
    M[12] = M[13] = M[14] = 0.0;
    M[15] = 1.0;
}

void hp_pose_to_quaternion(const double xi[6], double t[3], double q[4])
{
    double R[9];
    hp_rotation(xi[HP_PITCH], xi[HP_ROLL], xi[HP_YAW], R);
    memcpy(t, xi, 3 * sizeof *t);
    /* Shepperd: divide by the largest of the four candidates, never by a small number. */
    double tr = R[0] + R[4] + R[8];
    if (tr >= R[0] && tr >= R[4] && tr >= R[8]) {
        double s = 2.0 * sqrt(1.0 + tr);
        q[0] = 0.25 * s;
        q[1] = (R[7] - R[5]) / s;
        q[2] = (R[2] - R[6]) / s;
        q[3] = (R[3] - R[1]) / s;
    } else if (R[0] >= R[4] && R[0] >= R[8]) {
        double s = 2.0 * sqrt(1.0 + R[0] - R[4] - R[8]);
        q[0] = (R[7] - R[5]) / s;
        q[1] = 0.25 * s;
        q[2] = (R[1] + R[3]) / s;
        q[3] = (R[2] + R[6]) / s;
    } else if (R[4] >= R[8]) {
        double s = 2.0 * sqrt(1.0 + R[4] - R[0] - R[8]);
        q[0] = (R[2] - R[6]) / s;
        q[1] = (R[1] + R[3]) / s;
        q[2] = 0.25 * s;
        q[3] = (R[5] + R[7]) / s;
    } else {
        double s = 2.0 * sqrt(1.0 + R[8] - R[0] - R[4]);
        q[0] = (R[3] - R[1]) / s;
        q[1] = (R[2] + R[6]) / s;
        q[2] = (R[5] + R[7]) / s;
        q[3] = 0.25 * s;
    }
    if (q[0] < 0) /* q and −q are the same rotation: give the one with w >= 0 */
        for (int i = 0; i < 4; ++i) q[i] = -q[i];
}

/* The REP 103 head frame in IEC axes: x anterior (+Z), y patient's left (+X), z superior
 * (+Y). P maps IEC coordinates to REP 103 ones: v_ros = P·v_iec. */
static const double P_ROS[9] = {0, 0, 1, 1, 0, 0, 0, 1, 0};

static void conjugate(const double P[9], const double R[9], int forward, double out[9])
{
    /* forward: P·R·Pᵀ; otherwise Pᵀ·R·P. */
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            double s = 0.0;
            for (int a = 0; a < 3; ++a)
                for (int b = 0; b < 3; ++b)
                    s += (forward ? P[i * 3 + a] * P[j * 3 + b] : P[a * 3 + i] * P[b * 3 + j]) *
                         R[a * 3 + b];
            out[i * 3 + j] = s;
        }
}

static void rep103_map(const double in[6], double out[6], int forward)
{
    double R[9], Q[9];
    /* Both conventions compose Rz·Ry·Rx of the angles about their own x, y, z axes. */
    hp_rotation(in[3], in[4], in[5], R);
    conjugate(P_ROS, R, forward, Q);
    for (int i = 0; i < 3; ++i) {
        double s = 0.0;
        for (int a = 0; a < 3; ++a) s += (forward ? P_ROS[i * 3 + a] : P_ROS[a * 3 + i]) * in[a];
        out[i] = s;
    }
    hp_rotation_angles(Q, &out[3], &out[4], &out[5]);
}

void hp_pose_to_rep103(const double xi[6], double ros[6]) { rep103_map(xi, ros, 1); }

void hp_pose_from_rep103(const double ros[6], double xi[6]) { rep103_map(ros, xi, 0); }
