/* The material fit (hp_fit_material): Student's t quantile against printed tables; exact
 * recovery from noise-free data (inner and outer radius); the Jacobian behind the standard
 * errors against central differences of the forward kinematics; coverage of the 95 %
 * intervals over 400 seeded trials; refusal of designs that cannot determine both moduli;
 * the information gain of one more point; neo-Hookean data (C2 = 0, on the model's bound),
 * radii in the wrong unit (a fit that does not fit), data too close to lambda = 1 to
 * separate the moduli whatever the noise. */
#include "support/test_util.h"
#include "support/rng.h"
#include "headplan/hp_calib.h"

#include <string.h>

#define RI 0.027
#define RO 0.030

/* n points at pressures evenly spaced over [plo, phi] from a bladder with moduli C1, C2,
 * radius (inner or outer) with normal noise sigma (0: exact). */
static void synth(hp_calib_radius kind, double C1, double C2, double plo, double phi, int n,
                  double sigma, uint64_t *r, hp_calib_point *pts)
{
    hp_iab b = {RI, RO, C1, C2};
    for (int i = 0; i < n; ++i) {
        double P = plo + (phi - plo) * i / (n - 1), ri, rad;
        assert_int_equal(hp_iab_fk(&b, P, &ri), HP_OK);
        rad = ri;
        if (kind == HP_CALIB_OUTER) assert_int_equal(hp_iab_ro(&b, ri, &rad), HP_OK);
        pts[i].pressure = P;
        pts[i].radius = rad + (sigma > 0 ? sigma * test_rng_normal(r) : 0.0);
        pts[i].sigma = sigma > 0 ? sigma : 2e-5;
        pts[i].line = i + 2;
    }
}

/* Reference values: the 0.975 quantiles printed in every statistics table (e.g. NIST/SEMATECH
 * e-Handbook, table 1.3.6.7.2), to the 3-5 digits printed there. */
static void test_t_quantile(void **state)
{
    (void)state;
    const double dof[] = {1, 2, 5, 10, 30, 100};
    const double want[] = {12.706, 4.303, 2.571, 2.228, 2.042, 1.984};
    for (int i = 0; i < 6; ++i)
        hp_assert_close(hp_calib_t_quantile(0.975, dof[i]), want[i], 0, 6e-4);
    /* dof = 1 is the Cauchy distribution: t = tan(π(p − 1/2)) exactly. */
    hp_assert_close(hp_calib_t_quantile(0.975, 1), tan(3.14159265358979323846 * 0.475), 1e-10, 0);
    hp_assert_close(hp_calib_t_quantile(0.9, 1), tan(3.14159265358979323846 * 0.4), 1e-10, 0);
    /* dof = 2: t = (2p − 1)·sqrt(2 / (1 − (2p − 1)²)) (closed form of the 2-dof CDF). */
    double a = 2 * 0.975 - 1;
    hp_assert_close(hp_calib_t_quantile(0.975, 2), a * sqrt(2 / (1 - a * a)), 1e-10, 0);
    hp_assert_close(hp_calib_t_quantile(0.975, 1e9), 1.959963984540054, 1e-12, 0);
    assert_true(isnan(hp_calib_t_quantile(0.975, 0.5)));
    assert_true(isnan(hp_calib_t_quantile(1.0, 5)));
}

static void test_exact_recovery(void **state)
{
    (void)state;
    hp_calib_point pts[12];
    const double C[][2] = {{1.1e4, 2.2e4}, {1.25e4, 1.9e4}, {1.1e4, 1e3}};
    for (int kind = 0; kind < 2; ++kind)
        for (int c = 0; c < 3; ++c) {
            /* The soft material (C2 = 1e3) has a limit point: stay at 90 % of it. */
            hp_iab b = {RI, RO, C[c][0], C[c][1]};
            hp_iab_limit lp;
            assert_int_equal(hp_iab_limit_point(&b, &lp), HP_OK);
            double phi = lp.exists ? fmin(6000, 0.9 * lp.pressure) : 6000;
            synth((hp_calib_radius)kind, C[c][0], C[c][1], -4000, phi, 12, 0, NULL, pts);
            hp_material_fit f;
            hp_diag d = {{0}};
            assert_int_equal(hp_fit_material(RI, RO, (hp_calib_radius)kind, pts, 12, &f, NULL, &d),
                             HP_OK);
            /* Noise-free: the only error is the FK's rounding (~1e-15 m of 3e-2 m) amplified
             * by the condition number (~20-100): 1e-8 relative is a wide margin. */
            hp_assert_close(f.C1, C[c][0], 1e-8, 0);
            hp_assert_close(f.C2, C[c][1], 1e-8, 0);
            hp_assert_close(f.C10, C[c][0] / 2, 1e-8, 0);
            hp_assert_close(f.C01, C[c][1] / 2, 1e-8, 0);
            assert_true(f.rms < 1e-12);
        }
}

/* The standard errors rebuilt from a Jacobian of central differences of hp_iab_fk (a route
 * that shares nothing with the fit's implicit-function derivatives). */
static void test_jacobian_vs_finite_differences(void **state)
{
    (void)state;
    uint64_t r = 7;
    hp_calib_point pts[10];
    for (int kind = 0; kind < 2; ++kind) {
        synth((hp_calib_radius)kind, 1.2e4, 2.0e4, -3000, 5000, 10, 2e-5, &r, pts);
        hp_material_fit f;
        double res[10];
        assert_int_equal(hp_fit_material(RI, RO, (hp_calib_radius)kind, pts, 10, &f, res, NULL),
                         HP_OK);
        double A[3] = {0};
        for (int i = 0; i < 10; ++i) {
            double g[2];
            for (int j = 0; j < 2; ++j) {
                double h = 1e-4 * (j ? f.C2 : f.C1), rp, rm;
                hp_iab bp = {RI, RO, f.C1 + (j ? 0 : h), f.C2 + (j ? h : 0)};
                hp_iab bm = {RI, RO, f.C1 - (j ? 0 : h), f.C2 - (j ? h : 0)};
                assert_int_equal(hp_iab_fk(&bp, pts[i].pressure, &rp), HP_OK);
                assert_int_equal(hp_iab_fk(&bm, pts[i].pressure, &rm), HP_OK);
                if (kind == HP_CALIB_OUTER) {
                    assert_int_equal(hp_iab_ro(&bp, rp, &rp), HP_OK);
                    assert_int_equal(hp_iab_ro(&bm, rm, &rm), HP_OK);
                }
                g[j] = (rp - rm) / (2 * h) / pts[i].sigma;
            }
            A[0] += g[0] * g[0];
            A[1] += g[0] * g[1];
            A[2] += g[1] * g[1];
        }
        double det = A[0] * A[2] - A[1] * A[1];
        double s2 = 0;
        for (int i = 0; i < 10; ++i) s2 += (res[i] / pts[i].sigma) * (res[i] / pts[i].sigma);
        s2 /= 8;
        /* Central differences with h = 1e-4 relative: truncation ~h² = 1e-8, FK rounding
         * ~1e-15/(3e-2·1e-4) ~ 3e-10; 1e-6 relative leaves room for the correlation -0.99
         * amplifying both through det. */
        hp_assert_close(f.se[0], sqrt(s2 * A[2] / det), 1e-6, 0);
        hp_assert_close(f.se[1], sqrt(s2 * A[0] / det), 1e-6, 0);
        hp_assert_close(f.corr, -A[1] / sqrt(A[0] * A[2]), 1e-6, 0);
    }
}

/* 400 seeded trials of 12 noisy points: each 95 % interval must cover the truth in
 * 95 % ± 3.3 % of them (3 binomial standard deviations, sqrt(0.95·0.05/400) = 1.09 %). */
static void test_coverage(void **state)
{
    (void)state;
    uint64_t r = 20261201;
    const int trials = 400;
    int cover[2][2] = {{0}};
    hp_calib_point pts[12];
    for (int kind = 0; kind < 2; ++kind)
        for (int t = 0; t < trials; ++t) {
            synth((hp_calib_radius)kind, 1.25e4, 1.9e4, -4000, 6000, 12, 2e-5, &r, pts);
            hp_material_fit f;
            hp_diag d = {{0}};
            assert_int_equal(hp_fit_material(RI, RO, (hp_calib_radius)kind, pts, 12, &f, NULL, &d),
                             HP_OK);
            cover[kind][0] += f.ci[0][0] <= 1.25e4 && 1.25e4 <= f.ci[0][1];
            cover[kind][1] += f.ci[1][0] <= 1.9e4 && 1.9e4 <= f.ci[1][1];
        }
    for (int kind = 0; kind < 2; ++kind)
        for (int j = 0; j < 2; ++j) {
            double c = (double)cover[kind][j] / trials;
            print_message("coverage %s C%d: %.4f\n", kind ? "outer" : "inner", j + 1, c);
            assert_true(c >= 0.95 - 0.033 && c <= 0.95 + 0.033);
        }
}

static void expect_refusal(const hp_calib_point *pts, int n, const char *words)
{
    hp_material_fit f;
    hp_diag d = {{0}};
    hp_error e = hp_fit_material(RI, RO, HP_CALIB_INNER, pts, n, &f, NULL, &d);
    if (e == HP_OK || !strstr(d.text, words)) {
        print_error("want a refusal naming '%s', got %d '%s'\n", words, e, d.text);
        fail();
    }
    assert_true(isnan(f.C1) && isnan(f.C2) && isnan(f.se[0]));
}

static void test_unidentifiable_designs(void **state)
{
    (void)state;
    uint64_t r = 3;
    hp_calib_point pts[12];
    /* One pressure, many repeats: one equation for two moduli. */
    synth(HP_CALIB_INNER, 1.1e4, 2.2e4, 2000, 2000.0000001, 12, 2e-5, &r, pts);
    for (int i = 0; i < 12; ++i) pts[i].pressure = 2000;
    expect_refusal(pts, 12, "only one non-zero pressure");
    /* One pressure plus zero-pressure points: P = 0 says nothing about the moduli. */
    for (int i = 0; i < 6; ++i) pts[i].pressure = 0, pts[i].radius = RI;
    expect_refusal(pts, 12, "only one non-zero pressure");
    for (int i = 0; i < 12; ++i) pts[i].pressure = 0, pts[i].radius = RI;
    expect_refusal(pts, 12, "no non-zero pressure");
    /* Two points: no degree of freedom left for the scatter. */
    synth(HP_CALIB_INNER, 1.1e4, 2.2e4, 1000, 3000, 2, 2e-5, &r, pts);
    expect_refusal(pts, 2, "at least 3");
    /* All within 1e-4 of λ = 1 on one side: only C1 + C2 is seen (condition ~7e4 > 1e4).
     * Pressure 5.5 Pa holds λi − 1 ≈ 1e-4 for these moduli. */
    synth(HP_CALIB_INNER, 1.1e4, 2.2e4, 0.5, 5.5, 12, 0, NULL, pts);
    expect_refusal(pts, 12, "condition number");
    /* One side up to λi ≈ 1.1 is only ill-conditioned: the fit answers, and its condition
     * number (~86) says how much worse than both sides (~21) it is. */
    hp_material_fit f;
    synth(HP_CALIB_INNER, 1.1e4, 2.2e4, 300, 3300, 12, 2e-5, &r, pts);
    assert_int_equal(hp_fit_material(RI, RO, HP_CALIB_INNER, pts, 12, &f, NULL, NULL), HP_OK);
    assert_true(f.condition > 50 && f.condition < 200);
}

/* The limit point of a soft bladder (small C2/C1), which must have one. */
static hp_iab_limit soft_limit(const hp_iab *b)
{
    hp_iab_limit lp;
    assert_int_equal(hp_iab_limit_point(b, &lp), HP_OK);
    assert_true(lp.exists);
    return lp;
}

/* Radii measured past the limit point of a neo-Hookean-like bladder (C2 small): the
 * stable-branch model cannot reproduce them; the fit says it runs into the limit point. */
static void test_limit_point_refused(void **state)
{
    (void)state;
    hp_iab b = {RI, RO, 1.1e4, 200};
    soft_limit(&b);
    hp_calib_point pts[12];
    for (int i = 0; i < 12; ++i) {
        double lam = 1.05 + 0.07 * i, P; /* up to 1.82, past the limit (~1.43) */
        assert_int_equal(hp_iab_ik(&b, lam * RI, &P), HP_OK);
        pts[i] = (hp_calib_point){P, lam * RI, 2e-5, i + 2};
    }
    expect_refusal(pts, 12, "limit point");
}

static void test_bad_points(void **state)
{
    (void)state;
    hp_calib_point pts[6];
    synth(HP_CALIB_INNER, 1.1e4, 2.2e4, -2000, 3000, 6, 0, NULL, pts);
    hp_calib_point bad[6];
    memcpy(bad, pts, sizeof bad);
    bad[2].pressure = NAN;
    expect_refusal(bad, 6, "point 4: pressure");
    memcpy(bad, pts, sizeof bad);
    bad[3].radius = -1e-3;
    expect_refusal(bad, 6, "point 5: radius");
    memcpy(bad, pts, sizeof bad);
    bad[1].sigma = 0;
    expect_refusal(bad, 6, "point 3: sigma");
    hp_material_fit f;
    assert_int_equal(hp_fit_material(0.03, 0.03, HP_CALIB_INNER, pts, 6, &f, NULL, NULL),
                     HP_ERR_INVALID);
    assert_int_equal(hp_fit_material(RI, RO, HP_CALIB_INNER, pts, 6, NULL, NULL, NULL),
                     HP_ERR_NULL);
}

/* The gain of one more point: in (0, 1]; equal to the ratio of the standard errors of a fit
 * with the point added at its model radius (zero residual) once the change of s² is undone. */
static void test_information_gain(void **state)
{
    (void)state;
    uint64_t r = 11;
    hp_calib_point pts[13];
    synth(HP_CALIB_INNER, 1.2e4, 2.0e4, -3000, 3000, 12, 2e-5, &r, pts);
    hp_material_fit f;
    assert_int_equal(hp_fit_material(RI, RO, HP_CALIB_INNER, pts, 12, &f, NULL, NULL), HP_OK);
    double cand[3] = {-5000, 500, 6000}, shrink[6];
    assert_int_equal(
        hp_fit_material_gain(RI, RO, HP_CALIB_INNER, pts, 12, &f, cand, 3, 2e-5, shrink, NULL),
        HP_OK);
    for (int j = 0; j < 3; ++j) {
        assert_true(shrink[2 * j] > 0 && shrink[2 * j] <= 1);
        /* Add the point at the fitted model's radius: the optimum does not move. */
        hp_iab fb = {RI, RO, f.C1, f.C2};
        double ri;
        assert_int_equal(hp_iab_fk(&fb, cand[j], &ri), HP_OK);
        pts[12] = (hp_calib_point){cand[j], ri, 2e-5, 99};
        hp_material_fit g;
        assert_int_equal(hp_fit_material(RI, RO, HP_CALIB_INNER, pts, 13, &g, NULL, NULL), HP_OK);
        /* s² changes from RSS/10 to RSS/11: undo it. */
        double back = sqrt(10.0 / 11.0);
        hp_assert_close(g.se[0] / f.se[0], shrink[2 * j] * back, 1e-6, 0);
        hp_assert_close(g.se[1] / f.se[1], shrink[2 * j + 1] * back, 1e-6, 0);
    }
    /* Further from λ = 1 helps more than near it. */
    assert_true(shrink[4] < shrink[2]);
}

/* Noise-free neo-Hookean data (C2 = 0) lie on the model's bound C2 >= 0: the fit gives
 * C1 back and C2 = 0 (to the rounding of the data), not a refusal. Noisy ones may prefer
 * C2 < 0; then the fit answers at the bound too (C2 = 0, the best fit the model allows). */
static void test_neo_hookean(void **state)
{
    (void)state;
    hp_iab b = {RI, RO, 1.1e4, 0.0};
    hp_iab_limit lp = soft_limit(&b);
    hp_calib_point pts[12];
    synth(HP_CALIB_INNER, 1.1e4, 0.0, -4000, 0.9 * lp.pressure, 12, 0, NULL, pts);
    hp_material_fit f;
    hp_diag d = {{0}};
    hp_error e = hp_fit_material(RI, RO, HP_CALIB_INNER, pts, 12, &f, NULL, &d);
    if (e) print_error("%s\n", d.text);
    assert_int_equal(e, HP_OK);
    /* Rounding of the synthesised radii (1e-16 relative) through a condition number of ~100:
     * 1e-8 relative on C1 and 1e-8·C1 absolute on C2 are wide margins. */
    hp_assert_close(f.C1, 1.1e4, 1e-8, 0);
    assert_true(f.C2 >= 0 && f.C2 < 1e-8 * 1.1e4);
    assert_true(f.rms < 1e-12);
    /* With noise: every one of 40 seeded data sets gives an answer with C2 >= 0 and C1
     * within 5 standard errors of the truth. */
    uint64_t r = 20261204;
    for (int t = 0; t < 40; ++t) {
        synth(HP_CALIB_INNER, 1.1e4, 0.0, -4000, 0.9 * lp.pressure, 12, 2e-5, &r, pts);
        e = hp_fit_material(RI, RO, HP_CALIB_INNER, pts, 12, &f, NULL, &d);
        if (e) print_error("trial %d: %s\n", t, d.text);
        assert_int_equal(e, HP_OK);
        assert_true(f.C2 >= 0);
        assert_true(fabs(f.C1 - 1.1e4) < 5 * f.se[0]);
    }
}

/* All points within 1e-4 of lambda = 1 see only C1 + C2: with noise too, every data set is
 * refused by name ("cannot determine both moduli"), never "did not converge" (70) nor an
 * answer. 60 seeds at each of four noise levels, from far below to far above the span of
 * the radii (2.7 um). */
static void test_near_one_refused(void **state)
{
    (void)state;
    const double sig[4] = {1e-8, 1e-7, 1e-6, 2e-5};
    int counts[4][3] = {{0}};
    for (int k = 0; k < 4; ++k) {
        uint64_t r = 1000 + (uint64_t)k;
        for (int t = 0; t < 60; ++t) {
            hp_calib_point pts[12];
            synth(HP_CALIB_INNER, 1.1e4, 2.2e4, 0.5, 5.5, 12, sig[k], &r, pts);
            hp_material_fit f;
            hp_diag d = {{0}};
            hp_error e = hp_fit_material(RI, RO, HP_CALIB_INNER, pts, 12, &f, NULL, &d);
            int named = e == HP_ERR_INVALID && strstr(d.text, "cannot determine both moduli");
            counts[k][e == HP_OK ? 0 : named ? 1 : 2]++;
            if (!named) print_error("sigma %g trial %d: %d %s\n", sig[k], t, e, d.text);
        }
    }
    for (int k = 0; k < 4; ++k) assert_int_equal(counts[k][1], 60);
}

/* Radii written in cm under an ri_mm header read ten times too small: no moduli reproduce
 * them (the fit's radii miss by ~1 m). A fit that does not fit is refused, naming the
 * residual against the data's size and the unit to check; the data in the right unit fit. */
static void test_misfit_refused(void **state)
{
    (void)state;
    uint64_t r = 7;
    hp_calib_point pts[12];
    synth(HP_CALIB_INNER, 1.25e4, 1.9e4, -4000, 6000, 12, 2e-5, &r, pts);
    hp_material_fit f;
    hp_diag d = {{0}};
    assert_int_equal(hp_fit_material(RI, RO, HP_CALIB_INNER, pts, 12, &f, NULL, &d), HP_OK);
    assert_true(f.rms < 1e-4);
    for (int i = 0; i < 12; ++i) pts[i].radius *= 0.1, pts[i].sigma = 1e-3;
    hp_error e = hp_fit_material(RI, RO, HP_CALIB_INNER, pts, 12, &f, NULL, &d);
    assert_int_equal(e, HP_ERR_INVALID);
    assert_non_null(strstr(d.text, "the fit misses the data"));
    assert_non_null(strstr(d.text, "10x too small"));
    assert_true(isnan(f.C1));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_t_quantile),
        cmocka_unit_test(test_exact_recovery),
        cmocka_unit_test(test_jacobian_vs_finite_differences),
        cmocka_unit_test(test_coverage),
        cmocka_unit_test(test_unidentifiable_designs),
        cmocka_unit_test(test_limit_point_refused),
        cmocka_unit_test(test_bad_points),
        cmocka_unit_test(test_information_gain),
        cmocka_unit_test(test_neo_hookean),
        cmocka_unit_test(test_near_one_refused),
        cmocka_unit_test(test_misfit_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
