/* Poses: a 6-DOF correction, its units and its other forms (quaternion, matrix, ROS).
 *
 * Frame: IEC 61217 patient-support axes, head-first supine: +X lateral (patient's left),
 * +Y longitudinal (superior), +Z vertical (anterior, up). A correction (pose) is the vector
 * xi = [x, y, z, pitch, roll, yaw] in metres and radians: pitch about X, roll about Y, yaw
 * about Z, right-hand positive, applied about the layout's pivot, with
 * R = Rz(yaw)·Ry(roll)·Rx(pitch) (pitch applied first). A head point q moves to
 * pivot + R·(q − pivot) + t.
 *
 * Functions are reentrant and allocate nothing unless they say so. */
#ifndef HP_POSE_H
#define HP_POSE_H

#include "headplan/hp_common.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Index of each component of a pose vector. */
enum { HP_X = 0, HP_Y, HP_Z, HP_PITCH, HP_ROLL, HP_YAW, HP_DOF };

/* Clinical units (mm, degrees) <-> SI (m, rad), the one place these conversions live. */
HP_API void hp_pose_from_clinical(const double mm_deg[6], double xi[6]);
HP_API void hp_pose_to_clinical(const double xi[6], double mm_deg[6]);
/* Names of the pose components as a user types them: "x_mm" ... "yaw_deg". */
HP_API const char *hp_pose_key(int i);

/* Rotation matrix R = Rz(yaw)·Ry(roll)·Rx(pitch), row-major 3×3. */
HP_API void hp_rotation(double pitch, double roll, double yaw, double R[9]);

/* The angles (rad) of a rotation matrix R (row-major, orthonormal) in the convention above:
 * pitch and yaw in (−π, π], roll in [−π/2, π/2]. At roll = ±π/2 (gimbal lock) any split of
 * pitch and yaw that gives R is returned. */
HP_API void hp_rotation_angles(const double R[9], double *pitch, double *roll, double *yaw);

/* The exact inverse of a pose about the pivot: the rotation Rᵀ and translation −Rᵀ·t, in
 * the angle convention above. A measured deviation's correction is its inverse (not its
 * negation: −xi leaves 0.26 mm of a 5 mm / 3° yaw deviation uncorrected). inv may be xi. */
HP_API void hp_pose_inverse(const double xi[6], double inv[6]);

/* A pose from translation t [m] and a unit quaternion q = (w, x, y, z) (Hamilton, active:
 * the same rotation R as the pose's). |q| must be 1 within 1e-6 (it is normalised); else
 * HP_ERR_INVALID, as for non-finite input. q and −q give the same pose. */
HP_API hp_error hp_pose_from_quaternion(const double t[3], const double q[4], double xi[6],
                                        hp_diag *diag);
/* The pose's translation t [m] and its unit quaternion (w >= 0). */
HP_API void hp_pose_to_quaternion(const double xi[6], double t[3], double q[4]);

/* A pose from a 4×4 rigid transform M (row-major, translation column in metres) in the
 * frame centred on the pivot: M maps q − pivot to R·(q − pivot) + t. The last row must be
 * exactly 0 0 0 1 and the 3×3 block a rotation (RᵀR = I within 1e-6, det +1); else
 * HP_ERR_INVALID naming what is wrong. */
HP_API hp_error hp_pose_from_matrix(const double M[16], double xi[6], hp_diag *diag);
/* The pose as a 4×4 rigid transform (same layout). */
HP_API void hp_pose_to_matrix(const double xi[6], double M[16]);

/* ROS REP 103: the pose in the head's body frame x anterior (IEC +Z), y patient's left
 * (IEC +X), z superior (IEC +Y), origin at the pivot, as ros = [x, y, z (m), roll, pitch,
 * yaw (rad)] with R = Rz(yaw)·Ry(pitch)·Rx(roll). Exact (through the rotation matrix), so
 * the two calls invert each other; the mapping of single angles is tabled in
 * docs/kinematics.md. */
HP_API void hp_pose_to_rep103(const double xi[6], double ros[6]);
HP_API void hp_pose_from_rep103(const double ros[6], double xi[6]);

/* Angle [rad] of the rotation of pose xi (pitch, roll, yaw in xi[3..5]) about its own axis,
 * in [0, pi]: the quantity hp_identifiable.rot_limit bounds. */
HP_API double hp_pose_rotation_angle(const double xi[6]);

#ifdef __cplusplus
}
#endif
#endif
