/* Layout validation (every bad field gives a message naming the bladder and the field),
 * placement by touch point, and the layout analysis. */
#include "support/test_util.h"

#include "support/default_layout.h"

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
    /* A valid layout comes back unchanged: validation derives and stores nothing. */
    assert_memory_equal(&L, &G, sizeof L);

#define BAD(stmt, code, s1, s2)                                                                    \
    do {                                                                                           \
        L = G;                                                                                     \
        stmt;                                                                                      \
        expect_bad(&L, code, s1, s2);                                                              \
    } while (0)
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
    double nrm[8][3];
    for (int k = 0; k < 8; ++k) {
        double pmm[3], p[3], rho0;
        default_touch_mm(k, pmm);
        assert_int_equal(hp_layout_contact(&L, k, p, nrm[k], &rho0), HP_OK);
        hp_assert_close(rho0, 0.031, 0, 1e-16);
        for (int i = 0; i < 3; ++i) hp_assert_close(p[i], pmm[i] * 1e-3, 0, 1e-16);
    }
    /* The normals: base mostly −Z, sides mostly ±X (left = +X). */
    for (int k = 0; k < 4; ++k) assert_true(nrm[k][2] < -0.8);
    assert_true(nrm[4][0] > 0.9 && nrm[6][0] > 0.9);
    assert_true(nrm[5][0] < -0.9 && nrm[7][0] < -0.9);
    /* hp_layout_contact refuses what has no contact. */
    assert_int_equal(hp_layout_contact(&L, 8, NULL, NULL, NULL), HP_ERR_INVALID);
    assert_int_equal(hp_layout_contact(&L, -1, NULL, NULL, NULL), HP_ERR_INVALID);
    assert_int_equal(hp_layout_contact(NULL, 0, NULL, NULL, NULL), HP_ERR_NULL);
    hp_layout in = L;
    memset(in.bladders[3].center, 0, sizeof in.bladders[3].center);
    assert_int_equal(hp_layout_contact(&in, 3, NULL, NULL, NULL), HP_ERR_INVALID);
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
                    if (hp_iab_ri(&b->iab, rho[k], &ri) != HP_OK) {
                        ok = 0;
                        break;
                    }
                    if (hp_iab_ik(&b->iab, ri, &P) != HP_OK) {
                        ok = 0;
                        break;
                    }
                    double lam = ri / b->iab.Ri;
                    if (lam < b->stretch_min || lam > b->stretch_max || P < b->p_min ||
                        P > b->p_max)
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

/* Everything the layout calls answer for layout L, collected for a bit-for-bit comparison. */
typedef struct kin_answers {
    double rho[3][HP_MAX_BLADDERS], J[3][HP_MAX_BLADDERS * 6], H[3][HP_MAX_BLADDERS * 36];
    double bound[2], fk[6], fk_resid, fit[6], xc[6];
    double contact[HP_MAX_BLADDERS][3], normal[HP_MAX_BLADDERS][3], rho0[HP_MAX_BLADDERS];
    hp_level autolevel;
    hp_identifiable id;
    hp_layout_analysis an;
} kin_answers;

static void answers_of(const hp_layout *L, kin_answers *a)
{
    memset(a, 0, sizeof *a);
    const double xi[6] = {0.002, -0.001, 0.0015, 0.02, -0.015, 0.01};
    for (int l = 0; l < 3; ++l)
        assert_int_equal(hp_contact_eval(L, (hp_level)l, xi, a->rho[l], a->J[l], a->H[l]), HP_OK);
    assert_int_equal(hp_contact_error_bound(L, HP_LEVEL_LINEAR, 0.005, 0.05, &a->bound[0]), HP_OK);
    assert_int_equal(hp_contact_error_bound(L, HP_LEVEL_PLANE, 0.005, 0.05, &a->bound[1]), HP_OK);
    assert_int_equal(hp_contact_auto(L, 1e-5, 0.005, 0.05, &a->autolevel), HP_OK);
    /* Forward kinematics from the surface distances of xi; a fit in x, y, z alone. */
    assert_int_equal(hp_contact_fk(L, HP_LEVEL_SURFACE, a->rho[2], NULL, a->fk, &a->fk_resid, NULL),
                     HP_OK);
    const int free_[6] = {1, 1, 1, 0, 0, 0};
    const double x0[6] = {0};
    assert_int_equal(hp_contact_fit(L, HP_LEVEL_PLANE, a->rho[1], free_, x0, a->fit, NULL, NULL),
                     HP_OK);
    assert_int_equal(hp_layout_identify(L, &a->id), HP_OK);
    assert_int_equal(hp_pose_commanded_part(L, &a->id, HP_LEVEL_SURFACE, xi, a->xc), HP_OK);
    assert_int_equal(hp_layout_analyze(L, HP_LEVEL_PLANE, &a->an), HP_OK);
    for (int k = 0; k < L->n; ++k)
        assert_int_equal(hp_layout_contact(L, k, a->contact[k], a->normal[k], &a->rho0[k]), HP_OK);
}

/* The layout holds inputs only, so editing it after validation cannot leave stale derived
 * data: every kinematics call answers for the edited layout exactly as for a freshly
 * validated copy of it (bit for bit: the same derivation runs on the same numbers), and
 * differently from the layout before the edit. Edits: a bladder centre moved 0.5 mm, the
 * head moved 0.3 mm and one semi-axis grown 0.2 mm; and a sphere whose radius is changed
 * after validation (its other two semi-axes, copied by validation, are then stale inputs
 * that the geometry must not read). */
static void test_edit_after_validation(void **state)
{
    (void)state;
    hp_head h = default_head();
    hp_layout L;
    assert_int_equal(default_layout_on(&L, &h, 0.0), 0);
    assert_int_equal(hp_layout_prepare(&L, NULL), HP_OK);
    static kin_answers before, edited, fresh;
    answers_of(&L, &before);

    hp_layout E = L; /* validated, then edited in place */
    E.bladders[2].center[0] += 0.0005;
    E.head.center[2] += 0.0003;
    E.head.semi_axes[1] += 0.0002;
    answers_of(&E, &edited);
    hp_layout F = E;
    assert_int_equal(hp_layout_prepare(&F, NULL), HP_OK);
    answers_of(&F, &fresh);
    assert_memory_equal(&edited, &fresh, sizeof edited);
    assert_true(edited.rho0[2] != before.rho0[2]);
    assert_true(edited.rho[2][0] != before.rho[2][0]);
    assert_true(edited.bound[1] != before.bound[1]);

    /* A sphere: validation copies the radius to the other semi-axes; a new radius set
     * afterwards leaves them stale in the input, which the geometry ignores. */
    hp_head s = default_head();
    s.shape = HP_HEAD_SPHERE;
    s.semi_axes[0] = 0.09;
    s.semi_axes[1] = s.semi_axes[2] = 0.0;
    assert_int_equal(default_layout_on(&L, &s, 0.0), 0);
    assert_int_equal(hp_layout_prepare(&L, NULL), HP_OK);
    assert_true(L.head.semi_axes[1] == 0.09 && L.head.semi_axes[2] == 0.09);
    E = L;
    E.head.semi_axes[0] = 0.0895; /* semi_axes[1], [2] still 0.09 */
    hp_identifiable ie, iff;
    double rho_e[8], rho_f[8], J_e[48], J_f[48], b_e, b_f;
    const double xi[6] = {0.001, 0.002, -0.001, 0, 0, 0};
    assert_int_equal(hp_layout_identify(&E, &ie), HP_OK);
    assert_int_equal(hp_contact_eval(&E, HP_LEVEL_PLANE, xi, rho_e, J_e, NULL), HP_OK);
    assert_int_equal(hp_contact_error_bound(&E, HP_LEVEL_PLANE, 0.005, 0.0, &b_e), HP_OK);
    F = E;
    assert_int_equal(hp_layout_prepare(&F, NULL), HP_OK);
    assert_true(F.head.semi_axes[1] == 0.0895);
    assert_int_equal(hp_layout_identify(&F, &iff), HP_OK);
    assert_int_equal(hp_contact_eval(&F, HP_LEVEL_PLANE, xi, rho_f, J_f, NULL), HP_OK);
    assert_int_equal(hp_contact_error_bound(&F, HP_LEVEL_PLANE, 0.005, 0.0, &b_f), HP_OK);
    assert_memory_equal(&ie, &iff, sizeof ie);
    assert_memory_equal(rho_e, rho_f, sizeof rho_e);
    assert_memory_equal(J_e, J_f, sizeof J_e);
    assert_memory_equal(&b_e, &b_f, sizeof b_e);
    assert_int_equal(ie.centre_only, 1);
    assert_true(ie.trans_limit == 0.0895);

    /* A layout whose geometry is broken by an edit is refused by every call (no stale
     * answer), with NaN outputs from hp_contact_eval. */
    E = L;
    memset(E.bladders[5].center, 0, sizeof E.bladders[5].center); /* inside the head */
    double r[8], Jb[48];
    assert_int_equal(hp_contact_eval(&E, HP_LEVEL_LINEAR, xi, r, Jb, NULL), HP_ERR_INVALID);
    for (int k = 0; k < 8; ++k) assert_true(isnan(r[k]) && isnan(Jb[6 * k]));
    assert_int_equal(hp_layout_identify(&E, &ie), HP_ERR_INVALID);
    assert_int_equal(hp_contact_error_bound(&E, HP_LEVEL_PLANE, 0.005, 0.0, &b_e), HP_ERR_INVALID);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_invalid_layouts),       cmocka_unit_test(test_touch_and_preload),
        cmocka_unit_test(test_edit_after_validation), cmocka_unit_test(test_analysis_default),
        cmocka_unit_test(test_analysis_sphere),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
