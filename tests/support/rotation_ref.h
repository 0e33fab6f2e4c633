/* The tests' own rotation formulas, written out here and not the library's, so that the
 * library's pose conventions are checked against an independent spelling of them:
 * R = Rz(yaw)·Ry(roll)·Rx(pitch) for angles th = (pitch, roll, yaw) [rad], its rotation angle,
 * and a rotation about a unit axis (Rodrigues) as a pose's Z-Y-X angles. */
#ifndef TESTS_SUPPORT_ROTATION_REF_H
#define TESTS_SUPPORT_ROTATION_REF_H

#include <math.h>
#include <string.h>

static inline void ref_rotation(const double th[3], double R[9])
{
    double ca = cos(th[0]), sa = sin(th[0]), cb = cos(th[1]), sb = sin(th[1]);
    double cg = cos(th[2]), sg = sin(th[2]);
    double M[9] = {cg * cb,
                   cg * sb * sa - sg * ca,
                   cg * sb * ca + sg * sa,
                   sg * cb,
                   sg * sb * sa + cg * ca,
                   sg * sb * ca - cg * sa,
                   -sb,
                   cb * sa,
                   cb * ca};
    memcpy(R, M, sizeof M);
}

/* The rotation angle of ref_rotation(th) [rad], from the matrix (atan2 of the axis part's
 * half-norm and the trace's, accurate at every angle). */
static inline double ref_rotation_angle(const double th[3])
{
    double R[9];
    ref_rotation(th, R);
    double s = 0.5 * sqrt((R[7] - R[5]) * (R[7] - R[5]) + (R[2] - R[6]) * (R[2] - R[6]) +
                          (R[3] - R[1]) * (R[3] - R[1]));
    return atan2(s, 0.5 * (R[0] + R[4] + R[8] - 1.0));
}

/* Rotation of angle th (rad) about unit axis u (Rodrigues) as a pose: no translation, the
 * Z-Y-X angles of the matrix. */
static inline void ref_axis_angle_pose(const double u[3], double th, double xi[6])
{
    double c = cos(th), s = sin(th), v = 1.0 - c, R[9];
    R[0] = c + u[0] * u[0] * v;
    R[1] = u[0] * u[1] * v - u[2] * s;
    R[2] = u[0] * u[2] * v + u[1] * s;
    R[3] = u[1] * u[0] * v + u[2] * s;
    R[4] = c + u[1] * u[1] * v;
    R[5] = u[1] * u[2] * v - u[0] * s;
    R[6] = u[2] * u[0] * v - u[1] * s;
    R[7] = u[2] * u[1] * v + u[0] * s;
    R[8] = c + u[2] * u[2] * v;
    xi[0] = xi[1] = xi[2] = 0.0;
    xi[4] = -asin(fmax(-1.0, fmin(1.0, R[6])));
    xi[3] = atan2(R[7], R[8]);
    xi[5] = atan2(R[3], R[0]);
}

#endif
