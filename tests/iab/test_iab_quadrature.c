/* The paper's two integrals P(r) and P(R), by fixed Gauss–Legendre and adaptive
 * Gauss–Kronrod quadrature, against the closed form; and the rules themselves against
 * exact integrals of monomials. */
#include "support/test_util.h"
#include "headplan/hp_iab.h"
#include "iab/iab_internal.h"

#include <float.h>

#define ULP 0x1p-52

/* An n-point Gauss rule integrates x^k exactly for k <= 2n − 1: ∫_{-1}^{1} x^k = 2/(k+1)
 * for even k (odd k vanish by symmetry, which the half-table builds in). Tolerance
 * (16 + 2k) ulps: a node's relative error δ (~1 ulp) becomes kδ in x^k, the weights carry a
 * few ulps, and the positive sum adds ≤ 1 ulp per term relative to the total. */
static void test_gauss_legendre_rule(void **state)
{
    (void)state;
    double x[HP_IAB_GL_MAX], w[HP_IAB_GL_MAX];
    for (int n = 1; n <= HP_IAB_GL_MAX; ++n) {
        assert_int_equal(hpi_iab_gl_rule(n, x, w), HP_OK);
        for (int k = 0; k <= 2 * n - 1; k += 2) {
            double sum = 0;
            for (int i = 0; i < (n + 1) / 2; ++i)
                sum += (x[i] == 0.0 ? 1.0 : 2.0) * w[i] * pow(x[i], k);
            /* the terms are positive, so the rounding error is relative to the sum */
            hp_assert_close(sum, 2.0 / (k + 1), (16 + 2 * k) * ULP, 0);
        }
        /* the rule is not exact one degree higher (for n < 64, where 2/(2n+1) is still
         * clearly distinguishable): shows the check can fail */
        if (n <= 20) {
            double sum = 0;
            for (int i = 0; i < (n + 1) / 2; ++i)
                sum += (x[i] == 0.0 ? 1.0 : 2.0) * w[i] * pow(x[i], 2 * n);
            assert_true(fabs(sum - 2.0 / (2 * n + 1)) > 1e-12);
        }
    }
    /* The cached table holds exactly what the rule computes. */
    for (int n = 1; n <= HP_IAB_GL_MAX; ++n) {
        const double *cx, *cw;
        assert_int_equal(hpi_iab_gl_rule(n, x, w), HP_OK);
        assert_int_equal(hpi_iab_gl_cached(n, &cx, &cw), HP_OK);
        assert_memory_equal(cx, x, (size_t)(n + 1) / 2 * sizeof *x);
        assert_memory_equal(cw, w, (size_t)(n + 1) / 2 * sizeof *w);
    }
    const double *cx, *cw;
    assert_int_equal(hpi_iab_gl_cached(0, &cx, &cw), HP_ERR_INVALID);
    assert_int_equal(hpi_iab_gl_cached(65, &cx, &cw), HP_ERR_INVALID);
    assert_int_equal(hpi_iab_gl_rule(0, x, w), HP_ERR_INVALID);
    assert_int_equal(hpi_iab_gl_rule(65, x, w), HP_ERR_INVALID);
    assert_int_equal(hpi_iab_gl_rule(5, NULL, w), HP_ERR_NULL);
}

typedef struct {
    double Ri, Ro, C1, C2;
} case_t;

static const double ratios[] = {0.5, 0.7, 0.9, 0.98};

/* Size of ∫Σ|terms| of either integrand, whose rounding (a few ulps per evaluation) is the
 * floor of any quadrature of the paper's forms: the terms are 2C1(λ² + λ⁻⁴)/r,
 * 2C2(λ⁴ + λ⁻²)/r in the current form and the same times (R/r)² = λ⁻² in the reference
 * form, over a wall of thickness ro − ri. */
static double quad_scale(const hp_iab *b, double ri, double P)
{
    double ro;
    if (hp_iab_ro(b, ri, &ro) != HP_OK) return NAN;
    double m = 0;
    double ls[2] = {ri / b->Ri, ro / b->Ro};
    for (int i = 0; i < 2; ++i) {
        double l = ls[i], l2 = l * l;
        double t = b->C1 * (l2 + 1 + 1 / (l2 * l2 * l2)) + b->C2 * (l2 * l2 + l2 + 1 / (l2 * l2));
        if (t > m) m = t;
    }
    return fabs(P) + 2 * m * (ro - ri) / ri;
}
static const double c2c1[] = {0.0, 0.1, 2.0};

/* Gauss–Legendre, both forms, against the closed form, n = 64. The integrands are analytic
 * on the interval; the n-point error decays like ρ^(-2n) where ρ is the Bernstein-ellipse
 * parameter of the nearest singularity. The current form's nearest singularities (r = 0 and
 * the branch points of R(r) = cbrt(r³ − ri³ + Ri³)) keep ρ >= ~3 over this sweep. The
 * reference form has a branch point of r(R) = cbrt(R³ − (Ri³ − ri³)) at R = (Ri³ − ri³)^⅓,
 * which approaches Ri as ri → 0: for Ri/Ro = 0.5, λi = 0.5 it gives ρ ≈ 1.5, so n = 32
 * leaves ~1e-10 relative error there while n = 64 gives ~1e-22. Tolerance: 1e-14 of the
 * scale ∫Σ|terms| (whose rounding, ~1e-15 of it after 64 terms, the four-term
 * integrand carries, and which cancels to a small P near λi = 1): see quad_scale. */
static void test_gauss_vs_closed_form(void **state)
{
    (void)state;
    double worst = 0;
    for (size_t iq = 0; iq < sizeof ratios / sizeof ratios[0]; ++iq)
        for (size_t ic = 0; ic < sizeof c2c1 / sizeof c2c1[0]; ++ic) {
            hp_iab b = {ratios[iq] * 0.03, 0.03, 1.1e4, c2c1[ic] * 1.1e4};
            for (int k = 0; k <= 50; ++k) {
                double li = 0.5 + 2.5 * k / 50.0, ri = li * b.Ri, P;
                assert_int_equal(hp_iab_ik(&b, ri, &P), HP_OK);
                double scale = quad_scale(&b, ri, P);
                for (int form = 0; form < 2; ++form) {
                    double Pg;
                    assert_int_equal(hp_iab_ik_gauss(&b, ri, (hp_quad_form)form, 64, &Pg), HP_OK);
                    hp_assert_close(Pg, P, 0, 1e-14 * scale);
                    if (fabs(Pg - P) / scale > worst) worst = fabs(Pg - P) / scale;
                }
            }
        }
    printf("Gauss-Legendre n=64 vs closed form: worst |err|/scale = %.3g\n", worst);
}

/* Convergence in n: a few-point rule is visibly wrong and the error falls with n; shows
 * the comparison is not vacuous. Reference row 1 of docs/model.md (P = 3053.1854 Pa). */
static void test_gauss_convergence(void **state)
{
    (void)state;
    hp_iab b = {0.027, 0.03, 1.1e4, 2.2e4};
    double P, e_prev = INFINITY;
    assert_int_equal(hp_iab_ik(&b, 0.04, &P), HP_OK);
    for (int form = 0; form < 2; ++form) {
        e_prev = INFINITY;
        for (int n = 1; n <= 6; ++n) {
            double Pg;
            assert_int_equal(hp_iab_ik_gauss(&b, 0.04, (hp_quad_form)form, n, &Pg), HP_OK);
            double e = fabs(Pg - P);
            if (n == 1) assert_true(e > 1e-6 * fabs(P));
            assert_true(e < e_prev || e < 1e-12 * fabs(P));
            e_prev = e;
        }
    }
}

/* Adaptive Gauss–Kronrod, both forms: the result meets the requested tolerance against the
 * closed form (with the noise floor 64ε·∫Σ|terms| the routine documents), the error
 * estimate bounds the true error (|K15 − G7| is pessimistic), and a tighter tolerance does
 * not cost fewer evaluations. */
static void test_adaptive_vs_closed_form(void **state)
{
    (void)state;
    double worst_ratio = 0;
    for (size_t iq = 0; iq < sizeof ratios / sizeof ratios[0]; ++iq)
        for (size_t ic = 0; ic < sizeof c2c1 / sizeof c2c1[0]; ++ic) {
            hp_iab b = {ratios[iq] * 0.03, 0.03, 1.1e4, c2c1[ic] * 1.1e4};
            for (int k = 0; k <= 25; ++k) {
                double li = 0.5 + 2.5 * k / 25.0, ri = li * b.Ri, P;
                assert_int_equal(hp_iab_ik(&b, ri, &P), HP_OK);
                double scale = quad_scale(&b, ri, P);
                for (int form = 0; form < 2; ++form) {
                    const double tols[] = {1e-6, 1e-10, 1e-13};
                    int prev_evals = 0;
                    for (int t = 0; t < 3; ++t) {
                        double Pa, err;
                        int evals;
                        assert_int_equal(hp_iab_ik_adaptive(&b, ri, (hp_quad_form)form, tols[t],
                                                            &Pa, &err, &evals),
                                         HP_OK);
                        /* the true error is within the estimate plus rounding of the sum */
                        hp_assert_close(Pa, P, 0, err + 1e-14 * scale);
                        hp_assert_close(Pa, P, tols[t], 1e-13 * scale);
                        assert_true(evals >= prev_evals && evals >= 15 && evals % 15 == 0);
                        prev_evals = evals;
                        if (err > 0 && fabs(Pa - P) / err > worst_ratio)
                            worst_ratio = fabs(Pa - P) / err;
                    }
                }
            }
        }
    printf("adaptive GK15: worst |true error| / estimate = %.3g\n", worst_ratio);
}

/* Paper errata check by quadrature: the paper's integrals reproduce docs/model.md's reference
 * pressures (3053.1854, −5402.1338, 0 Pa) to their printed digits. */
static void test_quadrature_reference_values(void **state)
{
    (void)state;
    static const struct {
        double Ri, Ro, ri, P;
    } rows[] = {{27, 30, 30, 3053.1854}, {25, 30, 23, -5402.1338}, {27.5, 30, 27.5, 0}};
    for (size_t i = 0; i < 3; ++i) {
        hp_iab b = {rows[i].Ri * 1e-3, rows[i].Ro * 1e-3, 1.1e4, 2.2e4};
        for (int form = 0; form < 2; ++form) {
            double Pg, Pa;
            assert_int_equal(hp_iab_ik_gauss(&b, rows[i].ri * 1e-3, (hp_quad_form)form, 20, &Pg),
                             HP_OK);
            assert_int_equal(hp_iab_ik_adaptive(&b, rows[i].ri * 1e-3, (hp_quad_form)form, 1e-12,
                                                &Pa, NULL, NULL),
                             HP_OK);
            hp_assert_close(Pg, rows[i].P, 0, 0.5e-4);
            hp_assert_close(Pa, rows[i].P, 0, 0.5e-4);
        }
    }
}

/* The Kronrod constants (typed from the published tables) are checked by what defines them:
 * K15 integrates x^k exactly for k <= 22 and the embedded G7 for k <= 13 (odd k vanish by
 * symmetry). Tolerance 64 ulps: k·(node error) in x^k plus the weights' rounding. G7 must
 * miss x^14 (shows the check can fail). Then one GK15 panel on a smooth pressure integrand
 * equals Gauss–Legendre n = 64 to 1e-12 (a single interval meets tolerance 1e-3). */
static void test_kronrod_rule(void **state)
{
    (void)state;
    const double *x, *wk, *wg;
    hpi_iab_gk15_rule(&x, &wk, &wg);
    for (int k = 0; k <= 22; k += 2) {
        double sk = wk[7] * (k == 0 ? 1.0 : 0.0), sg = wg[3] * (k == 0 ? 1.0 : 0.0);
        for (int j = 0; j < 7; ++j) sk += 2 * wk[j] * pow(x[j], k);
        for (int j = 0; j < 3; ++j) sg += 2 * wg[j] * pow(x[2 * j + 1], k);
        hp_assert_close(sk, 2.0 / (k + 1), 64 * ULP, 0);
        if (k <= 13) hp_assert_close(sg, 2.0 / (k + 1), 64 * ULP, 0);
        if (k == 14) assert_true(fabs(sg - 2.0 / 15) > 1e-6);
    }
    /* the embedded nodes are the 7-point Gauss–Legendre nodes */
    double gx[HP_IAB_GL_MAX], gw[HP_IAB_GL_MAX];
    assert_int_equal(hpi_iab_gl_rule(7, gx, gw), HP_OK);
    for (int j = 0; j < 4; ++j) {
        hp_assert_close(x[2 * j + 1], gx[j], 4 * ULP, 1e-300);
        hp_assert_close(wg[j], gw[j], 8 * ULP, 0);
    }
    hp_iab b = {0.027, 0.03, 1.1e4, 2.2e4};
    double Pa, Pg, err;
    int evals;
    assert_int_equal(hp_iab_ik_adaptive(&b, 0.03, HP_QUAD_CURRENT, 1e-3, &Pa, &err, &evals), HP_OK);
    assert_int_equal(evals, 15);
    assert_int_equal(hp_iab_ik_gauss(&b, 0.03, HP_QUAD_CURRENT, 64, &Pg), HP_OK);
    hp_assert_close(Pa, Pg, 1e-12, 0);
}

static void test_quadrature_errors(void **state)
{
    (void)state;
    hp_iab b = {0.027, 0.03, 1.1e4, 2.2e4}, bad = {0.03, 0.027, 1.1e4, 2.2e4};
    double P = 0;
    assert_int_equal(hp_iab_ik_gauss(&b, 0.03, HP_QUAD_CURRENT, 0, &P), HP_ERR_INVALID);
    assert_int_equal(hp_iab_ik_gauss(&b, 0.03, HP_QUAD_CURRENT, 65, &P), HP_ERR_INVALID);
    assert_int_equal(hp_iab_ik_gauss(&b, 0.03, (hp_quad_form)7, 10, &P), HP_ERR_INVALID);
    assert_int_equal(hp_iab_ik_gauss(&b, -0.03, HP_QUAD_CURRENT, 10, &P), HP_ERR_DOMAIN);
    assert_int_equal(hp_iab_ik_gauss(&bad, 0.03, HP_QUAD_CURRENT, 10, &P), HP_ERR_DOMAIN);
    assert_int_equal(hp_iab_ik_gauss(&b, 0.03, HP_QUAD_CURRENT, 10, NULL), HP_ERR_NULL);
    assert_int_equal(hp_iab_ik_adaptive(&b, 0.03, HP_QUAD_REFERENCE, 0, &P, NULL, NULL),
                     HP_ERR_INVALID);
    assert_int_equal(hp_iab_ik_adaptive(&b, 0.03, HP_QUAD_REFERENCE, NAN, &P, NULL, NULL),
                     HP_ERR_INVALID);
    assert_int_equal(hp_iab_ik_adaptive(&b, NAN, HP_QUAD_REFERENCE, 1e-8, &P, NULL, NULL),
                     HP_ERR_INVALID);
    assert_int_equal(hp_iab_ik_adaptive(&b, 0.03, HP_QUAD_REFERENCE, 1e-8, NULL, NULL, NULL),
                     HP_ERR_NULL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_gauss_legendre_rule),
        cmocka_unit_test(test_gauss_vs_closed_form),
        cmocka_unit_test(test_gauss_convergence),
        cmocka_unit_test(test_adaptive_vs_closed_form),
        cmocka_unit_test(test_quadrature_reference_values),
        cmocka_unit_test(test_kronrod_rule),
        cmocka_unit_test(test_quadrature_errors),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
