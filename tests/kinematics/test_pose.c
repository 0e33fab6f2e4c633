/* Pose units and the rotation convention R = Rz(yaw)·Ry(roll)·Rx(pitch). */
#include "support/test_util.h"

#include "headplan/hp_contact.h"
#include "kinematics/kin_internal.h"

#include <string.h>

static const double PI = 3.14159265358979323846;

static void test_clinical_round_trip(void **state)
{
    (void)state;
    const double c[6] = {1.0, -2.5, 10.0, 90.0, -45.0, 180.0};
    double xi[6], back[6];
    hp_pose_from_clinical(c, xi);
    /* Hand values: 1 mm = 1e-3 m, 90° = π/2; exact to a few ulps. */
    hp_assert_close(xi[0], 1e-3, 1e-15, 0);
    hp_assert_close(xi[1], -2.5e-3, 1e-15, 0);
    hp_assert_close(xi[3], PI / 2, 1e-15, 0);
    hp_assert_close(xi[4], -PI / 4, 1e-15, 0);
    hp_assert_close(xi[5], PI, 1e-15, 0);
    hp_pose_to_clinical(xi, back);
    for (int i = 0; i < 6; ++i) hp_assert_close(back[i], c[i], 1e-15, 0);
    assert_string_equal(hp_pose_key(0), "x_mm");
    assert_string_equal(hp_pose_key(HP_PITCH), "pitch_deg");
    assert_string_equal(hp_pose_key(HP_YAW), "yaw_deg");
    assert_string_equal(hp_pose_key(6), "unknown");
    assert_string_equal(hp_pose_key(-1), "unknown");
}

static void mat_close(const double A[9], const double B[9], double tol)
{
    for (int i = 0; i < 9; ++i) hp_assert_close(A[i], B[i], 0, tol);
}

static void matmul(const double A[9], const double B[9], double C[9])
{
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            C[i * 3 + j] = 0;
            for (int k = 0; k < 3; ++k) C[i * 3 + j] += A[i * 3 + k] * B[k * 3 + j];
        }
}

/* 90° about each axis, written by hand from the right-hand rule: pitch +90° takes +Y to +Z,
 * roll +90° takes +Z to +X, yaw +90° takes +X to +Y. Entries are sin/cos of π/2: 1e-15. */
static void test_rotation_90(void **state)
{
    (void)state;
    double R[9];
    const double Rx[9] = {1, 0, 0, 0, 0, -1, 0, 1, 0};
    const double Ry[9] = {0, 0, 1, 0, 1, 0, -1, 0, 0};
    const double Rz[9] = {0, -1, 0, 1, 0, 0, 0, 0, 1};
    hp_rotation(PI / 2, 0, 0, R);
    mat_close(R, Rx, 1e-15);
    hp_rotation(0, PI / 2, 0, R);
    mat_close(R, Ry, 1e-15);
    hp_rotation(0, 0, PI / 2, R);
    mat_close(R, Rz, 1e-15);
    /* Order: pitch first. R = Rz·Ry·Rx; with pitch 90° and yaw 90°, +Y goes to +Z by the
     * pitch, and the yaw leaves +Z alone: R·e_y = e_z. The other order (Rx·Rz) would send
     * +Y to −X and then stay there. */
    hp_rotation(PI / 2, 0, PI / 2, R);
    double want[9], T[9];
    matmul(Ry, Rx, T);
    matmul(Rz, Rx, want); /* roll 0 */
    mat_close(R, want, 1e-15);
    hp_assert_close(R[1 * 3 + 1], 0.0, 0, 1e-15); /* column 1 = R e_y */
    hp_assert_close(R[2 * 3 + 1], 1.0, 0, 1e-15);
    hp_assert_close(R[0 * 3 + 1], 0.0, 0, 1e-15);
    /* All three: Rz(90)·Ry(90)·Rx(90). */
    double ZYX[9];
    matmul(Rz, T, ZYX);
    hp_rotation(PI / 2, PI / 2, PI / 2, R);
    mat_close(R, ZYX, 1e-15);
}

/* Orthogonality and det 1 for arbitrary angles (rounding of a 3-term dot product: 1e-15). */
static void test_rotation_orthogonal(void **state)
{
    (void)state;
    const double angles[4][3] = {
        {0.3, -1.1, 2.5}, {-3.0, 0.01, 0.7}, {1e-9, 2e-9, -3e-9}, {PI, -PI / 3, PI / 7}};
    for (int a = 0; a < 4; ++a) {
        double R[9], RtR[9], Rt[9];
        hp_rotation(angles[a][0], angles[a][1], angles[a][2], R);
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) Rt[i * 3 + j] = R[j * 3 + i];
        matmul(Rt, R, RtR);
        const double I[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
        mat_close(RtR, I, 2e-15);
        double det = R[0] * (R[4] * R[8] - R[5] * R[7]) - R[1] * (R[3] * R[8] - R[5] * R[6]) +
                     R[2] * (R[3] * R[7] - R[4] * R[6]);
        hp_assert_close(det, 1.0, 0, 2e-15);
        /* Against the product of single-axis rotations built independently. */
        double X[9], Y[9], Z[9], ZY[9], want[9];
        hp_rotation(angles[a][0], 0, 0, X);
        hp_rotation(0, angles[a][1], 0, Y);
        hp_rotation(0, 0, angles[a][2], Z);
        double cx = cos(angles[a][0]), sx = sin(angles[a][0]);
        const double Xh[9] = {1, 0, 0, 0, cx, -sx, 0, sx, cx};
        mat_close(X, Xh, 1e-16);
        matmul(Z, Y, ZY);
        matmul(ZY, X, want);
        mat_close(R, want, 1e-15);
    }
}

/* Rotation derivatives against central differences (h = 1e-5: truncation h²/6 ≈ 2e-11,
 * rounding 1e-16/h ≈ 1e-11; tolerance 1e-9). */
static void test_rotation_derivs(void **state)
{
    (void)state;
    const double th[3] = {0.2, -0.4, 0.9};
    double R[9], dR[3][9], d2R[3][3][9];
    hpi_kin_rotation_derivs(th, R, dR, d2R);
    const double h = 1e-5;
    for (int j = 0; j < 3; ++j) {
        double tp[3], tm[3], Rp[9], Rm[9], dRp[3][9], dRm[3][9];
        memcpy(tp, th, sizeof tp);
        memcpy(tm, th, sizeof tm);
        tp[j] += h;
        tm[j] -= h;
        hpi_kin_rotation_derivs(tp, Rp, dRp, NULL);
        hpi_kin_rotation_derivs(tm, Rm, dRm, NULL);
        for (int i = 0; i < 9; ++i) {
            hp_assert_close(dR[j][i], (Rp[i] - Rm[i]) / (2 * h), 0, 1e-9);
            for (int k = 0; k < 3; ++k)
                hp_assert_close(d2R[k][j][i], (dRp[k][i] - dRm[k][i]) / (2 * h), 0, 1e-9);
        }
    }
}

/* The derivatives' closed forms on many angles: R = Rz(γ)Ry(β)Rx(α) and every first and
 * second derivative built here from the textbook elementary matrices (and their
 * derivatives: the 2×2 block of cos/sin turned by a quarter turn per order, the axis entry
 * 0) by plain 3×3 products (the library's own former method, kept here as the reference).
 * The library writes every entry in closed form as the same non-zero products summed in
 * the same order, an exact negation moved out, so every entry must be equal (a bound of 0
 * ulps; ==: only the sign of a zero may differ). Random angles in ±0.1 and ±3.2 rad, some
 * zero, and every combination of the special angles 0, ±π/2, ±π (where sines or cosines
 * round to ±6e-17 or ±1e-16 rather than 0, and products of them underflow nothing). */
static void elem_ref(int axis, double t, int order, double M[9])
{
    double c = cos(t), s = sin(t);
    double cd = order == 0 ? c : order == 1 ? -s : -c; /* d^o/dt^o of cos */
    double sd = order == 0 ? s : order == 1 ? c : -s;  /* d^o/dt^o of sin */
    double one = order == 0 ? 1.0 : 0.0;
    double X[9] = {one, 0, 0, 0, cd, -sd, 0, sd, cd};
    double Y[9] = {cd, 0, sd, 0, one, 0, -sd, 0, cd};
    double Z[9] = {cd, -sd, 0, sd, cd, 0, 0, 0, one};
    memcpy(M, axis == 0 ? X : axis == 1 ? Y : Z, sizeof X);
}

static void mul_ref(const double A[9], const double B[9], double C[9])
{
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            C[i * 3 + j] = A[i * 3] * B[j] + A[i * 3 + 1] * B[3 + j] + A[i * 3 + 2] * B[6 + j];
}

static void product_ref(const double th[3], const int ord[3], double P[9])
{
    double X[9], Y[9], Z[9], T[9];
    elem_ref(0, th[0], ord[0], X);
    elem_ref(1, th[1], ord[1], Y);
    elem_ref(2, th[2], ord[2], Z);
    mul_ref(Z, Y, T);
    mul_ref(T, X, P);
}

static void test_rotation_derivs_closed_form(void **state)
{
    (void)state;
    uint64_t r = 99;
    const double special[5] = {0.0, PI / 2, -PI / 2, PI, -PI};
    const int nspecial = 5 * 5 * 5;
    for (int it = 0; it < 20000 + nspecial; ++it) {
        double th[3];
        for (int i = 0; i < 3; ++i) {
            r = r * 6364136223846793005ull + 1442695040888963407ull;
            th[i] = ((double)(r >> 11) * 0x1.0p-53 - 0.5) * (it % 2 ? 6.4 : 0.2);
        }
        if (it % 50 == 0) th[it % 3] = 0.0;
        if (it >= 20000) {
            int c = it - 20000;
            th[0] = special[c % 5];
            th[1] = special[(c / 5) % 5];
            th[2] = special[c / 25];
        }
        double R[9], dR[3][9], d2R[3][3][9], P[9];
        hpi_kin_rotation_derivs(th, R, dR, d2R);
        int ord[3] = {0, 0, 0};
        product_ref(th, ord, P);
        for (int i = 0; i < 9; ++i) assert_true(R[i] == P[i]);
        for (int j = 0; j < 3; ++j) {
            int o1[3] = {0, 0, 0};
            o1[j] = 1;
            product_ref(th, o1, P);
            for (int i = 0; i < 9; ++i) assert_true(dR[j][i] == P[i]);
            for (int k = 0; k < 3; ++k) {
                int o2[3] = {0, 0, 0};
                o2[j] += 1;
                o2[k] += 1;
                product_ref(th, o2, P);
                for (int i = 0; i < 9; ++i) assert_true(d2R[j][k][i] == P[i]);
            }
        }
    }
}

static void test_names(void **state)
{
    (void)state;
    hp_level l;
    hp_head_shape s;
    assert_int_equal(hp_level_parse("surface", &l), HP_OK);
    assert_int_equal(l, HP_LEVEL_SURFACE);
    assert_int_equal(hp_level_parse("auto", &l), HP_OK);
    assert_int_equal(l, HP_LEVEL_AUTO);
    assert_int_equal(hp_level_parse("Surface", &l), HP_ERR_INVALID);
    assert_string_equal(hp_level_name(HP_LEVEL_PLANE), "plane");
    assert_string_equal(hp_level_name((hp_level)99), "unknown");
    assert_int_equal(hp_head_shape_parse("ellipsoid", &s), HP_OK);
    assert_int_equal(s, HP_HEAD_ELLIPSOID);
    assert_int_equal(hp_head_shape_parse("cube", &s), HP_ERR_INVALID);
    assert_string_equal(hp_head_shape_name(HP_HEAD_SPHERE), "sphere");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_clinical_round_trip),         cmocka_unit_test(test_rotation_90),
        cmocka_unit_test(test_rotation_orthogonal),         cmocka_unit_test(test_rotation_derivs),
        cmocka_unit_test(test_rotation_derivs_closed_form), cmocka_unit_test(test_names),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
