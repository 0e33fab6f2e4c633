/* Pose forms: the exact inverse (deviation -> correction), quaternions, 4x4 transforms and
 * ROS REP 103 angles. References are hand derivations and point-by-point rigid motions. */
#include "support/test_util.h"

#include "headplan/hp_pose.h"

#include <math.h>
#include <string.h>

static const double PI = 3.14159265358979323846;
static double rad(double deg) { return deg * PI / 180.0; }

/* Moves q (pivot-centred, m) by pose xi: R·q + t. */
static void move(const double xi[6], const double q[3], double out[3])
{
    double R[9];
    hp_rotation(xi[3], xi[4], xi[5], R);
    for (int i = 0; i < 3; ++i)
        out[i] = R[i * 3] * q[0] + R[i * 3 + 1] * q[1] + R[i * 3 + 2] * q[2] + xi[i];
}

/* Largest distance (m) by which the correction fails to bring head points back. */
static double residual(const double dev[6], const double cor[6])
{
    /* Points 0.1 m from the pivot, about where the bladders touch the head. */
    const double pts[4][3] = {{0.1, 0, 0}, {0, 0.1, 0}, {0, 0, 0.1}, {-0.06, 0.05, -0.07}};
    double worst = 0.0;
    for (int k = 0; k < 4; ++k) {
        double a[3], b[3];
        move(dev, pts[k], a);
        move(cor, a, b);
        double d = sqrt((b[0] - pts[k][0]) * (b[0] - pts[k][0]) +
                        (b[1] - pts[k][1]) * (b[1] - pts[k][1]) +
                        (b[2] - pts[k][2]) * (b[2] - pts[k][2]));
        if (d > worst) worst = d;
    }
    return worst;
}

/* The correction of a deviation undoes it: every point returns to 1e-12 m (a few ulps of
 * 0.1 m lever arms times a handful of operations), and the composed 4x4 is the identity. */
static void test_inverse_is_exact(void **state)
{
    (void)state;
    const double devs[4][6] = {{5e-3, 0, 0, 0, 0, rad(3)},
                               {0, 0, 0, rad(3), rad(3), rad(3)},
                               {2e-3, -4e-3, 1e-3, rad(-7), rad(12), rad(25)},
                               {0, 0, 0, 0, 0, 0}};
    for (int c = 0; c < 4; ++c) {
        double cor[6], Md[16], Mc[16];
        hp_pose_inverse(devs[c], cor);
        assert_true(residual(devs[c], cor) < 1e-12);
        hp_pose_to_matrix(devs[c], Md);
        hp_pose_to_matrix(cor, Mc);
        for (int i = 0; i < 4; ++i)
            for (int j = 0; j < 4; ++j) {
                double s = 0;
                for (int k = 0; k < 4; ++k) s += Mc[i * 4 + k] * Md[k * 4 + j];
                hp_assert_close(s, i == j ? 1.0 : 0.0, 0, 1e-12);
            }
        /* The inverse of the inverse is the deviation again. */
        double back[6];
        hp_pose_inverse(cor, back);
        for (int i = 0; i < 6; ++i) hp_assert_close(back[i], devs[c][i], 0, 1e-12);
    }
}

/* The old rule (negate all six) leaves a 5 mm / 3° yaw deviation uncorrected by
 * |R(−3°)t − t| = 2·5 mm·sin(1.5°) = 0.2617 mm (hand derivation): more than 0.1 mm. */
static void test_negation_is_wrong(void **state)
{
    (void)state;
    const double dev[6] = {5e-3, 0, 0, 0, 0, rad(3)};
    double neg[6];
    for (int i = 0; i < 6; ++i) neg[i] = -dev[i];
    /* Every point moves by the same translation error (the rotation is undone exactly). */
    hp_assert_close(residual(dev, neg), 2 * 5e-3 * sin(rad(1.5)), 1e-12, 0);
    assert_true(residual(dev, neg) > 1e-4);
    /* 3°/3°/3° without translation: the rotation left is over 0.1° (hand: ~0.27°). */
    const double dev3[6] = {0, 0, 0, rad(3), rad(3), rad(3)};
    double neg3[6], R[9], Rn[9];
    for (int i = 0; i < 6; ++i) neg3[i] = -dev3[i];
    hp_rotation(dev3[3], dev3[4], dev3[5], R);
    hp_rotation(neg3[3], neg3[4], neg3[5], Rn);
    double tr = 0; /* trace of Rn·R = 1 + 2 cos(angle left) */
    for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k) tr += Rn[i * 3 + k] * R[k * 3 + i];
    double left_deg = acos((tr - 1) / 2) * 180 / PI;
    assert_true(left_deg > 0.1);
    hp_assert_close(left_deg, 0.27, 0.05, 0);
}

/* Quaternions: single-axis hand cases, both signs, round trips and refusals. */
static void test_quaternion(void **state)
{
    (void)state;
    const double t[3] = {1e-3, 2e-3, -3e-3};
    double xi[6];
    const double th = rad(10);
    const double qs[3][4] = {{cos(th / 2), sin(th / 2), 0, 0},
                             {cos(th / 2), 0, sin(th / 2), 0},
                             {cos(th / 2), 0, 0, sin(th / 2)}};
    for (int a = 0; a < 3; ++a) {
        assert_int_equal(hp_pose_from_quaternion(t, qs[a], xi, NULL), HP_OK);
        for (int i = 0; i < 3; ++i) hp_assert_close(xi[i], t[i], 0, 0);
        for (int i = 0; i < 3; ++i) hp_assert_close(xi[3 + i], i == a ? th : 0.0, 0, 1e-15);
        double nq[4] = {-qs[a][0], -qs[a][1], -qs[a][2], -qs[a][3]}, xn[6];
        assert_int_equal(hp_pose_from_quaternion(t, nq, xn, NULL), HP_OK);
        for (int i = 0; i < 6; ++i) hp_assert_close(xn[i], xi[i], 0, 1e-15);
    }
    const double pose[6] = {1e-3, -2e-3, 4e-3, rad(-20), rad(35), rad(170)};
    double tq[3], q[4], back[6];
    hp_pose_to_quaternion(pose, tq, q);
    assert_true(q[0] >= 0);
    assert_int_equal(hp_pose_from_quaternion(tq, q, back, NULL), HP_OK);
    for (int i = 0; i < 6; ++i) hp_assert_close(back[i], pose[i], 0, 1e-13);
    /* A tracker's five decimals: each component off by up to 5e-6, the norm by up to
     * 2e-5 (|q|_1 <= 2). Accepted and normalised: the pose equals the exact quaternion's to
     * the rounding's own size (an angle error of about 2·5e-6 rad per component). */
    double q5[4], x5[6];
    for (int i = 0; i < 4; ++i) q5[i] = round(q[i] * 1e5) * 1e-5;
    assert_int_equal(hp_pose_from_quaternion(tq, q5, x5, NULL), HP_OK);
    for (int i = 3; i < 6; ++i) hp_assert_close(x5[i], pose[i], 0, 4e-5);
    /* Four decimals off in the norm by up to 2e-4 (the tolerance is 1e-3): accepted. */
    const double q4[4] = {0.9998, 0.0175, 0, 0}; /* 2° about x, four decimals */
    assert_int_equal(hp_pose_from_quaternion(t, q4, xi, NULL), HP_OK);
    hp_assert_close(xi[3], rad(2), 0, 2e-4);
    /* Beyond 1e-3 it is not a rotation (an unnormalised or mis-ordered quaternion). */
    hp_diag d = {{0}};
    const double bad[4] = {1, 0.05, 0, 0}; /* norm 1.00125 */
    assert_int_equal(hp_pose_from_quaternion(t, bad, xi, &d), HP_ERR_INVALID);
    assert_non_null(strstr(d.text, "norm"));
    assert_non_null(strstr(d.text, "0.001"));
    const double half[4] = {0.5, 0.5, 0, 0}; /* norm 0.707 */
    assert_int_equal(hp_pose_from_quaternion(t, half, xi, &d), HP_ERR_INVALID);
    const double nan_q[4] = {NAN, 0, 0, 0};
    assert_int_equal(hp_pose_from_quaternion(t, nan_q, xi, NULL), HP_ERR_INVALID);
}

/* 4x4 transforms: round trip, and refusals of a reflection, a scaled block, a bad last row. */
static void test_matrix(void **state)
{
    (void)state;
    const double pose[6] = {3e-3, 0, -1e-3, rad(5), rad(-80), rad(-120)};
    double M[16], back[6];
    hp_pose_to_matrix(pose, M);
    assert_int_equal(hp_pose_from_matrix(M, back, NULL), HP_OK);
    for (int i = 0; i < 6; ++i) hp_assert_close(back[i], pose[i], 0, 1e-12);
    hp_diag d = {{0}};
    double R[16];
    memcpy(R, M, sizeof R);
    for (int j = 0; j < 3; ++j) R[j] = -R[j]; /* flip one row: det -1 */
    assert_int_equal(hp_pose_from_matrix(R, back, &d), HP_ERR_INVALID);
    assert_non_null(strstr(d.text, "reflection"));
    memcpy(R, M, sizeof R);
    R[0] *= 1.01;
    assert_int_equal(hp_pose_from_matrix(R, back, &d), HP_ERR_INVALID);
    assert_non_null(strstr(d.text, "orthonormal"));
    memcpy(R, M, sizeof R);
    R[15] = 2;
    assert_int_equal(hp_pose_from_matrix(R, back, &d), HP_ERR_INVALID);
    assert_non_null(strstr(d.text, "last row"));
}

/* REP 103 in the head body frame (x anterior = IEC Z, y left = IEC X, z superior = IEC Y):
 * the table of docs/kinematics.md, both ways, from the axes each angle turns about. */
static void test_rep103_table(void **state)
{
    (void)state;
    const double a = rad(10);
    /* IEC (x, y, z, pitch, roll, yaw) -> ROS (x, y, z, roll, pitch, yaw). */
    const double iec[6][6] = {{1e-3, 0, 0, 0, 0, 0}, {0, 1e-3, 0, 0, 0, 0}, {0, 0, 1e-3, 0, 0, 0},
                              {0, 0, 0, a, 0, 0},    {0, 0, 0, 0, a, 0},    {0, 0, 0, 0, 0, a}};
    const double ros[6][6] = {{0, 1e-3, 0, 0, 0, 0}, {0, 0, 1e-3, 0, 0, 0}, {1e-3, 0, 0, 0, 0, 0},
                              {0, 0, 0, 0, a, 0},    {0, 0, 0, 0, 0, a},    {0, 0, 0, a, 0, 0}};
    for (int c = 0; c < 6; ++c) {
        double got[6], back[6];
        hp_pose_to_rep103(iec[c], got);
        for (int i = 0; i < 6; ++i) hp_assert_close(got[i], ros[c][i], 0, 1e-15);
        hp_pose_from_rep103(ros[c], back);
        for (int i = 0; i < 6; ++i) hp_assert_close(back[i], iec[c][i], 0, 1e-15);
    }
    /* A general pose: the same physical motion of a point in both frames, and a round trip. */
    const double pose[6] = {1e-3, -2e-3, 3e-3, rad(12), rad(-7), rad(31)};
    double r[6], back[6];
    hp_pose_to_rep103(pose, r);
    hp_pose_from_rep103(r, back);
    for (int i = 0; i < 6; ++i) hp_assert_close(back[i], pose[i], 0, 1e-14);
    const double q_iec[3] = {0.03, -0.05, 0.08};
    const double q_ros[3] = {q_iec[2], q_iec[0], q_iec[1]};
    double m_iec[3], m_ros[3];
    move(pose, q_iec, m_iec);
    move(r, q_ros, m_ros); /* hp_rotation(roll, pitch, yaw) = Rz·Ry·Rx: REP 103's order */
    hp_assert_close(m_ros[0], m_iec[2], 0, 1e-15);
    hp_assert_close(m_ros[1], m_iec[0], 0, 1e-15);
    hp_assert_close(m_ros[2], m_iec[1], 0, 1e-15);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_inverse_is_exact), cmocka_unit_test(test_negation_is_wrong),
        cmocka_unit_test(test_quaternion),       cmocka_unit_test(test_matrix),
        cmocka_unit_test(test_rep103_table),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
