/* The point-to-head distance: robust root find and its exact derivatives. */
#include "support/test_util.h"

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
    assert_int_equal(hpi_kin_head_distance(h, q, &d, g, NULL, foot), HP_OK);
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
            for (int k = 0; k < 3; ++k)
                e += (q[k] - h->center[k] - s[k]) * (q[k] - h->center[k] - s[k]);
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
            assert_int_equal(hpi_kin_head_distance(&h, q, &d, g, NULL, NULL), HP_OK);
            hp_assert_close(d, 0.03, 1e-13, 0);
            hp_assert_close(g[ax], (double)sg, 0, 1e-15);
            check_closest(&h, q);
        }
    /* On the x axis inside (x semi-axis is the smallest: closest point is the x tip). */
    double qi[3] = {h.center[0] + 0.07, h.center[1], h.center[2]};
    double d;
    assert_int_equal(hpi_kin_head_distance(&h, qi, &d, NULL, NULL, NULL), HP_OK);
    hp_assert_close(d, -0.0075, 1e-12, 0);
    /* The centre itself: no unique closest point. */
    assert_int_equal(hpi_kin_head_distance(&h, h.center, &d, NULL, NULL, NULL), HP_ERR_DOMAIN);
    /* Far points (1 m and 1 km away): the distance tends to |q − centre| − (support). */
    const double far[2][3] = {{0.3, 0.7, -0.6}, {400.0, -900.0, 100.0}};
    for (int i = 0; i < 2; ++i) check_closest(&h, far[i]);
    /* Points on coordinate planes and exactly on the surface. */
    const double plane_pts[3][3] = {{0.11, 0.05, 0.005}, {0.01, -0.02, 0.2}, {0.09, -0.02, 0.01}};
    for (int i = 0; i < 3; ++i) check_closest(&h, plane_pts[i]);
    uint64_t rng = 7;
    for (int i = 0; i < 200; ++i) {
        double u[3], s[3];
        kin_rng_vec3(&rng, 1.0, u);
        for (int k = 0; k < 3; ++k) s[k] = h.center[k] + h.semi_axes[k] * u[k];
        assert_int_equal(hpi_kin_head_distance(&h, s, &d, NULL, NULL, NULL), HP_OK);
        /* On the surface to rounding of s: |d| within a few ulps of 0.1 m. */
        hp_assert_close(d, 0.0, 0, 1e-16);
    }
    for (int i = 0; i < 20; ++i) {
        double q[3];
        kin_rng_vec3(&rng, test_rng_uniform(&rng, 0.09, 0.3), q);
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
    uint64_t rng = 11;
    for (int c = 0; c < 4; ++c)
        for (int i = 0; i < 100; ++i) {
            double q[3];
            kin_rng_vec3(&rng, test_rng_uniform(&rng, 0.05, 0.4), q);
            if (i % 10 == 0) q[0] = q[1] = 0.0; /* on the z axis */
            if (i % 10 == 1) q[1] = 0.0;        /* on a coordinate plane */
            double d1, d2, g1[3], g2[3], H1[9], H2[9];
            assert_int_equal(hpi_kin_head_distance(&cases[c], q, &d1, g1, H1, NULL), HP_OK);
            assert_int_equal(hpi_kin_head_distance(&s, q, &d2, g2, H2, NULL), HP_OK);
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
    assert_int_equal(hpi_kin_head_distance(h, q, &d, g, H, NULL), HP_OK);
    for (int j = 0; j < 3; ++j) {
        double qp[3], qm[3], gp[3], gm[3], dp, dm;
        const double hh = 1e-6;
        memcpy(qp, q, sizeof qp);
        memcpy(qm, q, sizeof qm);
        qp[j] += hh;
        qm[j] -= hh;
        assert_int_equal(hpi_kin_head_distance(h, qp, &dp, gp, NULL, NULL), HP_OK);
        assert_int_equal(hpi_kin_head_distance(h, qm, &dm, gm, NULL, NULL), HP_OK);
        for (int i = 0; i < 3; ++i)
            hp_assert_close(H[i * 3 + j], (gp[i] - gm[i]) / (2 * hh), 0, 2e-8);
        /* Richardson on the value for the gradient. */
        double D[2];
        for (int l = 0; l < 2; ++l) {
            double s = 1e-4 / (1 << l), a1[3], a2[3], v1, v2;
            memcpy(a1, q, sizeof a1);
            memcpy(a2, q, sizeof a2);
            a1[j] += s;
            a2[j] -= s;
            assert_int_equal(hpi_kin_head_distance(h, a1, &v1, NULL, NULL, NULL), HP_OK);
            assert_int_equal(hpi_kin_head_distance(h, a2, &v2, NULL, NULL, NULL), HP_OK);
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
    uint64_t rng = 3;
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
            assert_int_equal(hpi_kin_head_distance(&h, q, &d0, g0, NULL, NULL), HP_OK);
            double off = test_rng_uniform(&rng, 0.001, 0.06);
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
    uint64_t rng = 11;
    for (int i = 0; i < 400; ++i) {
        double q[3], dir[3];
        kin_rng_vec3(&rng, 1.0, q);
        double sc = i < 360 ? 1.0 : 0.9;
        for (int k = 0; k < 3; ++k) q[k] *= h.semi_axes[k] * sc;
        if (i < 360) {
            double d0, g0[3];
            assert_int_equal(hpi_kin_head_distance(&h, q, &d0, g0, NULL, NULL), HP_OK);
            double off = test_rng_uniform(&rng, 1e-4, 0.06);
            for (int k = 0; k < 3; ++k) q[k] += off * g0[k];
        }
        double d, g[3], H[9], foot[3];
        hp_kin_dist_warm wc;
        hpi_kin_dist_warm_cold(&wc, 1);
        assert_int_equal(hpi_kin_head_distance_warm(&h, q, &wc, &d, g, H, foot), HP_OK);
        double s_cold = wc.s;
        assert_true(isfinite(s_cold));
        /* A nearby point's multiplier: the point moved by up to 2 mm. */
        kin_rng_vec3(&rng, 1.0, dir);
        double qn[3], dn;
        hp_kin_dist_warm wn;
        hpi_kin_dist_warm_cold(&wn, 1);
        for (int k = 0; k < 3; ++k) qn[k] = q[k] + 0.002 * dir[k];
        assert_int_equal(hpi_kin_head_distance_warm(&h, qn, &wn, &dn, NULL, NULL, NULL), HP_OK);
        /* Multipliers alone (a zero gradient: the prediction is the multiplier itself), then
         * the nearby point's whole state (its prediction), then that state with gradients
         * that predict far off on either side or NaN. */
        const double guesses[7] = {wn.s, s_cold * 3.0 + 0.5, s_cold - 0.5, -0.999, 1e6, -5.0, NAN};
        const double dsbad[3] = {1e6, -1e6, NAN};
        for (int gi = 0; gi < 11; ++gi) {
            hp_kin_dist_warm w = wn;
            if (gi < 7) {
                w.s = guesses[gi];
                w.ds[0] = w.ds[1] = w.ds[2] = 0.0;
            } else if (gi > 7) {
                w.ds[gi % 3] = dsbad[gi - 8];
            }
            double dw, gw[3], Hw[9], fw[3];
            assert_int_equal(hpi_kin_head_distance_warm(&h, q, &w, &dw, gw, Hw, fw), HP_OK);
            double s = w.s;
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

/* The root's own uncertainty at the warm answer's s (the bound of test_long_double_reference
 * below): Q is evaluated to a few ε, so s is defined to 8ε/|Q'(s)|, besides the iteration's
 * resolution 2ε·max(1, |s|) that either solve may stop anywhere within (twice: two solves). */
static double root_spread(const hp_head *h, const double q[3], double s)
{
    const double eps = 2.220446049250313e-16, *a = h->semi_axes;
    double e = fmin(a[0], fmin(a[1], a[2])), dQ = 0.0;
    for (int k = 0; k < 3; ++k) {
        double rk = (a[k] / e) * (a[k] / e), zk = fabs(q[k] - h->center[k]) / a[k];
        double qk = rk * zk / (rk + s);
        dQ += 2.0 * qk * qk / (rk + s);
    }
    return 2.0 * (8.0 * eps / dQ + 4.0 * eps * fmax(1.0, fabs(s)));
}

/* The predicted warm start (s + ∂s/∂y·(y − y_w)) along walks like a solver's: from 300
 * seeded points (outside at 0.1..60 mm, 30 inside) around a head of axis ratio 1:1.5 and
 * one of 1:10, 40 steps each of a random length log-uniform in 1e-10..1e-3 m, every point
 * evaluated with the state the last one left (distance, normal, Hessian) and cold. Agreement:
 * the multipliers within the root's own spread (root_spread: both solves stop anywhere
 * inside it), the distance within that spread times ∂d/∂s <= e·√3·(1 + |s|/(1 + s)) (the
 * long-double test's bound) plus 4 ulps of its final rounding, the normal within
 * 2/(1 + s) times the spread plus 8ε, the Hessian 1e-12 relative as test_warm_start. The
 * path: every step up to 2e-3 of the smallest radius of curvature ρ (0.1 mm on the first
 * head, 4 µm on the second) takes one evaluation of Q (the predicted start is off by about
 * (h/ρ)², the third-order step by the cube of that); over all steps the predicted starts take
 * fewer evaluations than the same walks started from the multiplier alone (∂s/∂y = 0).
 * Then a far jump (the next walk's start with the last walk's state) and deliberately bad
 * states (wrong y, gradients of ±1e6 and NaN, an infinite multiplier) agree with the cold
 * solve the same way. */
static void check_warm_vs_cold(const hp_head *h, const double q[3], hp_kin_dist_warm *w,
                               double *worst)
{
    double d, g[3], H[9], dc, gc[3], Hc[9];
    assert_int_equal(hpi_kin_head_distance_warm(h, q, w, &d, g, H, NULL), HP_OK);
    hp_kin_dist_warm c;
    hpi_kin_dist_warm_cold(&c, 1);
    assert_int_equal(hpi_kin_head_distance_warm(h, q, &c, &dc, gc, Hc, NULL), HP_OK);
    const double eps = 2.220446049250313e-16, *a = h->semi_axes;
    double e = fmin(a[0], fmin(a[1], a[2])), sp = root_spread(h, q, c.s);
    double bd = sp * e * 1.7320508 * (1.0 + fabs(c.s) / (1.0 + c.s)) + 4.0 * eps * fabs(dc);
    double bs = sp, bg = sp * 2.0 / (1.0 + c.s) + 8.0 * eps;
    if (!(fabs(w->s - c.s) <= bs && fabs(d - dc) <= bd))
        fail_msg("warm s %.17g d %.17g, cold s %.17g d %.17g (bounds %.3g, %.3g)", w->s, d, c.s, dc,
                 bs, bd);
    worst[0] = fmax(worst[0], fabs(d - dc) / bd);
    worst[1] = fmax(worst[1], fabs(d - dc));
    for (int k = 0; k < 3; ++k) assert_true(fabs(g[k] - gc[k]) <= bg);
    for (int k = 0; k < 9; ++k) assert_true(fabs(H[k] - Hc[k]) <= 1e-12 * (1.0 + fabs(Hc[k])));
}

static void test_warm_predictor(void **state)
{
    (void)state;
    const double heads[2][3] = {{0.0775, 0.115, 0.0975}, {0.02, 0.2, 0.1}};
    uint64_t rng = 404;
    long ev_pred = 0, ev_mult = 0, small = 0;
    double worst[2] = {0, 0};
    for (int hc = 0; hc < 2; ++hc) {
        hp_head h = ellipsoid(heads[hc][0], heads[hc][1], heads[hc][2]);
        h.center[0] = 0.004;
        hp_kin_dist_warm w, wm;
        hpi_kin_dist_warm_cold(&w, 1);
        double hsmall = 2e-3 * hpi_kin_head_min_curvature_radius(&h);
        for (int i = 0; i < 150; ++i) {
            double q[3];
            kin_rng_vec3(&rng, 1.0, q);
            double sc = i % 10 == 9 ? 0.9 : 1.0;
            for (int k = 0; k < 3; ++k) q[k] = h.center[k] + q[k] * h.semi_axes[k] * sc;
            if (sc == 1.0) {
                double d0, g0[3], off = exp(test_rng_uniform(&rng, log(1e-4), log(0.06)));
                assert_int_equal(hpi_kin_head_distance(&h, q, &d0, g0, NULL, NULL), HP_OK);
                for (int k = 0; k < 3; ++k) q[k] += off * g0[k];
            }
            /* The far jump: w still holds the last walk's end. */
            check_warm_vs_cold(&h, q, &w, worst);
            wm = w;
            for (int st = 0; st < 40; ++st) {
                double dir[3], len = exp(test_rng_uniform(&rng, log(1e-10), log(1e-3)));
                kin_rng_vec3(&rng, 1.0, dir);
                for (int k = 0; k < 3; ++k) q[k] += len * dir[k];
                check_warm_vs_cold(&h, q, &w, worst);
                ev_pred += w.evals;
                if (len <= hsmall) {
                    ++small;
                    if (w.evals != 1)
                        fail_msg("head %d walk %d step %d (%.3g m): %d evaluations", hc, i, st, len,
                                 w.evals);
                }
                double dm;
                wm.ds[0] = wm.ds[1] = wm.ds[2] = 0.0; /* the multiplier alone */
                assert_int_equal(hpi_kin_head_distance_warm(&h, q, &wm, &dm, NULL, NULL, NULL),
                                 HP_OK);
                ev_mult += wm.evals;
            }
            /* Bad states at the walk's end point. */
            for (int b = 0; b < 5; ++b) {
                hp_kin_dist_warm bad = w;
                if (b == 0) bad.y[b % 3] += 0.05;
                if (b == 1) bad.ds[0] = 1e6;
                if (b == 2) bad.ds[1] = -1e6;
                if (b == 3) bad.ds[2] = NAN;
                if (b == 4) bad.s = INFINITY;
                check_warm_vs_cold(&h, q, &bad, worst);
            }
        }
    }
    print_message("warm predictor: %ld evaluations predicted, %ld from the multiplier alone "
                  "(%ld steps <= 2e-3 of the smallest curvature radius, all one evaluation); worst "
                  "distance difference %.2f of "
                  "its bound, %.2g m\n",
                  ev_pred, ev_mult, small, worst[0], worst[1]);
    assert_true(ev_pred < ev_mult);
}

/* The distance against an independent long-double reference: the root t of
 * G(t) = Σ (a_i y_i/(a_i² + t))² − 1 on (−a_min², ∞) by bisection down to adjacent long
 * doubles (64-bit significand, ε = 1.1e-19), then x_i = a_i² y_i/(a_i² + t),
 * d = sign(t)·|y − x| and the normal m/|m| with m_i = x_i/a_i², all in long double.
 * Bound (derived below, per point): the library's scaled root s = t/e² (e = a_min) is
 * defined to about 8ε/|Q'(s)| + 4ε·max(1, |s|) in double (ε = 2.2e-16), which moves d and
 * the normal by at most that times their derivatives in s, plus a few ε of final rounding.
 * Heads with axis ratios up to 1:10, points outside (0.1 mm to 300 mm), inside (10 % to
 * 99 % of the way out) and within 1e-6 of an axis plane; HP_ERR_DOMAIN is accepted only
 * inside and within 1e-3·e of the plane through the smallest semi-axis' normal (the only
 * place where the library's domain test, max_i r_i(|y_i|/a_i − 1) < −1 + 1e-3 with
 * r_i = (a_i/e)² >= 1, can fail). Seeded; about 20 000 points. A root iteration stopping
 * 1000× coarser fails it. */
static long double ref_G(const long double a[3], const long double y[3], long double t)
{
    long double g = -1.0L;
    for (int i = 0; i < 3; ++i) {
        long double q = a[i] * y[i] / (a[i] * a[i] + t);
        g += q * q;
    }
    return g;
}

/* hpi_kin_head_distances (the root finds side by side) against one hpi_kin_head_distance_k
 * call per point, in index order, on the same warm states: every distance, gradient,
 * Hessian asked for and warm state the same bits, and on failure the same error at the same
 * (first) point with every point before it the same. Heads: 1:1.5 and 1:10 ellipsoids and
 * a sphere; 300 seeded sets of 1 to 16 points each, outside, inside, on an axis, deep inside
 * (no smooth distance: an error), NaN and far away (errors), with cold, nearby (one
 * evaluation), stale and garbage warm states and a random Hessian mask. */
static void fill_point(uint64_t *rng, const hp_head *h, double q[3])
{
    const double *a = h->semi_axes;
    double u = test_rng_uniform(rng, 0.0, 1.0), f = test_rng_uniform(rng, 0.5, 1.6);
    kin_rng_vec3(rng, 1.0, q);
    for (int i = 0; i < 3; ++i)
        q[i] = h->center[i] + q[i] * a[h->shape == HP_HEAD_SPHERE ? 0 : i] * f;
    if (u < 0.03) q[1] = NAN;
    else if (u < 0.06) q[0] = 2e6;
    else if (u < 0.09)
        for (int i = 0; i < 3; ++i) q[i] = h->center[i] + 1e-6 * (q[i] - h->center[i]);
    else if (u < 0.15) q[2] = h->center[2]; /* on a coordinate plane */
}

static void test_batch(void **state)
{
    (void)state;
    hp_head heads[3] = {ellipsoid(0.0775, 0.115, 0.0975), ellipsoid(0.02, 0.2, 0.09),
                        ellipsoid(0.09, 0.09, 0.09)};
    heads[1].center[0] = 0.01;
    heads[2].shape = HP_HEAD_SPHERE;
    uint64_t rng = 90210;
    int errors = 0, compared = 0;
    for (int hi = 0; hi < 3; ++hi) {
        const hp_head *h = &heads[hi];
        hp_kin_head_k k = {0};
        if (h->shape != HP_HEAD_SPHERE) hpi_kin_head_consts(h, &k);
        for (int set = 0; set < 300; ++set) {
            int n = 1 + (int)test_rng_uniform(&rng, 0.0, HP_MAX_BLADDERS);
            double q[HP_MAX_BLADDERS][3];
            hp_kin_dist_warm w0[HP_MAX_BLADDERS];
            unsigned char want[HP_MAX_BLADDERS];
            for (int j = 0; j < n; ++j) {
                fill_point(&rng, h, q[j]);
                want[j] = test_rng_uniform(&rng, 0.0, 1.0) < 0.5;
                hpi_kin_dist_warm_cold(&w0[j], 1);
                double kind = test_rng_uniform(&rng, 0.0, 1.0);
                if (kind < 0.6) { /* a state from a point up to 1 mm away */
                    double qn[3], dir[3], dd, gg[3];
                    kin_rng_vec3(&rng, test_rng_uniform(&rng, 0.0, 1e-3), dir);
                    for (int i = 0; i < 3; ++i) qn[i] = q[j][i] + dir[i];
                    (void)hpi_kin_head_distance_k(h, &k, qn, &w0[j], &dd, gg, NULL, NULL);
                } else if (kind < 0.8) { /* garbage */
                    w0[j].s = test_rng_uniform(&rng, -2.0, 1e3);
                    for (int i = 0; i < 3; ++i) {
                        w0[j].y[i] = test_rng_uniform(&rng, -1.0, 1.0);
                        w0[j].ds[i] = test_rng_uniform(&rng, -1e3, 1e3);
                    }
                }
            }
            /* the reference: one call per point, stopping at the first error */
            hp_kin_dist_warm wr[HP_MAX_BLADDERS], wb[HP_MAX_BLADDERS];
            memcpy(wr, w0, sizeof wr);
            memcpy(wb, w0, sizeof wb);
            double dr[HP_MAX_BLADDERS], gr[HP_MAX_BLADDERS][3], Hr[HP_MAX_BLADDERS][9];
            double db[HP_MAX_BLADDERS], gb[HP_MAX_BLADDERS][3], Hb[HP_MAX_BLADDERS][9];
            memset(Hr, 0, sizeof Hr);
            memset(Hb, 0, sizeof Hb);
            hp_error er = HP_OK;
            int first = -1;
            for (int j = 0; j < n && er == HP_OK; ++j) {
                er = hpi_kin_head_distance_k(h, &k, q[j], &wr[j], &dr[j], gr[j],
                                             want[j] ? Hr[j] : NULL, NULL);
                if (er != HP_OK) first = j;
            }
            int bad = -2;
            hp_error eb = hpi_kin_head_distances(h, &k, n, (const double(*)[3])q, wb, db, gb, Hb,
                                                 want, &bad);
            assert_int_equal(eb, er);
            assert_int_equal(bad, first);
            errors += er != HP_OK;
            int upto = er == HP_OK ? n : first;
            for (int j = 0; j < upto; ++j) {
                assert_memory_equal(&db[j], &dr[j], sizeof db[j]);
                assert_memory_equal(gb[j], gr[j], sizeof gb[j]);
                assert_memory_equal(Hb[j], Hr[j], sizeof Hb[j]);
                assert_memory_equal(&wb[j], &wr[j], sizeof wb[j]);
                ++compared;
            }
        }
    }
    /* the draw reaches both outcomes, and most points are compared */
    assert_true(errors > 50 && errors < 600);
    assert_true(compared > 2000);
    /* want_h NULL: every point's Hessian, the bits of one call each */
    {
        double q8[8][3], d8[8], g8[8][3], H8[8][9], dr1, gr1[3], Hr1[9];
        for (int j = 0; j < 8; ++j) {
            kin_rng_vec3(&rng, 0.12 + 0.01 * j, q8[j]);
        }
        hp_kin_head_k k0;
        hpi_kin_head_consts(&heads[0], &k0);
        int bad8 = 0;
        assert_int_equal(hpi_kin_head_distances(&heads[0], &k0, 8, (const double(*)[3])q8, NULL, d8,
                                                g8, H8, NULL, &bad8),
                         HP_OK);
        assert_int_equal(bad8, -1);
        for (int j = 0; j < 8; ++j) {
            assert_int_equal(
                hpi_kin_head_distance_k(&heads[0], &k0, q8[j], NULL, &dr1, gr1, Hr1, NULL), HP_OK);
            assert_memory_equal(&d8[j], &dr1, sizeof dr1);
            assert_memory_equal(H8[j], Hr1, sizeof Hr1);
        }
    }
    /* more points than the batch holds: refused */
    double q1[HP_MAX_BLADDERS + 1][3] = {{0}}, d1[HP_MAX_BLADDERS + 1], g1[HP_MAX_BLADDERS + 1][3];
    int bad = 0;
    assert_int_equal(hpi_kin_head_distances(&heads[0], &(hp_kin_head_k){0}, HP_MAX_BLADDERS + 1,
                                            (const double(*)[3])q1, NULL, d1, g1, NULL, NULL, &bad),
                     HP_ERR_INVALID);
}

static void test_long_double_reference(void **state)
{
    (void)state;
    const double heads[6][3] = {{0.0775, 0.115, 0.0975}, {0.01, 0.1, 0.05}, {0.1, 0.01, 0.1},
                                {0.1, 0.1, 0.01},        {0.02, 0.2, 0.2},  {0.09, 0.09, 0.09}};
    const double eps = 2.220446049250313e-16;
    uint64_t rng = 2026;
    int n_checked = 0, n_domain = 0;
    for (int hc = 0; hc < 6; ++hc) {
        hp_head h = ellipsoid(heads[hc][0], heads[hc][1], heads[hc][2]);
        h.center[0] = 0.003;
        h.center[1] = -0.002;
        h.center[2] = 0.001;
        const double *a = h.semi_axes;
        int imin = a[0] <= a[1] && a[0] <= a[2] ? 0 : a[1] <= a[2] ? 1 : 2;
        double e = a[imin];
        long double al[3] = {a[0], a[1], a[2]}, el = e;
        for (int it = 0; it < 3400; ++it) {
            double u[3], y[3];
            kin_rng_vec3(&rng, 1.0, u);
            int kind = it % 4; /* 0, 1: outside; 2: inside; 3: near an axis plane */
            double f = kind == 2 ? test_rng_uniform(&rng, 0.1, 0.99) : 1.0;
            for (int k = 0; k < 3; ++k) y[k] = a[k] * u[k] * f; /* on (or inside) the surface */
            if (kind == 3) {
                int ax = it % 3;
                y[ax] = a[ax] * 1e-6 * test_rng_uniform(&rng, -1.0, 1.0);
                f = test_rng_uniform(&rng, 0.3, 1.5); /* inside or outside */
                for (int k = 0; k < 3; ++k) y[k] *= f;
            }
            if (kind <= 1) {
                /* Outside along the outward normal of the surface point (1e-4..0.3 m). */
                double nrm[3], nl = 0;
                for (int k = 0; k < 3; ++k) {
                    nrm[k] = y[k] / (a[k] * a[k]);
                    nl += nrm[k] * nrm[k];
                }
                nl = sqrt(nl);
                double off = exp(test_rng_uniform(&rng, log(1e-4), log(0.3)));
                for (int k = 0; k < 3; ++k) y[k] += off * nrm[k] / nl;
            }
            double q[3];
            long double yl[3];
            for (int k = 0; k < 3; ++k) {
                q[k] = h.center[k] + y[k];
                yl[k] = (long double)q[k] - (long double)h.center[k]; /* exact */
            }
            /* Reference root by bisection. */
            long double lo = -el * el, hi;
            long double ynorm = sqrtl(yl[0] * yl[0] + yl[1] * yl[1] + yl[2] * yl[2]);
            hi = ref_G(al, yl, 0.0L) > 0 ? ynorm * fmaxl(al[0], fmaxl(al[1], al[2])) + 1.0L : 0.0L;
            for (int b = 0; b < 20000; ++b) {
                long double mid = 0.5L * (lo + hi);
                if (mid <= lo || mid >= hi) break;
                if (ref_G(al, yl, mid) > 0) lo = mid;
                else hi = mid;
            }
            long double t = 0.5L * (lo + hi), ml[3], mnl = 0, dl = 0;
            for (int k = 0; k < 3; ++k) {
                long double xk = al[k] * al[k] * yl[k] / (al[k] * al[k] + t);
                ml[k] = xk / (al[k] * al[k]);
                mnl += ml[k] * ml[k];
                dl += (yl[k] - xk) * (yl[k] - xk);
            }
            mnl = sqrtl(mnl);
            long double dref = t < 0 ? -sqrtl(dl) : sqrtl(dl);
            double d, g[3];
            hp_kin_dist_warm w_out;
            hpi_kin_dist_warm_cold(&w_out, 1);
            hp_error err = hpi_kin_head_distance_warm(&h, q, &w_out, &d, g, NULL, NULL);
            if (err == HP_ERR_DOMAIN) {
                assert_true(t < 0 && fabs(y[imin]) < 1e-3 * e);
                ++n_domain;
                continue;
            }
            assert_int_equal(err, HP_OK);
            double sref = (double)(t / (el * el));
            /* The root's conditioning: Q(s) = Σ (r_i z_i/(r_i + s))² is evaluated to a few
             * ε, so s is only defined to about that over |Q'(s)| (large where the smallest
             * axis' term carries little of Q: near the plane through the other two axes),
             * besides the iteration's own resolution 2ε·max(1, |s|). */
            long double dQ = 0;
            for (int k = 0; k < 3; ++k) {
                long double rk = (al[k] / el) * (al[k] / el), zk = fabsl(yl[k]) / al[k];
                long double qk = rk * zk / (rk + t / (el * el));
                dQ += 2 * qk * qk / (rk + t / (el * el));
            }
            double ds = 8 * eps / (double)dQ + 4 * eps * fmax(1.0, fabs(sref));
            double ops = 1.0 + sref; /* the smallest r_i + s */
            /* ∂d/∂s = e²(|m| + s·∂|m|/∂s) with |m| <= √3/e, |∂|m|/∂s| <= |m|/(1 + s);
             * ∂n/∂s <= 2/(1 + s) per component. Margin ×2 over these first-order terms (the
             * worst point measured uses 15 % of the bound on d, 4 % on the normal). */
            double bound = 8 * eps * fabs((double)dref) +
                           2 * ds * e * 1.7320508 * (1 + fabs(sref) / ops);
            if (!(fabs(d - (double)dref) <= bound))
                fail_msg("head %d point %d: d %.17g, reference %.17Lg, bound %.3g", hc, it, d, dref,
                         bound);
            double gb = 8 * eps + 2 * ds * 2 / ops;
            for (int k = 0; k < 3; ++k)
                if (!(fabs(g[k] - (double)(ml[k] / mnl)) <= gb))
                    fail_msg("head %d point %d: normal %d %.17g, reference %.17Lg, bound %.3g", hc,
                             it, k, g[k], ml[k] / mnl, gb);
            ++n_checked;
        }
    }
    /* Nearly every point is answered (the DOMAIN set is a thin shell near the centre). */
    assert_true(n_checked > 19000);
    (void)n_domain;
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_axes_and_far), cmocka_unit_test(test_warm_predictor),
        cmocka_unit_test(test_near_sphere),  cmocka_unit_test(test_derivatives),
        cmocka_unit_test(test_warm_start),   cmocka_unit_test(test_long_double_reference),
        cmocka_unit_test(test_batch),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
