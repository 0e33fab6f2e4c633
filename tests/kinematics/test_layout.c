/* Layout validation (every bad field gives a message naming the bladder and the field),
 * placement by touch point, and the layout analysis. */
#include "test_util.h"

#include "default_layout.h"

#include <string.h>

static void expect_bad(const hp_layout *in, hp_error code, const char *s1, const char *s2)
{
    hp_layout L = *in;
    hp_diag d;
    d.text[0] = '\0';
    hp_error err = hp_layout_prepare(&L, &d);
    if (err != code || !strstr(d.text, s1) || (s2 && !strstr(d.text, s2))) {
        print_error("got %s '%s', want %s with '%s' and '%s'\n", hp_error_name(err), d.text,
                    hp_error_name(code), s1, s2 ? s2 : "");
        fail();
    }
    assert_int_equal(L.prepared, 0);
}

static void test_invalid_layouts(void **state)
{
    (void)state;
    hp_layout G;
    hp_head h = default_head();
    assert_int_equal(default_layout_on(&G, &h, 0.0), 0);
    hp_layout L;
    hp_diag d;
    L = G;
    assert_int_equal(hp_layout_prepare(&L, &d), HP_OK);
    assert_int_equal(L.prepared, 1);

#define BAD(stmt, code, s1, s2) do { L = G; stmt; expect_bad(&L, code, s1, s2); } while (0)
    BAD(L.head.semi_axes[1] = -0.1, HP_ERR_INVALID, "head", "semi_axes.y");
    BAD(L.head.semi_axes[2] = NAN, HP_ERR_INVALID, "head", "semi_axes.z");
    BAD(L.head.center[0] = INFINITY, HP_ERR_INVALID, "head", "center");
    BAD(L.head.shape = (hp_head_shape)7, HP_ERR_INVALID, "head", "shape");
    BAD(L.head.mass = -1, HP_ERR_INVALID, "head", "mass");
    BAD(L.pivot[2] = NAN, HP_ERR_INVALID, "pivot", NULL);
    BAD(L.n = 0, HP_ERR_INVALID, "count", NULL);
    BAD(L.n = HP_MAX_BLADDERS + 1, HP_ERR_INVALID, "count", NULL);
    BAD(L.bladders[2].name[0] = '\0', HP_ERR_INVALID, "bladder #3", "name");
    BAD(memset(L.bladders[2].name, 'x', HP_NAME_MAX), HP_ERR_INVALID, "bladder #3", "name");
    BAD(strcpy(L.bladders[5].name, "base_neck_left"), HP_ERR_INVALID, "base_neck_left", "name");
    BAD(L.bladders[4].center[1] = NAN, HP_ERR_INVALID, "side_fore_left", "center");
    BAD(L.bladders[1].iab.Ri = 0.031, HP_ERR_DOMAIN, "base_neck_right", "Ri");
    BAD(L.bladders[1].iab.C1 = NAN, HP_ERR_INVALID, "base_neck_right", "C1");
    BAD(L.bladders[6].p_min = NAN, HP_ERR_INVALID, "side_chin_left", "p_min");
    BAD(L.bladders[6].p_max = INFINITY, HP_ERR_INVALID, "side_chin_left", "p_max");
    BAD(L.bladders[6].p_max = -6e3, HP_ERR_INVALID, "side_chin_left", "p_max");
    BAD(L.bladders[7].stretch_min = 0, HP_ERR_INVALID, "side_chin_right", "stretch_min");
    BAD(L.bladders[7].stretch_max = 0.7, HP_ERR_INVALID, "side_chin_right", "stretch_max");
    BAD(L.bladders[7].rate_max = 0, HP_ERR_INVALID, "side_chin_right", "rate_max");
    BAD(L.bladders[7].rate_max = NAN, HP_ERR_INVALID, "side_chin_right", "rate_max");
    /* Nominal stretch 1 (no preload) must lie strictly inside the stretch limits, and the
     * nominal pressure 0 inside the pressure limits. */
    BAD(L.bladders[3].stretch_min = 1.0, HP_ERR_INVALID, "base_skull_right", "stretch_min");
    BAD(L.bladders[3].stretch_max = 1.0, HP_ERR_INVALID, "base_skull_right", "stretch_max");
    BAD(L.bladders[3].p_min = 100.0, HP_ERR_INVALID, "base_skull_right", "p_min");
    BAD(L.bladders[3].p_max = -100.0, HP_ERR_INVALID, "base_skull_right", "p_max");
    /* Centre inside the head. */
    BAD(memset(L.bladders[0].center, 0, sizeof L.bladders[0].center), HP_ERR_INVALID,
        "base_neck_left", "center");
    BAD(L.bladders[0].center[2] = -0.05, HP_ERR_INVALID, "base_neck_left", "center");
    /* Soft material with a limit point: stretch_max must stay below it (C2 = 0: λ ≈ 1.38
     * for this wall thickness; 1.3 passes, 1.6 must not). */
    L = G;
    L.bladders[2].iab.C2 = 0.0;
    assert_int_equal(hp_layout_prepare(&L, &d), HP_OK);
    BAD((L.bladders[2].iab.C2 = 0.0, L.bladders[2].stretch_max = 1.6), HP_ERR_INVALID,
        "base_skull_left", "limit point");
#undef BAD
    assert_int_equal(hp_layout_prepare(NULL, &d), HP_ERR_NULL);
}

/* Preload: with c = p + (Ro + preload)·n the nominal distance is Ro + preload and the
 * nominal stretch above 1; the prepared contact point is the touch point. */
static void test_touch_and_preload(void **state)
{
    (void)state;
    hp_head h = default_head();
    hp_layout L;
    assert_int_equal(default_layout_on(&L, &h, 0.001), 0);
    hp_diag d;
    assert_int_equal(hp_layout_prepare(&L, &d), HP_OK);
    for (int k = 0; k < 8; ++k) {
        double pmm[3];
        default_touch_mm(k, pmm);
        hp_assert_close(L.rho0[k], 0.031, 0, 1e-16);
        for (int i = 0; i < 3; ++i) hp_assert_close(L.contact[k][i], pmm[i] * 1e-3, 0, 1e-16);
    }
    /* The normals: base mostly −Z, sides mostly ±X (left = +X). */
    for (int k = 0; k < 4; ++k) assert_true(L.normal[k][2] < -0.8);
    assert_true(L.normal[4][0] > 0.9 && L.normal[6][0] > 0.9);
    assert_true(L.normal[5][0] < -0.9 && L.normal[7][0] < -0.9);
    double c[3];
    const double off[3] = {0.01, 0.01, 0.01};
    assert_int_equal(hp_head_center_from_touch(&h, off, 0.03, 0.0, c, &d), HP_ERR_INVALID);
    assert_non_null(strstr(d.text, "touch"));
    const double tip[3] = {0.0775, 0, 0};
    assert_int_equal(hp_head_center_from_touch(&h, tip, 0.03, 0.002, c, &d), HP_OK);
    hp_assert_close(c[0], 0.1095, 0, 1e-16);
    assert_int_equal(hp_head_center_from_touch(&h, tip, 0.03, -0.05, c, &d), HP_ERR_INVALID);
    assert_non_null(strstr(d.text, "preload"));
}

static void test_analysis_default(void **state)
{
    (void)state;
    hp_layout L;
    assert_int_equal(default_layout(&L), 0);
    hp_layout_analysis a;
    assert_int_equal(hp_layout_analyze(&L, HP_LEVEL_SURFACE, &a), HP_OK);
    print_message("sv: %.4f %.4f %.4f %.4f %.4f %.4f  rank %d cond %.2f\n", a.singular_values[0],
                  a.singular_values[1], a.singular_values[2], a.singular_values[3],
                  a.singular_values[4], a.singular_values[5], a.rank, a.condition);
    print_message("weakest: %.3f %.3f %.3f %.3f %.3f %.3f '%s'\n", a.weakest[0], a.weakest[1],
                  a.weakest[2], a.weakest[3], a.weakest[4], a.weakest[5], a.weakest_words);
    for (int i = 0; i < 6; ++i)
        print_message("reach %-9s %8.3f .. %8.3f\n", hp_pose_key(i), a.reach[i][0], a.reach[i][1]);
    assert_int_equal(a.rank, 6);
    assert_int_equal(a.rotation_commandable, 1);
    /* Singular values descending and positive; condition = first / last. */
    for (int i = 1; i < 6; ++i) assert_true(a.singular_values[i] <= a.singular_values[i - 1]);
    hp_assert_close(a.condition, a.singular_values[0] / a.singular_values[5], 1e-15, 0);
    /* The weakest direction is pitch with some longitudinal shift. Independent check from
     * the scaled Jacobian's column norms: Y is the weakest translation and pitch the weakest
     * rotation (roll, intrinsically weak on a near-round XZ section, comes next). */
    assert_string_equal(a.weakest_words, "pitch with some longitudinal shift");
    assert_true(a.weakest[HP_PITCH] > 0.9 && fabs(a.weakest[HP_Y]) > 0.3);
    const double zero[6] = {0};
    double J[HP_MAX_BLADDERS * 6], norm[6] = {0};
    assert_int_equal(hp_contact_eval(&L, HP_LEVEL_LINEAR, zero, NULL, J, NULL), HP_OK);
    for (int j = 0; j < 6; ++j) {
        double sc = j < 3 ? 1.0 : 1e3 * 3.14159265358979323846 / 180.0;
        for (int k = 0; k < L.n; ++k) norm[j] += (J[k * 6 + j] * sc) * (J[k * 6 + j] * sc);
    }
    assert_true(norm[HP_Y] < norm[HP_X] && norm[HP_Y] < norm[HP_Z]);
    assert_true(norm[HP_PITCH] < norm[HP_ROLL] && norm[HP_PITCH] < norm[HP_YAW]);
    /* |weakest| = 1 and J·v has norm sv_min (1e-12: SVD accuracy for a 8×6 matrix). */
    double Jv = 0, vv = 0;
    for (int k = 0; k < L.n; ++k) {
        double s = 0;
        for (int j = 0; j < 6; ++j)
            s += J[k * 6 + j] * (j < 3 ? 1.0 : 1e3 * 3.14159265358979323846 / 180.0) * a.weakest[j];
        Jv += s * s;
    }
    for (int j = 0; j < 6; ++j) vv += a.weakest[j] * a.weakest[j];
    hp_assert_close(vv, 1.0, 1e-12, 0);
    hp_assert_close(sqrt(Jv), a.singular_values[5], 1e-12, 0);
    /* Reach: symmetric layout -> symmetric reach in x, y, pitch, roll, yaw (mirror
     * symmetry of the layout in X and Y planes; 1e-9 of the bisection resolution), and
     * every reach inside its cap and non-trivial. Vertical is not symmetric: the base
     * bladders sit only under the head. */
    for (int i = 0; i < 6; ++i)
        if (i != HP_Z) hp_assert_close(-a.reach[i][0], a.reach[i][1], 0, 1e-9);
    for (int i = 0; i < 6; ++i) {
        double cap = i < 3 ? 50.0 : 30.0;
        assert_true(a.reach[i][0] < -0.1 && a.reach[i][0] >= -cap);
        assert_true(a.reach[i][1] > 0.1 && a.reach[i][1] <= cap);
    }
    /* Just inside the reach every bladder holds; just outside one does not. */
    for (int i = 0; i < 6; ++i)
        for (int sgn = 0; sgn < 2; ++sgn) {
            double r = a.reach[i][sgn], mm[6] = {0}, xi[6], rho[HP_MAX_BLADDERS];
            for (int f = 0; f < 2; ++f) {
                mm[i] = r * (f == 0 ? 0.999 : 1.001);
                hp_pose_from_clinical(mm, xi);
                assert_int_equal(hp_contact_eval(&L, HP_LEVEL_SURFACE, xi, rho, NULL, NULL), HP_OK);
                int ok = 1;
                for (int k = 0; k < L.n; ++k) {
                    const hp_bladder *b = &L.bladders[k];
                    double ri, P;
                    if (hp_iab_ri(&b->iab, rho[k], &ri) != HP_OK) { ok = 0; break; }
                    if (hp_iab_ik(&b->iab, ri, &P) != HP_OK) { ok = 0; break; }
                    double lam = ri / b->iab.Ri;
                    if (lam < b->stretch_min || lam > b->stretch_max || P < b->p_min || P > b->p_max)
                        ok = 0;
                }
                assert_int_equal(ok, f == 0);
            }
        }
}

/* A sphere head: rotation about its centre is not commandable, rank 3. */
static void test_analysis_sphere(void **state)
{
    (void)state;
    hp_head s = default_head();
    s.shape = HP_HEAD_SPHERE;
    s.semi_axes[0] = 0.09;
    hp_layout L;
    assert_int_equal(default_layout_on(&L, &s, 0.0), 0);
    assert_int_equal(hp_layout_prepare(&L, NULL), HP_OK);
    hp_layout_analysis a;
    assert_int_equal(hp_layout_analyze(&L, HP_LEVEL_SURFACE, &a), HP_OK);
    assert_int_equal(a.rank, 3);
    assert_true(isinf(a.condition));
    assert_int_equal(a.rotation_commandable, 0);
    for (int i = 3; i < 6; ++i) assert_true(a.reach[i][0] == 0.0 && a.reach[i][1] == 0.0);
    for (int i = 0; i < 3; ++i) assert_true(a.reach[i][1] > 0.1);
    /* The weakest direction is a rotation (the null space). */
    assert_true(fabs(a.weakest[0]) + fabs(a.weakest[1]) + fabs(a.weakest[2]) < 1e-9);
    /* Also with the pivot away from the sphere centre: still rank 3. */
    L.pivot[1] = 0.03;
    assert_int_equal(hp_layout_prepare(&L, NULL), HP_OK);
    assert_int_equal(hp_layout_analyze(&L, HP_LEVEL_LINEAR, &a), HP_OK);
    assert_int_equal(a.rank, 3);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_invalid_layouts),
        cmocka_unit_test(test_touch_and_preload),
        cmocka_unit_test(test_analysis_default),
        cmocka_unit_test(test_analysis_sphere),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
