/* Closed-form IK: docs/model.md §3 reference values, accuracy against a __float128 reference
 * over λi in [0.5, 3] × wall thicknesses × C2/C1, exact derivatives, the volume law and the
 * wall stresses. */
#include "support/test_util.h"
#include "headplan/hp_iab.h"
#include "iab_quadref.h"
#include "iab/iab_internal.h"

#include <float.h>
#include <stdint.h>
#include <string.h>

#define ULP 0x1p-52 /* 2.22e-16, the spacing of doubles in [1, 2) */

/* docs/model.md §3 table (C1 = 1.1e4 Pa, C2 = 2.2e4 Pa), printed to 7 and 8 significant
 * digits: half a unit of the last printed digit is the tolerance. */
static void test_reference_values(void **state)
{
    (void)state;
    static const struct {
        double Ri, Ro, ri, ro, P, ro_tol, P_tol;
    } rows[] = {
        {27, 30, 30, 32.49649, 3053.1854, 0.5e-5, 0.5e-4},
        {25, 30, 23, 28.66033, -5402.1338, 0.5e-5, 0.5e-4},
        {27.5, 30, 27.5, 30, 0, 0, 0},
    };
    for (size_t i = 0; i < sizeof rows / sizeof rows[0]; ++i) {
        hp_iab b = {rows[i].Ri * 1e-3, rows[i].Ro * 1e-3, 1.1e4, 2.2e4};
        double ro, P;
        assert_int_equal(hp_iab_ro(&b, rows[i].ri * 1e-3, &ro), HP_OK);
        assert_int_equal(hp_iab_ik(&b, rows[i].ri * 1e-3, &P), HP_OK);
        hp_assert_close(ro * 1e3, rows[i].ro, 0, rows[i].ro_tol + 1e-12);
        hp_assert_close(P, rows[i].P, 0, rows[i].P_tol);
    }
}

static const double ratios[] = {0.5, 0.7, 0.9, 0.95, 0.98}; /* Ri/Ro */
static const double c2c1[] = {0.0, 0.1, 2.0};
#define N_SWEEP 2001

/* The sweep's stretches: 2001 evenly over [0.5, 3], and 1 ± 10^-k (k = 3..12) with a few
 * mantissas, where the naive form cancels. Returns the count. */
static int sweep_points(double *l)
{
    int n = 0;
    for (int k = 0; k < N_SWEEP; ++k) l[n++] = 0.5 + 2.5 * k / (N_SWEEP - 1);
    for (int e = 3; e <= 12; ++e)
        for (int m = 1; m <= 9; m += 4) {
            double d = m * pow(10.0, -e);
            l[n++] = 1.0 + d;
            l[n++] = 1.0 - d;
        }
    return n;
}

/* Accuracy of hp_iab_ik against the quad reference. Bound: 16 ulps relative (16·2⁻⁵² =
 * 3.6e-15) wherever |P| > 1e-6 Pa, and 1e-9 Pa absolute below that. Why 16: a first-order
 * worst-case count of the factored form's roundings (cube differences ~3 ulps each, ro ~2,
 * the denominator x² + xy + y² ~6, the brackets F and G ~6, each rounding ≤ ½ ulp) gives
 * about 30 ulps; the roundings partly cancel and the measured worst is 8.8 ulps (printed on
 * stdout, recorded in docs/accuracy.md). The naive double form misses this bound by many
 * orders of magnitude near λi = 1 (test_naive_form_is_worse). */
static void test_accuracy_vs_quad(void **state)
{
    (void)state;
    static double l[N_SWEEP + 64];
    int n = sweep_points(l);
    double worst = 0, worst_l = 0, worst_q = 0, worst_c = 0, worst_abs = 0;
    long count = 0;
    for (size_t iq = 0; iq < sizeof ratios / sizeof ratios[0]; ++iq)
        for (size_t ic = 0; ic < sizeof c2c1 / sizeof c2c1[0]; ++ic) {
            const double Ro = 0.03, Ri = ratios[iq] * Ro, C1 = 1.1e4, C2 = c2c1[ic] * C1;
            hp_iab b = {Ri, Ro, C1, C2};
            for (int k = 0; k < n; ++k) {
                double ri = l[k] * Ri, P;
                assert_int_equal(hp_iab_ik(&b, ri, &P), HP_OK);
                double want = (double)q_ik(Ri, Ro, C1, C2, ri);
                double qerr = (double)fabsq((q128)P - q_ik(Ri, Ro, C1, C2, ri));
                ++count;
                if (fabs(want) > 1e-6) {
                    double rel = qerr / fabs(want);
                    if (rel > worst) {
                        worst = rel;
                        worst_l = ri / Ri;
                        worst_q = ratios[iq];
                        worst_c = c2c1[ic];
                    }
                    hp_assert_close(P, want, 16 * ULP, 0);
                } else {
                    if (qerr > worst_abs) worst_abs = qerr;
                    hp_assert_close(P, want, 0, 1e-9);
                }
            }
        }
    printf("closed form vs quad: %ld points, worst relative error %.3g (%.2f ulps) at "
           "lambda_i = %.17g, Ri/Ro = %g, C2/C1 = %g; worst absolute where |P| <= 1e-6 Pa: "
           "%.3g Pa\n",
           count, worst, worst / ULP, worst_l, worst_q, worst_c, worst_abs);
}

/* The naive double formula would fail the same test: shows the test can fail and that the
 * factored form is what passes it. At λi = 1 + 1e-9 the naive form keeps ~7 digits. */
static void test_naive_form_is_worse(void **state)
{
    (void)state;
    const double Ri = 0.027, Ro = 0.03, C1 = 1.1e4, C2 = 2.2e4, ri = Ri * (1 + 1e-9);
    double ro = cbrt(Ro * Ro * Ro + ri * ri * ri - Ri * Ri * Ri), li = ri / Ri, lo = ro / Ro;
    double naive = 2 * C1 * ((-1 / li - 1 / (4 * pow(li, 4))) - (-1 / lo - 1 / (4 * pow(lo, 4)))) +
                   2 * C2 * ((li - 1 / (2 * li * li)) - (lo - 1 / (2 * lo * lo)));
    double want = (double)q_ik(Ri, Ro, C1, C2, ri), P;
    hp_iab b = {Ri, Ro, C1, C2};
    assert_int_equal(hp_iab_ik(&b, ri, &P), HP_OK);
    assert_true(fabs(naive - want) > 1e3 * fabs(P - want));
    assert_true(fabs(naive - want) / fabs(want) > 1e-10);
}

/* Exact derivatives against (a) the analytic quad derivative, (b) a quad central difference
 * of the quad pressure with step h = 1e-10·ri (truncation ~h² ≈ 1e-20 relative, rounding
 * ~1e-34/1e-10 = 1e-24), and for d²P/dri² (c) a quad central difference of the quad dP/dri.
 * Tolerance: 32 ulps of the scale S = Σ|terms| of the double formula — dP/dri is a
 * difference of two terms of size S that vanishes at a limit point, so only an absolute
 * error ~ulp(S) is meaningful there. */
static void test_derivatives(void **state)
{
    (void)state;
    double worst1 = 0, worst2 = 0;
    for (size_t iq = 0; iq < sizeof ratios / sizeof ratios[0]; ++iq)
        for (size_t ic = 0; ic < sizeof c2c1 / sizeof c2c1[0]; ++ic) {
            const double Ro = 0.03, Ri = ratios[iq] * Ro, C1 = 1.1e4, C2 = c2c1[ic] * C1;
            hp_iab b = {Ri, Ro, C1, C2};
            for (int k = 0; k <= 250; ++k) {
                double li = 0.5 + 2.5 * k / 250.0, ri = li * Ri;
                double P, d1, d2, Ponly, d1only;
                assert_int_equal(hp_iab_ik_derivs(&b, ri, &P, &d1, &d2), HP_OK);
                assert_int_equal(hp_iab_ik_derivs(&b, ri, &Ponly, &d1only, NULL), HP_OK);
                assert_true(P == Ponly && d1 == d1only);
                double ro = cbrt(Ro * Ro * Ro + ri * ri * ri - Ri * Ri * Ri), lo = ro / Ro;
                double s = ri * ri / (Ro * ro * ro);
                double S1 = 2 * C1 *
                                ((1 / (li * li) + pow(li, -5)) / Ri +
                                 (1 / (lo * lo) + pow(lo, -5)) * s) +
                            2 * C2 * ((1 + pow(li, -3)) / Ri + (1 + pow(lo, -3)) * s);
                q128 qri = ri, h = 1e-10 * (q128)ri;
                q128 a1 = q_dik(Ri, Ro, C1, C2, qri);
                q128 fd1 = (q_ik(Ri, Ro, C1, C2, qri + h) - q_ik(Ri, Ro, C1, C2, qri - h)) /
                           (2 * h);
                q128 fd2 = (q_dik(Ri, Ro, C1, C2, qri + h) - q_dik(Ri, Ro, C1, C2, qri - h)) /
                           (2 * h);
                /* the two quad references agree far below the tolerance */
                hp_assert_close((double)a1, (double)fd1, 0, 1e-18 * S1);
                hp_assert_close(d1, (double)a1, 0, 32 * ULP * S1);
                /* scale of d²P: S1/ri is its natural size (each term of d² is a term of d¹
                 * over a length ~ri) */
                hp_assert_close(d2, (double)fd2, 0, 64 * ULP * S1 / ri);
                if (fabs(d1 - (double)a1) / S1 > worst1) worst1 = fabs(d1 - (double)a1) / S1;
                if (fabs(d2 - (double)fd2) * ri / S1 > worst2)
                    worst2 = fabs(d2 - (double)fd2) * ri / S1;
                /* and against each other: a double central difference of hp_iab_ik (step
                 * 1e-5·ri: truncation ~1e-10, rounding ~1e-16·P/1e-5·ri) */
                double hh = 1e-5 * ri, Pp, Pm;
                assert_int_equal(hp_iab_ik(&b, ri + hh, &Pp), HP_OK);
                assert_int_equal(hp_iab_ik(&b, ri - hh, &Pm), HP_OK);
                hp_assert_close((Pp - Pm) / (2 * hh), d1, 0, 1e-8 * S1);
                hp_assert_close((Pp - 2 * P + Pm) / (hh * hh), d2, 0, 1e-4 * S1 / ri);
            }
        }
    printf("derivatives vs quad: worst |d1 err|/S = %.3g (%.2f ulps), worst |d2 err|·ri/S = %.3g "
           "(%.2f ulps)\n",
           worst1, worst1 / ULP, worst2, worst2 / ULP);
}

/* Volume law: ro against quad cbrt (2 ulps: cbrt of a sum of two positive terms), and the
 * inverse law against the quad inverse of the same double ro to 4 ulps (Newton-refined on a
 * cancellation-free residual, see hp_iab_ri), on the sweep's walls and on thick ones (Ri/Ro
 * down to 1e-3, where the inverse's start cbrt(ro³ − (Ro³ − Ri³)) cancels up to 1e-7 of its
 * value and the Newton steps must recover it). */
static void test_volume_law(void **state)
{
    (void)state;
    static const double thick[] = {0.1, 0.01, 0.001};
    const size_t nr = sizeof ratios / sizeof ratios[0];
    for (size_t iq = 0; iq < nr + sizeof thick / sizeof thick[0]; ++iq) {
        const double Ro = 0.03, Ri = (iq < nr ? ratios[iq] : thick[iq - nr]) * Ro;
        hp_iab b = {Ri, Ro, 1.1e4, 0};
        for (int k = 0; k <= 500; ++k) {
            double ri = (0.5 + 2.5 * k / 500.0) * Ri, ro, back;
            assert_int_equal(hp_iab_ro(&b, ri, &ro), HP_OK);
            hp_assert_close(ro, (double)q_ro(Ri, Ro, ri), 2 * ULP, 0);
            assert_int_equal(hp_iab_ri(&b, ro, &back), HP_OK);
            /* ro carries ≤2 ulps; dri/dro = ro²/ri² amplifies it by ≤ (Ro/Ri)²·... so
             * compare with the quad inverse of the double ro */
            q128 qro = ro;
            q128 want = cbrtq(qro * qro * qro - (q128)Ro * Ro * Ro + (q128)Ri * Ri * Ri);
            hp_assert_close(back, (double)want, 4 * ULP, 0);
        }
    }
}

/* Wall stresses: σrr(ri) = −P, σrr(ro) = 0, σθθ − σrr against the constitutive law in quad,
 * and σrr(r) against the quad closed form from r to ro. Tolerance 32 ulps of the stress
 * scale max(|P|, C1, |σθθ|): the stresses are sums of terms of that size, and R(r) carries
 * ~2 ulps (cbrt of a rounded sum) that σθθ − σrr ≈ C2·λ⁴ amplifies fourfold, plus ~10
 * roundings of the formula. */
static void test_wall_stress(void **state)
{
    (void)state;
    const double Ri = 0.027, Ro = 0.03, C1 = 1.1e4, C2 = 2.2e4;
    hp_iab b = {Ri, Ro, C1, C2};
    for (int k = 0; k <= 20; ++k) {
        double ri = (0.6 + 2.0 * k / 20.0) * Ri, ro, P, srr, stt;
        assert_int_equal(hp_iab_ro(&b, ri, &ro), HP_OK);
        assert_int_equal(hp_iab_ik(&b, ri, &P), HP_OK);
        assert_int_equal(hp_iab_wall_stress(&b, ri, ri, &srr, &stt), HP_OK);
        assert_true(srr == -P);
        assert_int_equal(hp_iab_wall_stress(&b, ri, ro, &srr, &stt), HP_OK);
        assert_true(srr == 0.0);
        for (int j = 0; j <= 10; ++j) {
            double r = j == 10 ? ro : ri + (ro - ri) * j / 10.0;
            assert_int_equal(hp_iab_wall_stress(&b, ri, r, &srr, &stt), HP_OK);
            q128 qr = r, qri = ri;
            /* The library takes r == ro (== ri) as the outer (inner) surface, R = Ro (Ri):
             * the reference does the same rather than map the rounded ro back through the
             * volume law, which would amplify ro's rounding by dR/dr = r²/R². */
            q128 R = j == 10  ? (q128)Ro
                     : j == 0 ? (q128)Ri
                              : cbrtq(qr * qr * qr - qri * qri * qri + (q128)Ri * Ri * Ri);
            q128 l = qr / R, qro = q_ro(Ri, Ro, qri);
            q128 srr_q = -(2 * (q128)C1 * (qf(l) - qf(qro / Ro)) +
                           2 * (q128)C2 * (qg(l) - qg(qro / Ro)));
            q128 diff_q = (q128)C1 * (l * l - 1 / (l * l * l * l)) -
                          (q128)C2 * (1 / (l * l) - l * l * l * l);
            double scale = fmax(fmax(fabs(P), C1), fabs(stt));
            hp_assert_close(srr, (double)srr_q, 0, 32 * ULP * scale);
            hp_assert_close(stt - srr, (double)diff_q, 0, 32 * ULP * scale);
        }
    }
    double srr, stt;
    assert_int_equal(hp_iab_wall_stress(&b, Ri, 0.5 * Ri, &srr, &stt), HP_ERR_DOMAIN);
    assert_int_equal(hp_iab_wall_stress(&b, Ri, 1.01 * Ro, &srr, &stt), HP_ERR_DOMAIN);
    assert_int_equal(hp_iab_wall_stress(&b, Ri, NAN, &srr, &stt), HP_ERR_INVALID);
}

/* The scaling by a power of two makes the model exactly unit-free: the same bladder in
 * metres and in millimetres gives bit-identical pressures when the ratio is a power of two,
 * and a huge or tiny bladder still works. */
static void test_scale_invariance(void **state)
{
    (void)state;
    hp_iab a = {0.027, 0.03, 1.1e4, 2.2e4}, b = {0.027 * 1024, 0.03 * 1024, 1.1e4, 2.2e4};
    hp_iab c = {0.027e-200, 0.03e-200, 1.1e4, 2.2e4};
    double Pa, Pb, Pc;
    assert_int_equal(hp_iab_ik(&a, 0.03, &Pa), HP_OK);
    assert_int_equal(hp_iab_ik(&b, 0.03 * 1024, &Pb), HP_OK);
    assert_int_equal(hp_iab_ik(&c, 0.03e-200, &Pc), HP_OK);
    assert_true(Pa == Pb);
    hp_assert_close(Pc, Pa, 16 * ULP, 0);
}

/* hpi_iab_cbrt against quad cbrtq: within 0.5 ulp of the result (plus 1e-6 ulp for the
 * near-midpoint cases its header allows) on 200 000 seeded random doubles of every binade
 * of the normal range, exact on exact cubes (k³ -> k), and libm's cbrt on the values it
 * leaves to it (0, subnormal, negative, infinities, NaN). */
static void test_cbrt(void **state)
{
    (void)state;
    uint64_t st = 0x9e3779b97f4a7c15ULL;
    double worst = 0;
    for (int it = 0; it < 200000; ++it) {
        st ^= st << 13;
        st ^= st >> 7;
        st ^= st << 17;
        uint64_t E = 1 + (st >> 11) % 2046; /* biased exponent of a normal double */
        uint64_t bits = (E << 52) | (st & 0x000fffffffffffffULL);
        double x;
        memcpy(&x, &bits, sizeof x);
        double y = hpi_iab_cbrt(x);
        int ex;
        frexp(y, &ex);
        double ulp = ldexp(1.0, ex - 53);
        double err = (double)fabsq((q128)y - cbrtq((q128)x)) / ulp;
        worst = fmax(worst, err);
        assert_true(err <= 0.5 + 1e-6);
    }
    for (int k = 1; k <= 100000; ++k) {
        double c = (double)k * k * k;
        assert_true(hpi_iab_cbrt(c) == k);
        assert_true(hpi_iab_cbrt(c * 0x1p-600) == k * 0x1p-200);
    }
    const double special[] = {0.0, -0.0, 0x1p-1074, 0x1p-1030, -8.0, -1e-300, INFINITY, -INFINITY};
    for (size_t i = 0; i < sizeof special / sizeof special[0]; ++i) {
        double a = hpi_iab_cbrt(special[i]), b = cbrt(special[i]);
        assert_memory_equal(&a, &b, sizeof a);
    }
    assert_true(isnan(hpi_iab_cbrt(NAN)));
    printf("hpi_iab_cbrt vs quad: worst %.4f ulps\n", worst);
}

/* hpi_iab_cbrt_near against quad cbrtq: the same bound as hpi_iab_cbrt (0.5 ulp + 1e-6) from
 * starts a few ulps and up to 1e-13 (below its 2^-40 acceptance) off the root, on 100 000
 * seeded random x across its range [2^-300, 2^300]; hpi_iab_cbrt's very bits from starts it
 * must refuse (1e-9 off and farther, 0, negative, NaN, inf) and for x outside the range. The
 * number of near starts whose result differs from hpi_iab_cbrt's is printed (the header
 * allows it only within ~1e-7 ulp of a midpoint, so expect 0). */
static void test_cbrt_near(void **state)
{
    (void)state;
    uint64_t st = 0x2545f4914f6cdd1dULL;
    static const double near[] = {0.0,          0x1p-52,        -0x1p-52, 3 * 0x1p-52,
                                  -3 * 0x1p-52, 1000 * 0x1p-52, -1e-13,   1e-13};
    static const double far[] = {1e-9, -1e-9, 0.01, 1.0, -0.5};
    double worst = 0;
    long differ = 0;
    for (int it = 0; it < 100000; ++it) {
        st ^= st << 13;
        st ^= st >> 7;
        st ^= st << 17;
        uint64_t E = 1023 - 300 + (st >> 11) % 601; /* x in [2^-300, 2^301) */
        uint64_t bits = (E << 52) | (st & 0x000fffffffffffffULL);
        double x;
        memcpy(&x, &bits, sizeof x);
        if (x > 0x1p300) x = 0x1p300;
        double ref = hpi_iab_cbrt(x);
        q128 exact = cbrtq((q128)x);
        int ex;
        frexp(ref, &ex);
        double ulp = ldexp(1.0, ex - 53);
        for (size_t j = 0; j < sizeof near / sizeof near[0]; ++j) {
            double y = hpi_iab_cbrt_near(x, ref * (1.0 + near[j]));
            double err = (double)fabsq((q128)y - exact) / ulp;
            worst = fmax(worst, err);
            assert_true(err <= 0.5 + 1e-6);
            differ += y != ref;
        }
        for (size_t j = 0; j < sizeof far / sizeof far[0]; ++j) {
            double y = hpi_iab_cbrt_near(x, ref * (1.0 + far[j]));
            assert_memory_equal(&y, &ref, sizeof y);
        }
    }
    const double bad_start[] = {0.0, -1.0, NAN, INFINITY, 1e200, 1e-200};
    const double xs[] = {0.5,    27.0,  0x1p-300, 0x1p300, 0x1p-301, 0x1p302,
                         1e-320, 1e308, 0.0,      -8.0,    INFINITY};
    for (size_t i = 0; i < sizeof xs / sizeof xs[0]; ++i) {
        double ref = hpi_iab_cbrt(xs[i]);
        for (size_t j = 0; j < sizeof bad_start / sizeof bad_start[0]; ++j) {
            double y = hpi_iab_cbrt_near(xs[i], bad_start[j]);
            assert_memory_equal(&y, &ref, sizeof y);
        }
        if (!(xs[i] >= 0x1p-300 && xs[i] <= 0x1p300)) { /* outside the range: no refinement */
            double y = hpi_iab_cbrt_near(xs[i], ref);
            assert_memory_equal(&y, &ref, sizeof y);
        }
    }
    assert_true(isnan(hpi_iab_cbrt_near(NAN, 1.0)));
    printf("hpi_iab_cbrt_near vs quad: worst %.4f ulps; %ld of 800000 differ from hpi_iab_cbrt\n",
           worst, differ);
}

/* The scaled model's power of two (read off the exponent bits) is exactly the one frexp and
 * ldexp give, its reciprocal exactly 2^(e−1) (so a product by it has the division's bits),
 * and brings Ro into [1, 2), for Ro across the normal double range (Ri = Ro/2: any valid
 * bladder will do). */
static void test_scale_bits(void **state)
{
    (void)state;
    const double ros[] = {0.03,   1.0,       2.0,   0.5,      1.5,     0x1.fffffffffffffp-1,
                          1e-300, 0x1p-1022, 1e300, 0x1p1022, DBL_MAX, 3e-200,
                          7e250};
    for (size_t i = 0; i < sizeof ros / sizeof ros[0]; ++i) {
        hp_iab b = {ros[i] * 0.5, ros[i], 1e4, 0};
        hp_iab_s s;
        assert_int_equal(hpi_iab_scaled_init(&b, &s, NULL), HP_OK);
        int e;
        frexp(ros[i], &e);
        assert_true(s.scale == ldexp(1.0, 1 - e));
        assert_true(s.inv_scale == ldexp(1.0, e - 1)); /* exact: back to metres by a product */
        assert_true(s.Ro >= 1.0 && s.Ro < 2.0);
    }
}

/* The per-plan entry points on a bladder validated once (hpi_iab_s_ik_m, hpi_iab_s_ro_m,
 * hpi_iab_s_ri_m, what the planner calls) against the public functions: the same bits over
 * the accuracy sweep's stretches and wall thicknesses, the same codes for bad radii (NaN,
 * inf, zero, negative, a cube outside the range) and for a collapsed cavity. */
static void test_validated_once_same_bits(void **state)
{
    (void)state;
    static double l[N_SWEEP + 64];
    int n = sweep_points(l);
    for (size_t iq = 0; iq < sizeof ratios / sizeof ratios[0]; ++iq)
        for (size_t ic = 0; ic < sizeof c2c1 / sizeof c2c1[0]; ++ic) {
            const double Ro = 0.03, Ri = ratios[iq] * Ro;
            hp_iab b = {Ri, Ro, 1.1e4, c2c1[ic] * 1.1e4};
            hp_iab_s s;
            assert_int_equal(hpi_iab_scaled_init(&b, &s, NULL), HP_OK);
            for (int k = 0; k < n; ++k) {
                double ri = l[k] * Ri, P1, P2, o1, o2, r1, r2;
                assert_int_equal(hp_iab_ik(&b, ri, &P1), HP_OK);
                assert_int_equal(hpi_iab_s_ik_m(&s, ri, &P2), HP_OK);
                assert_memory_equal(&P1, &P2, sizeof P1);
                assert_int_equal(hp_iab_ro(&b, ri, &o1), HP_OK);
                assert_int_equal(hpi_iab_s_ro_m(&s, ri, &o2), HP_OK);
                assert_memory_equal(&o1, &o2, sizeof o1);
                /* the answer's path: the outer radius the pressure uses refined from a
                 * nearby one (the exact one, or one 4 ulps off) */
                double P3, P4;
                assert_int_equal(hpi_iab_s_ik_near_m(&s, ri, o1, &P3), HP_OK);
                assert_int_equal(hpi_iab_s_ik_near_m(&s, ri, o1 * (1 + 4 * ULP), &P4), HP_OK);
                assert_memory_equal(&P1, &P3, sizeof P1);
                assert_memory_equal(&P1, &P4, sizeof P1);
                double P5, o5;
                assert_int_equal(hpi_iab_s_ik_ro_m(&s, ri, &P5, &o5), HP_OK);
                assert_memory_equal(&P1, &P5, sizeof P1);
                assert_memory_equal(&o1, &o5, sizeof o1);
                hp_error e1 = hp_iab_ri(&b, o1, &r1), e2 = hpi_iab_s_ri_m(&s, o1, &r2);
                assert_int_equal(e1, e2);
                if (e1 == HP_OK) assert_memory_equal(&r1, &r2, sizeof r1);
            }
            const double bad[] = {NAN, INFINITY, -INFINITY, 0.0, -Ri, 1e-40, 1e40, 0.5 * (Ro - Ri)};
            for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
                double x = 5.0, y = 5.0;
                assert_int_equal(hpi_iab_s_ik_m(&s, bad[i], &x), hp_iab_ik(&b, bad[i], &y));
                assert_int_equal(hpi_iab_s_ro_m(&s, bad[i], &x), hp_iab_ro(&b, bad[i], &y));
                assert_int_equal(hpi_iab_s_ik_near_m(&s, bad[i], Ro, &x),
                                 hp_iab_ik(&b, bad[i], &y));
                double z = 5.0;
                assert_int_equal(hpi_iab_s_ik_ro_m(&s, bad[i], &x, &z), hp_iab_ik(&b, bad[i], &y));
                assert_int_equal(hpi_iab_s_ri_m(&s, bad[i], &x), hp_iab_ri(&b, bad[i], &y));
            }
        }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_reference_values),
        cmocka_unit_test(test_accuracy_vs_quad),
        cmocka_unit_test(test_naive_form_is_worse),
        cmocka_unit_test(test_derivatives),
        cmocka_unit_test(test_volume_law),
        cmocka_unit_test(test_wall_stress),
        cmocka_unit_test(test_scale_invariance),
        cmocka_unit_test(test_cbrt),
        cmocka_unit_test(test_cbrt_near),
        cmocka_unit_test(test_scale_bits),
        cmocka_unit_test(test_validated_once_same_bits),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
