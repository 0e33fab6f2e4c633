/* Fitting a reference radius with the moduli (hp_fit_material_ref): exact recovery from
 * noise-free data for every pairing of measured radius and fitted radius; the standard errors
 * against an information matrix built from central differences of the forward kinematics
 * (independent of the closed-form dP/dR); coverage of the radius's 95 % interval over seeded
 * trials; designs that cannot determine the radius refused by name. */
#include "support/test_util.h"
#include "support/rng.h"
#include "headplan/hp_calib.h"

#include <string.h>

#define C1T 1.25e4
#define C2T 1.9e4

/* n points at pressures evenly spaced over [plo, phi] from bladder b, radius kind, normal
 * noise sigma (0: exact; the stated sigma is then 2e-5 m). */
static void synth(const hp_iab *b, hp_calib_radius kind, double plo, double phi, int n,
                  double sigma, uint64_t *r, hp_calib_point *pts)
{
    for (int i = 0; i < n; ++i) {
        double P = plo + (phi - plo) * i / (n - 1), ri, rad;
        assert_int_equal(hp_iab_fk(b, P, &ri), HP_OK);
        rad = ri;
        if (kind == HP_CALIB_OUTER) assert_int_equal(hp_iab_ro(b, ri, &rad), HP_OK);
        pts[i].pressure = P;
        pts[i].radius = rad + (sigma > 0 ? sigma * test_rng_normal(r) : 0.0);
        pts[i].sigma = sigma > 0 ? sigma : 2e-5;
        pts[i].line = i + 2;
    }
}

/* The truth for fitted radius ref: Ri 27.3 mm (started from 27) or Ro 30.4 mm (from 30). */
static void truth(hp_calib_radius ref, hp_iab *b, double *Ri0, double *Ro0)
{
    *b = (hp_iab){0.027, 0.030, C1T, C2T};
    *Ri0 = 0.027;
    *Ro0 = 0.030;
    if (ref == HP_CALIB_INNER) b->Ri = 0.0273;
    else b->Ro = 0.0304;
}

/* Twelve points over -4..6 kPa of the truth for radius ref, measured as kind. */
static void make_case(int kind, int ref, double sigma, uint64_t *r, hp_iab *b, double *Ri0,
                      double *Ro0, hp_calib_point pts[12])
{
    truth((hp_calib_radius)ref, b, Ri0, Ro0);
    synth(b, (hp_calib_radius)kind, -4000, 6000, 12, sigma, r, pts);
}

static void test_exact_recovery(void **state)
{
    (void)state;
    for (int kind = 0; kind < 2; ++kind)
        for (int ref = 0; ref < 2; ++ref) {
            hp_iab b;
            double Ri0, Ro0;
            hp_calib_point pts[12];
            make_case(kind, ref, 0.0, NULL, &b, &Ri0, &Ro0, pts);
            hp_material_fit f;
            hp_diag d = {{0}};
            hp_error e = hp_fit_material_ref(Ri0, Ro0, (hp_calib_radius)kind, (hp_calib_radius)ref,
                                             pts, 12, &f, NULL, &d);
            if (e) print_error("kind %d ref %d: %s\n", kind, ref, d.text);
            assert_int_equal(e, HP_OK);
            assert_int_equal(f.ref_fitted, 1);
            assert_int_equal(f.ref_kind, ref);
            assert_int_equal(f.dof, 9);
            /* Noise-free: the optimum is the truth up to the solver's stopping tolerance
             * (relative steps below 1e-13) and the forward kinematics' rounding. */
            hp_assert_close(f.ref, ref ? b.Ro : b.Ri, 1e-9, 0);
            hp_assert_close(f.C1, C1T, 1e-7, 0);
            hp_assert_close(f.C2, C2T, 1e-7, 0);
        }
    /* The two-parameter fit says it fitted no radius. */
    hp_iab b = {0.027, 0.030, C1T, C2T};
    hp_calib_point pts[12];
    synth(&b, HP_CALIB_INNER, -4000, 6000, 12, 0.0, NULL, pts);
    hp_material_fit f;
    assert_int_equal(hp_fit_material(0.027, 0.030, HP_CALIB_INNER, pts, 12, &f, NULL, NULL), HP_OK);
    assert_int_equal(f.ref_fitted, 0);
    assert_true(isnan(f.ref) && isnan(f.ref_se));
}

/* Inverse of a symmetric 3×3 matrix by cofactors. */
static void inv3(const double A[9], double C[9])
{
    C[0] = A[4] * A[8] - A[5] * A[7];
    C[1] = A[2] * A[7] - A[1] * A[8];
    C[2] = A[1] * A[5] - A[2] * A[4];
    C[3] = A[5] * A[6] - A[3] * A[8];
    C[4] = A[0] * A[8] - A[2] * A[6];
    C[5] = A[2] * A[3] - A[0] * A[5];
    C[6] = A[3] * A[7] - A[4] * A[6];
    C[7] = A[1] * A[6] - A[0] * A[7];
    C[8] = A[0] * A[4] - A[1] * A[3];
    double det = A[0] * C[0] + A[1] * C[3] + A[2] * C[6];
    for (int i = 0; i < 9; ++i) C[i] /= det;
}

static void test_jacobian_vs_finite_differences(void **state)
{
    (void)state;
    uint64_t r = 11;
    for (int kind = 0; kind < 2; ++kind)
        for (int ref = 0; ref < 2; ++ref) {
            hp_iab b;
            double Ri0, Ro0;
            hp_calib_point pts[12];
            make_case(kind, ref, 2e-5, &r, &b, &Ri0, &Ro0, pts);
            hp_material_fit f;
            double res[12];
            assert_int_equal(hp_fit_material_ref(Ri0, Ro0, (hp_calib_radius)kind,
                                                 (hp_calib_radius)ref, pts, 12, &f, res, NULL),
                             HP_OK);
            double th[3] = {f.C1, f.C2, f.ref}, A[9] = {0}, s2 = 0.0;
            for (int i = 0; i < 12; ++i) {
                double g[3];
                for (int j = 0; j < 3; ++j) {
                    double h = 1e-5 * th[j], v[2];
                    for (int sgn = 0; sgn < 2; ++sgn) {
                        double t[3] = {th[0], th[1], th[2]}, ri;
                        t[j] += sgn ? -h : h;
                        hp_iab m = {ref ? 0.027 : t[2], ref ? t[2] : 0.030, t[0], t[1]};
                        assert_int_equal(hp_iab_fk(&m, pts[i].pressure, &ri), HP_OK);
                        v[sgn] = ri;
                        if (kind == HP_CALIB_OUTER)
                            assert_int_equal(hp_iab_ro(&m, ri, &v[sgn]), HP_OK);
                    }
                    g[j] = (v[0] - v[1]) / (2 * h) / pts[i].sigma;
                }
                for (int a = 0; a < 3; ++a)
                    for (int c = 0; c < 3; ++c) A[3 * a + c] += g[a] * g[c];
                s2 += (res[i] / pts[i].sigma) * (res[i] / pts[i].sigma);
            }
            s2 /= 9;
            double C[9];
            inv3(A, C);
            /* Central differences with h = 1e-5 relative: truncation ~1e-10, the forward
             * kinematics' rounding and stopping tolerance in each column; correlations near
             * ±0.999 (a radius fitted from the other radius) amplify them in the inverse:
             * 4e-7 relative measured there, 1e-8 where the radius is well determined. */
            hp_assert_close(f.se[0], sqrt(s2 * C[0]), 1e-6, 0);
            hp_assert_close(f.se[1], sqrt(s2 * C[4]), 1e-6, 0);
            hp_assert_close(f.ref_se, sqrt(s2 * C[8]), 1e-6, 0);
            /* A correlation lies in [-1, 1]: its error is absolute (~1e-7 measured). */
            hp_assert_close(f.ref_corr[1], C[5] / sqrt(C[4] * C[8]), 0, 1e-6);
            hp_assert_close(f.ref_corr[0], C[2] / sqrt(C[0] * C[8]), 0, 1e-6);
        }
}

/* Seeded trials of 12 noisy points: the radius's 95 % interval must cover the truth in
 * 95 % ± 3 binomial standard deviations of them (400 trials: 3·1.09 % = 3.3 %; under
 * AddressSanitizer 100 trials: 3·2.18 % = 6.5 %), for Ri from inner radii and Ro from
 * outer radii (the calipers' case). */
#if defined(__SANITIZE_ADDRESS__)
#define TRIALS 100
#else
#define TRIALS 400
#endif
static void test_coverage(void **state)
{
    (void)state;
    uint64_t r = 20261201;
    const double margin = 3.0 * sqrt(0.95 * 0.05 / TRIALS);
    for (int kind = 0; kind < 2; ++kind) {
        hp_iab b;
        double Ri0, Ro0;
        truth((hp_calib_radius)kind, &b, &Ri0, &Ro0);
        int cover[3] = {0};
        for (int t = 0; t < TRIALS; ++t) {
            hp_calib_point pts[12];
            synth(&b, (hp_calib_radius)kind, -4000, 6000, 12, 2e-5, &r, pts);
            hp_material_fit f;
            hp_diag d = {{0}};
            hp_error e = hp_fit_material_ref(Ri0, Ro0, (hp_calib_radius)kind, (hp_calib_radius)kind,
                                             pts, 12, &f, NULL, &d);
            if (e) print_error("trial %d: %s\n", t, d.text);
            assert_int_equal(e, HP_OK);
            double R = kind ? b.Ro : b.Ri;
            cover[0] += f.ref_ci[0] <= R && R <= f.ref_ci[1];
            cover[1] += f.ci[0][0] <= C1T && C1T <= f.ci[0][1];
            cover[2] += f.ci[1][0] <= C2T && C2T <= f.ci[1][1];
        }
        for (int j = 0; j < 3; ++j) {
            double c = (double)cover[j] / TRIALS;
            print_message("coverage %s, %s: %.4f (95 %% +- %.4f)\n",
                          kind ? "Ro from outer radii" : "Ri from inner radii",
                          j == 0   ? "radius"
                          : j == 1 ? "C1"
                                   : "C2",
                          c, margin);
            assert_true(c >= 0.95 - margin && c <= 0.95 + margin);
        }
    }
}

static void expect_refusal(double Ri0, double Ro0, hp_calib_radius kind, hp_calib_radius ref,
                           const hp_calib_point *pts, int n, const char *w1, const char *w2)
{
    hp_material_fit f;
    hp_diag d = {{0}};
    assert_int_equal(hp_fit_material_ref(Ri0, Ro0, kind, ref, pts, n, &f, NULL, &d),
                     HP_ERR_INVALID);
    print_message("refused: %s\n", d.text);
    assert_non_null(strstr(d.text, w1));
    assert_non_null(strstr(d.text, w2));
    assert_true(isnan(f.C1) && isnan(f.ref) && f.ref_fitted == 0);
}

static void test_unidentifiable_designs(void **state)
{
    (void)state;
    hp_iab b = {0.027, 0.030, C1T, C2T};
    uint64_t r = 5;
    /* Pressures 0, 2 and 5 kPa, each three times, inner radii: zero pressure returns Ri, so
     * Ri has its three equations; Ro has two (zero pressure says nothing about it). */
    hp_calib_point pts[12];
    const double P3[3] = {0, 2000, 5000};
    for (int i = 0; i < 9; ++i) {
        double ri;
        assert_int_equal(hp_iab_fk(&b, P3[i % 3], &ri), HP_OK);
        pts[i] = (hp_calib_point){P3[i % 3], ri + 2e-5 * test_rng_normal(&r), 2e-5, i + 2};
    }
    hp_material_fit f;
    assert_int_equal(
        hp_fit_material_ref(0.027, 0.030, HP_CALIB_INNER, HP_CALIB_INNER, pts, 9, &f, NULL, NULL),
        HP_OK);
    expect_refusal(0.027, 0.030, HP_CALIB_INNER, HP_CALIB_OUTER, pts, 9, "cannot determine Ro",
                   "2 equations for 3 unknowns");
    /* A narrow band of pressures far from zero: the moduli alone are determined (condition
     * below 1e4), the radius with them is not (9.9e4 measured). */
    synth(&b, HP_CALIB_INNER, 5000, 5100, 12, 2e-5, &r, pts);
    assert_int_equal(hp_fit_material(0.027, 0.030, HP_CALIB_INNER, pts, 12, &f, NULL, NULL), HP_OK);
    expect_refusal(0.027, 0.030, HP_CALIB_INNER, HP_CALIB_INNER, pts, 12, "cannot determine Ri",
                   "condition number");
    /* Three points: no degree of freedom for the scatter with three parameters. */
    synth(&b, HP_CALIB_INNER, -4000, 6000, 3, 2e-5, &r, pts);
    expect_refusal(0.027, 0.030, HP_CALIB_INNER, HP_CALIB_INNER, pts, 3, "cannot determine Ri",
                   "at least 4");
    /* An unknown radius to fit. */
    synth(&b, HP_CALIB_INNER, -4000, 6000, 12, 2e-5, &r, pts);
    expect_refusal(0.027, 0.030, HP_CALIB_INNER, (hp_calib_radius)7, pts, 12, "ref", "Ri");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_exact_recovery),
        cmocka_unit_test(test_jacobian_vs_finite_differences),
        cmocka_unit_test(test_coverage),
        cmocka_unit_test(test_unidentifiable_designs),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
