/* The point-to-head distance: robust root find and its exact derivatives. */
#include "test_util.h"

#include "kin_test_util.h"
#include "kinematics/kin_internal.h"

#include <string.h>

static hp_head ellipsoid(double a, double b, double c)
{
    hp_head h;
    memset(&h, 0, sizeof h);
    h.shape = HP_HEAD_ELLIPSOID;
    h.semi_axes[0] = a;
    h.semi_axes[1] = b;
    h.semi_axes[2] = c;
    return h;
}

/* Independent checks of a returned closest point (the optimality conditions):
 * foot on the surface (implicit function within 1e-14), q − foot parallel to the normal
 * ∇F(foot) with the returned gradient equal to that normal, |q − foot| = |d|, and no
 * surface point among a dense sample (40 000 by an area-free parametrisation) closer than d
 * (margin 1e-12 m, far below the sample spacing effect, which only makes samples farther). */
static void check_closest(const hp_head *h, const double q[3])
{
    double d, g[3], foot[3];
    assert_int_equal(hp_kin_head_distance(h, q, &d, g, NULL, foot), HP_OK);
    const double *a = h->semi_axes;
    double F = -1, m[3], mn = 0;
    for (int i = 0; i < 3; ++i) {
        double u = (foot[i] - h->center[i]) / a[i];
        F += u * u;
        m[i] = u / a[i];
        mn += m[i] * m[i];
    }
    mn = sqrt(mn);
    hp_assert_close(F, 0.0, 0, 1e-14);
    double diff[3], dl = 0;
    for (int i = 0; i < 3; ++i) {
        diff[i] = q[i] - foot[i];
        dl += diff[i] * diff[i];
        hp_assert_close(g[i], m[i] / mn, 0, 1e-12);
    }
    dl = sqrt(dl);
    hp_assert_close(fabs(d), dl, 1e-12, 1e-15);
    if (dl > 1e-9)
        for (int i = 0; i < 3; ++i) hp_assert_close(diff[i] / dl * (d < 0 ? -1 : 1), g[i], 0, 1e-9);
    const int N = 200;
    double best = INFINITY;
    for (int i = 0; i < N; ++i)
        for (int j = 0; j < N; ++j) {
            double th = 3.14159265358979 * (i + 0.5) / N, ph = 6.28318530717959 * j / N;
            double s[3] = {a[0] * sin(th) * cos(ph), a[1] * sin(th) * sin(ph), a[2] * cos(th)};
            double e = 0;
            for (int k = 0; k < 3; ++k) e += (q[k] - h->center[k] - s[k]) * (q[k] - h->center[k] - s[k]);
            best = fmin(best, sqrt(e));
        }
    assert_true(fabs(d) <= best + 1e-12);
}

static void test_axes_and_far(void **state)
{
    (void)state;
    hp_head h = ellipsoid(0.0775, 0.115, 0.0975);
    h.center[0] = 0.01;
    h.center[1] = -0.02;
    h.center[2] = 0.005;
    /* Points on each axis outside: distance is exactly |coordinate| − semi-axis. */
    for (int ax = 0; ax < 3; ++ax)
        for (int sg = -1; sg <= 1; sg += 2) {
            double q[3] = {h.center[0], h.center[1], h.center[2]};
            q[ax] += sg * (h.semi_axes[ax] + 0.03);
            double d, g[3];
            assert_int_equal(hp_kin_head_distance(&h, q, &d, g, NULL, NULL), HP_OK);
            hp_assert_close(d, 0.03, 1e-13, 0);
            hp_assert_close(g[ax], (double)sg, 0, 1e-15);
            check_closest(&h, q);
        }
    /* On the x axis inside (x semi-axis is the smallest: closest point is the x tip). */
    double qi[3] = {h.center[0] + 0.07, h.center[1], h.center[2]};
    double d;
    assert_int_equal(hp_kin_head_distance(&h, qi, &d, NULL, NULL, NULL), HP_OK);
    hp_assert_close(d, -0.0075, 1e-12, 0);
    /* The centre itself: no unique closest point. */
    assert_int_equal(hp_kin_head_distance(&h, h.center, &d, NULL, NULL, NULL), HP_ERR_DOMAIN);
    /* Far points (1 m and 1 km away): the distance tends to |q − centre| − (support). */
    const double far[2][3] = {{0.3, 0.7, -0.6}, {400.0, -900.0, 100.0}};
    for (int i = 0; i < 2; ++i) check_closest(&h, far[i]);
    /* Points on coordinate planes and exactly on the surface. */
    const double plane_pts[3][3] = {{0.11, 0.05, 0.005}, {0.01, -0.02, 0.2}, {0.09, -0.02, 0.01}};
    for (int i = 0; i < 3; ++i) check_closest(&h, plane_pts[i]);
    kin_rng rng = {7};
    for (int i = 0; i < 200; ++i) {
        double u[3], s[3];
        kin_rng_vec3(&rng, 1.0, u);
        for (int k = 0; k < 3; ++k) s[k] = h.center[k] + h.semi_axes[k] * u[k];
        assert_int_equal(hp_kin_head_distance(&h, s, &d, NULL, NULL, NULL), HP_OK);
        /* On the surface to rounding of s: |d| within a few ulps of 0.1 m. */
        hp_assert_close(d, 0.0, 0, 1e-16);
    }
    for (int i = 0; i < 20; ++i) {
        double q[3];
        kin_rng_vec3(&rng, kin_rng_uniform(&rng, 0.09, 0.3), q);
        for (int k = 0; k < 3; ++k) q[k] += h.center[k];
        check_closest(&h, q);
    }
}

/* Near-spherical heads against the sphere closed form: a=b=c·(1+1e-12) changes distances by
 * at most 1e-12·c ≈ 1e-13 m; both far and near points, and points on axes. */
static void test_near_sphere(void **state)
{
    (void)state;
    const double r = 0.1;
    hp_head s = ellipsoid(r, r, r);
    s.shape = HP_HEAD_SPHERE;
    const double e1 = 1.0 + 1e-12;
    hp_head cases[4] = {ellipsoid(r * e1, r * e1, r), ellipsoid(r, r, r),
                        ellipsoid(r, r * e1, r * e1), ellipsoid(r * e1, r, r * (1 - 1e-12))};
    kin_rng rng = {11};
    for (int c = 0; c < 4; ++c)
        for (int i = 0; i < 100; ++i) {
            double q[3];
            kin_rng_vec3(&rng, kin_rng_uniform(&rng, 0.05, 0.4), q);
            if (i % 10 == 0) q[0] = q[1] = 0.0; /* on the z axis */
            if (i % 10 == 1) q[1] = 0.0;        /* on a coordinate plane */
            double d1, d2, g1[3], g2[3], H1[9], H2[9];
            assert_int_equal(hp_kin_head_distance(&cases[c], q, &d1, g1, H1, NULL), HP_OK);
            assert_int_equal(hp_kin_head_distance(&s, q, &d2, g2, H2, NULL), HP_OK);
            hp_assert_close(d1, d2, 0, 1e-12 * r * 3);
            for (int k = 0; k < 3; ++k) hp_assert_close(g1[k], g2[k], 0, 1e-10);
            /* Hessian (I − nnᵀ)/|q|: the 1e-12 relative perturbation of the axes is amplified
             * by the 1/(a_i² + t) factors by up to r/|q| (here ≤ 100 for points on an axis
             * near the centre): relative 1e-9 keeps a ×10 margin over what was measured. */
            for (int k = 0; k < 9; ++k) hp_assert_close(H1[k], H2[k], 1e-9, 1e-9);
        }
}

/* Gradient and Hessian against central differences and Richardson extrapolation.
 * Central difference of the returned gradient with h = 1e-6 m: truncation h²·|∂³d|/6 with
 * |∂³d| <= 2/(R+d)² ≈ 1e3/m² gives 2e-10/m, rounding ε·|g|/h ≈ 2e-10/m; tolerance 2e-8/m
 * relative to Hessian entries of order 10/m. Richardson (h = 1e-4) of d itself for the
 * gradient: error O(h⁴·|∂⁵d|) ≈ 1e-16·1e7 = 1e-9 rounding ε·0.1/1e-4 ≈ 2e-13; tolerance 1e-8. */
static void check_derivs(const hp_head *h, const double q[3])
{
    double d, g[3], H[9];
    assert_int_equal(hp_kin_head_distance(h, q, &d, g, H, NULL), HP_OK);
    for (int j = 0; j < 3; ++j) {
        double qp[3], qm[3], gp[3], gm[3], dp, dm;
        const double hh = 1e-6;
        memcpy(qp, q, sizeof qp);
        memcpy(qm, q, sizeof qm);
        qp[j] += hh;
        qm[j] -= hh;
        assert_int_equal(hp_kin_head_distance(h, qp, &dp, gp, NULL, NULL), HP_OK);
        assert_int_equal(hp_kin_head_distance(h, qm, &dm, gm, NULL, NULL), HP_OK);
        for (int i = 0; i < 3; ++i) hp_assert_close(H[i * 3 + j], (gp[i] - gm[i]) / (2 * hh), 0, 2e-8);
        /* Richardson on the value for the gradient. */
        double D[2];
        for (int l = 0; l < 2; ++l) {
            double s = 1e-4 / (1 << l), a1[3], a2[3], v1, v2;
            memcpy(a1, q, sizeof a1);
            memcpy(a2, q, sizeof a2);
            a1[j] += s;
            a2[j] -= s;
            assert_int_equal(hp_kin_head_distance(h, a1, &v1, NULL, NULL, NULL), HP_OK);
            assert_int_equal(hp_kin_head_distance(h, a2, &v2, NULL, NULL, NULL), HP_OK);
            D[l] = (v1 - v2) / (2 * s);
        }
        hp_assert_close(g[j], (4 * D[1] - D[0]) / 3, 0, 1e-8);
    }
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) assert_true(H[i * 3 + j] == H[j * 3 + i]);
}

static void test_derivatives(void **state)
{
    (void)state;
    hp_head h = ellipsoid(0.0775, 0.115, 0.0975);
    kin_rng rng = {3};
    for (int i = 0; i < 100; ++i) {
        double q[3];
        kin_rng_vec3(&rng, 1.0, q);
        /* Outside at 1..60 mm, and a few just inside. */
        double sc = i < 90 ? 1.0 : 0.95;
        for (int k = 0; k < 3; ++k) q[k] *= h.semi_axes[k] * sc;
        if (i < 90) {
            double n[3];
            kin_rng_vec3(&rng, 1.0, n);
            double d0, g0[3];
            assert_int_equal(hp_kin_head_distance(&h, q, &d0, g0, NULL, NULL), HP_OK);
            double off = kin_rng_uniform(&rng, 0.001, 0.06);
            for (int k = 0; k < 3; ++k) q[k] += off * g0[k];
        }
        check_derivs(&h, q);
    }
    /* On an axis (degenerate first octant) and on the surface itself. */
    const double axis_pt[3] = {0, 0, -0.1275};
    check_derivs(&h, axis_pt);
    const double surf[3] = {0.0775, 0, 0};
    check_derivs(&h, surf);
    hp_head s = h;
    s.shape = HP_HEAD_SPHERE;
    s.semi_axes[1] = s.semi_axes[2] = s.semi_axes[0];
    const double sp[3] = {0.05, -0.07, 0.04};
    check_derivs(&s, sp);
}

/* The warm start changes the path, never the answer: from the multiplier of a nearby
 * point (what a fit or an SQP passes on), from far-off guesses on either side of the root,
 * from values outside the bracket and from NAN, the distance, normal, Hessian and foot
 * agree with the cold solve to 1e-15 m (~10 ulps of a 0.1 m distance) and 1e-12 relative
 * for the Hessian (its entries are ~1/distance; the root moves by an ulp or two), and the
 * multiplier handed back is the cold solve's (a second warm solve from it returns the same
 * distance). Points outside at 0.1..60 mm and just inside. */
static void test_warm_start(void **state)
{
    (void)state;
    hp_head h = ellipsoid(0.0775, 0.115, 0.0975);
    kin_rng rng = {11};
    for (int i = 0; i < 400; ++i) {
        double q[3], dir[3];
        kin_rng_vec3(&rng, 1.0, q);
        double sc = i < 360 ? 1.0 : 0.9;
        for (int k = 0; k < 3; ++k) q[k] *= h.semi_axes[k] * sc;
        if (i < 360) {
            double d0, g0[3];
            assert_int_equal(hp_kin_head_distance(&h, q, &d0, g0, NULL, NULL), HP_OK);
            double off = kin_rng_uniform(&rng, 1e-4, 0.06);
            for (int k = 0; k < 3; ++k) q[k] += off * g0[k];
        }
        double d, g[3], H[9], foot[3], s_cold = NAN;
        assert_int_equal(hp_kin_head_distance_warm(&h, q, &s_cold, &d, g, H, foot), HP_OK);
        assert_true(isfinite(s_cold));
        /* A nearby point's multiplier: the point moved by up to 2 mm. */
        kin_rng_vec3(&rng, 1.0, dir);
        double qn[3], sn = NAN, dn;
        for (int k = 0; k < 3; ++k) qn[k] = q[k] + 0.002 * dir[k];
        assert_int_equal(hp_kin_head_distance_warm(&h, qn, &sn, &dn, NULL, NULL, NULL), HP_OK);
        const double guesses[7] = {sn, s_cold * 3.0 + 0.5, s_cold - 0.5, -0.999, 1e6, -5.0, NAN};
        for (int gi = 0; gi < 7; ++gi) {
            double s = guesses[gi], dw, gw[3], Hw[9], fw[3];
            assert_int_equal(hp_kin_head_distance_warm(&h, q, &s, &dw, gw, Hw, fw), HP_OK);
            assert_true(fabs(dw - d) <= 1e-15);
            for (int k = 0; k < 3; ++k) {
                assert_true(fabs(gw[k] - g[k]) <= 1e-12);
                assert_true(fabs(fw[k] - foot[k]) <= 1e-15);
            }
            for (int k = 0; k < 9; ++k)
                assert_true(fabs(Hw[k] - H[k]) <= 1e-12 * (1.0 + fabs(H[k])));
            assert_true(fabs(s - s_cold) <= 1e-13 * (1.0 + fabs(s_cold)));
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_axes_and_far),
        cmocka_unit_test(test_near_sphere),
        cmocka_unit_test(test_derivatives),
        cmocka_unit_test(test_warm_start),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
