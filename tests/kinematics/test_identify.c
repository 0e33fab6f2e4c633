/* The identifiable range (hp_layout_identify, hp_pose_rotation_angle,
 * hp_pose_commanded_part): rank and commanded components per head shape and layout, their
 * independence of units, scale and pivot, the rotation bound below the head's half-turn
 * symmetry, and the commanded part of a correction checked against geometry written here. */
#include "support/rotation_ref.h"
#include "support/test_util.h"
#include "kin_test_util.h"
#include "support/ident_layouts.h"

#include <string.h>

#define PI 3.14159265358979323846

static void triaxial_range(void **st)
{
    (void)st;
    hp_layout L;
    assert_int_equal(il_layout(&L, HP_HEAD_ELLIPSOID, il_default_axes, il_origin, il_origin, 8,
                               il_default_rays, 1.0),
                     HP_OK);
    hp_identifiable id;
    assert_int_equal(hp_layout_identify(&L, &id), HP_OK);
    assert_int_equal(id.rank, 6);
    assert_int_equal(id.n_null, 0);
    for (int i = 0; i < 6; ++i) assert_int_equal(id.commanded[i], 1);
    assert_false(id.centre_only);
    /* The bound of the half-turn symmetry: exactly 90 degrees. */
    assert_true(id.rot_limit == 0.5 * PI);
    assert_true(id.trans_limit == 0.0775);
    assert_non_null(strstr(id.symmetry, "half-turns about its X, Y and Z axes"));
    assert_true(id.rel_sv[5] > 1e-2); /* well observable: far from the 1e-8 threshold */
}

/* A sphere: rotation about its centre changes no distance, whatever the pivot; the
 * unobservable motions are rotations about the centre written about the pivot. */
static void sphere_rank3_any_pivot(void **st)
{
    (void)st;
    const double r90[3] = {0.09, 0.09, 0.09};
    const double pivots[4][3] = {{0, 0, 0}, {0, 0, -0.07}, {0, 100, 0}, {0, 0, 1000}};
    for (int pi = 0; pi < 4; ++pi) {
        hp_layout L;
        assert_int_equal(
            il_layout(&L, HP_HEAD_SPHERE, r90, il_origin, pivots[pi], 8, il_default_rays, 1.0),
            HP_OK);
        hp_identifiable id;
        assert_int_equal(hp_layout_identify(&L, &id), HP_OK);
        assert_int_equal(id.rank, 3);
        assert_true(id.centre_only);
        for (int i = 0; i < 6; ++i) assert_int_equal(id.commanded[i], i < 3);
        assert_true(id.rot_limit == PI);
        /* J·v = 0 for every unobservable motion v, with the library's Jacobian about the
         * pivot (another code path): relative to |J|·|v| in mm and mm/deg. */
        double J[8 * 6], xi0[6] = {0};
        assert_int_equal(hp_contact_eval(&L, HP_LEVEL_SURFACE, xi0, NULL, J, NULL), HP_OK);
        for (int m = 0; m < id.n_null; ++m) {
            const double *v = id.null_space[m];
            /* A rotation about the centre: t = ω × (pivot − centre) exactly. */
            const double *w = pivots[pi]; /* pivot − centre */
            double t[3] = {v[4] * w[2] - v[5] * w[1], v[5] * w[0] - v[3] * w[2],
                           v[3] * w[1] - v[4] * w[0]};
            for (int i = 0; i < 3; ++i) hp_assert_close(v[i], t[i], 1e-12, 1e-12);
            /* Scale of the terms: every column's largest entry times its component, plus
             * the translation columns times |ω|·radius (the lever of a turn about the
             * centre, whose exact effect is zero). */
            double om = sqrt(v[3] * v[3] + v[4] * v[4] + v[5] * v[5]), sc = 0.09 * om;
            for (int i = 0; i < 6; ++i) {
                double cm = 0;
                for (int k = 0; k < 8; ++k) cm = fmax(cm, fabs(J[k * 6 + i]));
                sc += cm * fabs(v[i]);
            }
            for (int k = 0; k < 8; ++k) {
                double s = 0;
                for (int i = 0; i < 6; ++i) s += J[k * 6 + i] * v[i];
                assert_true(fabs(s) <= 1e-12 * sc);
            }
        }
    }
}

/* An ellipsoid of revolution about Y (a = c): the turn about Y (roll) is unobservable; the
 * other rotations still meet the half-turn bound. */
static void spheroid_rank5(void **st)
{
    (void)st;
    const double ax[3] = {0.09, 0.115, 0.09};
    hp_layout L;
    assert_int_equal(
        il_layout(&L, HP_HEAD_ELLIPSOID, ax, il_origin, il_origin, 8, il_default_rays, 1.0), HP_OK);
    hp_identifiable id;
    assert_int_equal(hp_layout_identify(&L, &id), HP_OK);
    assert_int_equal(id.rank, 5);
    for (int i = 0; i < 6; ++i) assert_int_equal(id.commanded[i], i != HP_ROLL);
    assert_false(id.centre_only);
    assert_true(id.rot_limit == 0.5 * PI);
    assert_non_null(strstr(id.symmetry, "every turn about its Y axis"));
    assert_true(fabs(id.null_space[0][HP_ROLL]) >
                0.99 * sqrt(id.null_space[0][0] * id.null_space[0][0] +
                            id.null_space[0][1] * id.null_space[0][1] +
                            id.null_space[0][2] * id.null_space[0][2] +
                            id.null_space[0][3] * id.null_space[0][3] +
                            id.null_space[0][4] * id.null_space[0][4] +
                            id.null_space[0][5] * id.null_space[0][5]));
}

/* The rank decision does not depend on units, the scene's scale or the pivot. Why the test
 * is sound: the decision is made on the Jacobian in the head-centred frame with the rotation
 * columns divided by the largest semi-axis, so every entry is a dimensionless number built
 * from normals and lever arms over the head's size: scaling the whole scene by s leaves it
 * unchanged up to rounding, and the pivot does not enter it at all (it only changes pose
 * coordinates, a non-singular map). The commanded components depend on the pivot only
 * through w/ell (pivot distance over head size), which changes rank decisions of column
 * subsets only beyond ~1e7 head sizes. On old main the rank of the Jacobian about the pivot in
 * mm and mm/deg against 1e-9 of its largest singular value dropped rotations with the pivot
 * at 1 km and not at 100 m. */
static void rank_independent_of_scale_and_pivot(void **st)
{
    (void)st;
    double flat[8][3];
    il_flat_rays(flat);
    const double r90[3] = {0.09, 0.09, 0.09};
    struct {
        const char *name;
        hp_head_shape shape;
        const double *ax;
        int n;
        const double (*rays)[3];
        int rank;
    } cases[] = {
        {"default", HP_HEAD_ELLIPSOID, il_default_axes, 8, il_default_rays, 6},
        {"1 bladder", HP_HEAD_ELLIPSOID, il_default_axes, 1, il_default_rays, 1},
        {"2 bladders", HP_HEAD_ELLIPSOID, il_default_axes, 2, il_default_rays, 2},
        {"3 bladders", HP_HEAD_ELLIPSOID, il_default_axes, 3, il_default_rays, 3},
        {"4 bladders", HP_HEAD_ELLIPSOID, il_default_axes, 4, il_default_rays, 4},
        {"5 bladders", HP_HEAD_ELLIPSOID, il_default_axes, 5, il_default_rays, 5},
        {"flat", HP_HEAD_ELLIPSOID, il_default_axes, 8, (const double(*)[3])flat, 3},
        {"sphere", HP_HEAD_SPHERE, r90, 8, il_default_rays, 3},
    };
    const double scales[3] = {1e-3, 1.0, 1e3};
    const double pivots[5][3] = {{0, 0, 0},
                                 {0.01, -0.02, -0.07},
                                 {0, 100, 0},
                                 {0, 0, 1000},
                                 {700, -700, 0}}; /* [m] at scale 1 */
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; ++c) {
        hp_layout L;
        assert_int_equal(il_layout(&L, cases[c].shape, cases[c].ax, il_origin, il_origin,
                                   cases[c].n, cases[c].rays, 1.0),
                         HP_OK);
        hp_identifiable ref;
        assert_int_equal(hp_layout_identify(&L, &ref), HP_OK);
        if (ref.rank != cases[c].rank)
            print_error("%s: rank %d, expected %d\n", cases[c].name, ref.rank, cases[c].rank);
        assert_int_equal(ref.rank, cases[c].rank);
        for (int si = 0; si < 3; ++si)
            for (int pi = 0; pi < 5; ++pi) {
                /* The whole scene times s, pivot included (s = 1e3: a 115 m head turned
                 * about a pivot 1000 km away). */
                assert_int_equal(il_layout(&L, cases[c].shape, cases[c].ax, il_origin, pivots[pi],
                                           cases[c].n, cases[c].rays, scales[si]),
                                 HP_OK);
                hp_identifiable id;
                assert_int_equal(hp_layout_identify(&L, &id), HP_OK);
                if (id.rank != ref.rank ||
                    memcmp(id.commanded, ref.commanded, sizeof ref.commanded))
                    print_error("%s scale %g pivot #%d: rank %d commanded %d%d%d%d%d%d\n",
                                cases[c].name, scales[si], pi, id.rank, id.commanded[0],
                                id.commanded[1], id.commanded[2], id.commanded[3], id.commanded[4],
                                id.commanded[5]);
                assert_int_equal(id.rank, ref.rank);
                assert_memory_equal(id.commanded, ref.commanded, sizeof ref.commanded);
                for (int j = 0; j < ref.rank; ++j) /* rounding of the scaled geometry only */
                    hp_assert_close(id.rel_sv[j], ref.rel_sv[j], 1e-9, 0);
            }
    }
}

/* The angle of a rotation about its own axis, against an independent construction. */
static void rotation_angle(void **st)
{
    (void)st;
    uint64_t rng = 42;
    for (int t = 0; t < 2000; ++t) {
        double u[3], xi[6];
        kin_rng_vec3(&rng, 1.0, u);
        double th = test_rng_uniform(&rng, 0.0, PI);
        ref_axis_angle_pose(u, th, xi);
        hp_assert_close(hp_pose_rotation_angle(xi), th, 0, 1e-12);
    }
    const double half[6] = {0, 0, 0, PI, 0, 0}, t170[6] = {0, 0, 0, 0, 0, 170 * PI / 180};
    hp_assert_close(hp_pose_rotation_angle(half), PI, 0, 1e-15);
    hp_assert_close(hp_pose_rotation_angle(t170), 170 * PI / 180, 0, 1e-15);
}

/* Too few bladders: the commanded part has zeros in the dropped components and the same
 * contact distances as the desired pose (linear level: J·xc = J·xd; surface: the fit). */
static void commanded_part_same_distances(void **st)
{
    (void)st;
    uint64_t rng = 7;
    for (int n = 1; n <= 5; ++n) {
        hp_layout L;
        assert_int_equal(il_layout(&L, HP_HEAD_ELLIPSOID, il_default_axes, il_origin, il_origin, n,
                                   il_default_rays, 1.0),
                         HP_OK);
        hp_identifiable id;
        assert_int_equal(hp_layout_identify(&L, &id), HP_OK);
        for (int t = 0; t < 20; ++t) {
            double xd[6], xc[6], a[8], b[8];
            kin_rng_pose(&rng, 0.003, 0.03, 0, xd);
            for (int lv = 0; lv < 3; lv += 2) {
                assert_int_equal(hp_pose_commanded_part(&L, &id, (hp_level)lv, xd, xc), HP_OK);
                for (int i = 0; i < 6; ++i)
                    if (!id.commanded[i]) assert_true(xc[i] == 0.0);
                assert_int_equal(hp_contact_eval(&L, (hp_level)lv, xd, a, NULL, NULL), HP_OK);
                assert_int_equal(hp_contact_eval(&L, (hp_level)lv, xc, b, NULL, NULL), HP_OK);
                for (int k = 0; k < n; ++k) hp_assert_close(b[k], a[k], 0, 1e-13);
            }
        }
    }
}

/* A sphere with an off-centre pivot: the commanded part is the translation that moves the
 * centre where the desired pose moves it, computed here from the rotation written above. */
static void commanded_part_sphere_centre(void **st)
{
    (void)st;
    const double r90[3] = {0.09, 0.09, 0.09}, pivot[3] = {0.01, -0.02, -0.07};
    hp_layout L;
    assert_int_equal(il_layout(&L, HP_HEAD_SPHERE, r90, il_origin, pivot, 8, il_default_rays, 1.0),
                     HP_OK);
    hp_identifiable id;
    assert_int_equal(hp_layout_identify(&L, &id), HP_OK);
    uint64_t rng = 11;
    for (int t = 0; t < 200; ++t) {
        double xd[6], xc[6], R[9];
        kin_rng_pose(&rng, 0.01, 0.5, 0, xd);
        assert_int_equal(hp_pose_commanded_part(&L, &id, HP_LEVEL_SURFACE, xd, xc), HP_OK);
        ref_rotation(xd + 3, R);
        for (int i = 0; i < 3; ++i) {
            double c = pivot[i] + xd[i]; /* pivot + R(centre − pivot) + t, centre = 0 */
            for (int j = 0; j < 3; ++j) c += R[i * 3 + j] * (0.0 - pivot[j]);
            hp_assert_close(xc[i], c, 0, 1e-15);
            assert_true(xc[3 + i] == 0.0);
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(triaxial_range),
        cmocka_unit_test(sphere_rank3_any_pivot),
        cmocka_unit_test(spheroid_rank5),
        cmocka_unit_test(rank_independent_of_scale_and_pivot),
        cmocka_unit_test(rotation_angle),
        cmocka_unit_test(commanded_part_same_distances),
        cmocka_unit_test(commanded_part_sphere_centre),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
