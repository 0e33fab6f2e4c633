/* Forward kinematics and the inflation limit point: against a hand derivation of
 * dP/dλi = 0 solved in quad precision, the thin-shell limit 7^(1/6), FK∘IK round trips,
 * and HP_ERR_NO_STABLE at and above the limit-point pressure. */
#include "support/test_util.h"
#include "support/rng.h"
#include "headplan/hp_iab.h"
#include "iab_quadref.h"
#include "iab/iab_internal.h"

#define ULP 0x1p-52

/* Hand derivation (C2 = 0). P = 2C1[f(λi) − f(λo)], f'(λ) = λ⁻²(1 + λ⁻³), and from the volume
 * law dλo/dλi = (Ri/Ro)³·λi²/λo². So dP/dλi = 0 ⇔ λi⁻⁴(1 + λi⁻³)·Ro³ = λo⁻⁴(1 + λo⁻³)·Ri³,
 * with λo³ = 1 + (λi³ − 1)(Ri/Ro)³. The left minus right side is positive at λi = 1 (Ro > Ri)
 * and negative for large λi; solved here by quad bisection (113-bit) on a bracket. */
static q128 hand_residual(q128 l, q128 q)
{
    q128 q3 = q * q * q;
    q128 lo = cbrtq(1 + (l * l * l - 1) * q3);
    return (1 + 1 / (l * l * l)) / (l * l * l * l) -
           q3 * (1 + 1 / (lo * lo * lo)) / (lo * lo * lo * lo);
}

static q128 hand_limit(q128 q)
{
    q128 a = 1, b = 10 / q;
    for (int it = 0; it < 200; ++it) {
        q128 m = (a + b) / 2;
        if (hand_residual(m, q) > 0) a = m;
        else b = m;
    }
    return (a + b) / 2;
}

static void test_limit_point_neo_hookean(void **state)
{
    (void)state;
    const double qs[] = {0.5, 0.7, 0.8, 0.9, 0.95, 0.98, 0.999};
    double worst = 0;
    for (size_t i = 0; i < sizeof qs / sizeof qs[0]; ++i) {
        const double Ro = 0.03, Ri = qs[i] * Ro, C1 = 1.1e4;
        hp_iab b = {Ri, Ro, C1, 0};
        hp_iab_limit lp;
        assert_int_equal(hp_iab_limit_point(&b, &lp), HP_OK);
        assert_int_equal(lp.exists, 1);
        q128 lq = hand_limit((q128)Ri / Ro);
        /* Tolerance 1e-12 relative in λi: the library locates the sign change of its computed
         * dP/dri, whose rounding noise (~ulps of its two terms of size S) shifts the root by
         * ~ε·S/|d²P/dri²|·(1/ri), about 1e-14 here (measured below); 100× margin. */
        hp_assert_close(lp.lambda_i, (double)lq, 1e-12, 0);
        if (fabs(lp.lambda_i - (double)lq) / (double)lq > worst)
            worst = fabs(lp.lambda_i - (double)lq) / (double)lq;
        hp_assert_close(lp.ri, lp.lambda_i * Ri, 2 * ULP, 0);
        /* P is flat at its maximum, so the λ error enters P at second order: 16 ulps. */
        hp_assert_close(lp.pressure, (double)q_ik(Ri, Ro, C1, 0, lq * Ri), 16 * ULP, 0);
        /* a maximum: P is lower a little either side */
        double Pm, Pp;
        assert_int_equal(hp_iab_ik(&b, lp.ri * (1 - 1e-4), &Pm), HP_OK);
        assert_int_equal(hp_iab_ik(&b, lp.ri * (1 + 1e-4), &Pp), HP_OK);
        assert_true(Pm < lp.pressure && Pp < lp.pressure);
    }
    printf(
        "neo-Hookean limit point vs quad hand derivation: worst relative error in lambda_i %.3g\n",
        worst);
    /* docs/model.md's "near 1.43" is the 27/30 mm shell: 1.4312271769565827 (quad). */
    hp_iab b = {0.027, 0.03, 1.1e4, 0};
    hp_iab_limit lp;
    assert_int_equal(hp_iab_limit_point(&b, &lp), HP_OK);
    hp_assert_close(lp.lambda_i, 1.4312271769565827, 1e-12, 0);
    /* Thin-shell limit: P ∝ λ⁻¹ − λ⁻⁷ (membrane), maximal at λ⁶ = 7. The thick-shell value
     * approaches it linearly in the thickness (0.999 gives 1.38352 vs 1.38309). */
    hp_iab thin = {0.03 * 0.99999, 0.03, 1.1e4, 0};
    assert_int_equal(hp_iab_limit_point(&thin, &lp), HP_OK);
    hp_assert_close(lp.lambda_i, pow(7.0, 1.0 / 6.0), 1e-4, 0);
}

/* With C2 > 0 the first maximum (if any) is found by the same dP/dri = 0 search; checked
 * against quad bisection on the quad analytic derivative for C2/C1 = 0.05, 0.1, and
 * "none" for the paper's C2/C1 = 2 (P rises monotonically: quad derivative positive on a
 * dense grid to λi = 64·Ro/Ri). */
static void test_limit_point_mooney_rivlin(void **state)
{
    (void)state;
    const double Ro = 0.03, Ri = 0.027, C1 = 1.1e4;
    const double cs[] = {0.05, 0.1};
    for (int i = 0; i < 2; ++i) {
        hp_iab b = {Ri, Ro, C1, cs[i] * C1};
        hp_iab_limit lp;
        assert_int_equal(hp_iab_limit_point(&b, &lp), HP_OK);
        assert_int_equal(lp.exists, 1);
        q128 a = Ri, c = 2 * Ri; /* dP > 0 at λi = 1, < 0 at 2 for these moduli */
        assert_true(q_dik(Ri, Ro, C1, cs[i] * C1, c) < 0);
        for (int it = 0; it < 200; ++it) {
            q128 m = (a + c) / 2;
            if (q_dik(Ri, Ro, C1, cs[i] * C1, m) > 0) a = m;
            else c = m;
        }
        hp_assert_close(lp.ri, (double)a, 1e-12, 0);
    }
    hp_iab paper = {Ri, Ro, C1, 2.2e4};
    hp_iab_limit lp;
    assert_int_equal(hp_iab_limit_point(&paper, &lp), HP_OK);
    assert_int_equal(lp.exists, 0);
    assert_true(isinf(lp.lambda_i) && isinf(lp.ri) && isinf(lp.pressure));
    for (int k = 0; k <= 4000; ++k) {
        q128 ri = Ri * powq(64 * Ro / Ri, (q128)k / 4000);
        assert_true(q_dik(Ri, Ro, C1, 2.2e4, ri) > 0);
    }
}

/* Near the threshold C2/C1 where the limit point disappears, the maximum and the following
 * minimum merge: a coarse scan of dP/dri could step over a narrow dip. The library's answer
 * (exists or not) is compared with a dense quad scan (20 000 points on λi ∈ [1, 4]) over a
 * fine sweep of C2/C1 across the threshold. */
static void test_limit_point_threshold(void **state)
{
    (void)state;
    const double Ro = 0.03, Ri = 0.027, C1 = 1.1e4;
    int seen_yes = 0, seen_no = 0;
    for (int k = 0; k <= 40; ++k) {
        double c = 0.15 + 0.0025 * k;
        hp_iab b = {Ri, Ro, C1, c * C1};
        hp_iab_limit lp;
        assert_int_equal(hp_iab_limit_point(&b, &lp), HP_OK);
        int quad_has = 0;
        for (int j = 0; j <= 20000 && !quad_has; ++j)
            if (q_dik(Ri, Ro, C1, c * C1, (q128)Ri * (1 + 3 * (q128)j / 20000)) <= 0) quad_has = 1;
        assert_int_equal(lp.exists, quad_has);
        seen_yes += quad_has;
        seen_no += !quad_has;
    }
    assert_true(seen_yes > 0 && seen_no > 0); /* the sweep does cross the threshold */
}

/* FK∘IK returns ri to 1e-12 relative on the stable branch. Conditioning: δri/ri ≈
 * δP/(ri·dP/dri) with δP ~ 16 ulps of P; away from the limit point (λi <= 0.97·λ*) this is
 * < 1e-13 for every case here. */
static void test_fk_round_trip(void **state)
{
    (void)state;
    const double qs[] = {0.5, 0.7, 0.9, 0.95, 0.98}, cs[] = {0, 0.1, 2};
    double worst = 0;
    for (size_t iq = 0; iq < 5; ++iq)
        for (size_t ic = 0; ic < 3; ++ic) {
            hp_iab b = {qs[iq] * 0.03, 0.03, 1.1e4, cs[ic] * 1.1e4};
            hp_iab_limit lp;
            assert_int_equal(hp_iab_limit_point(&b, &lp), HP_OK);
            double top = lp.exists ? fmin(3.0, 0.97 * lp.lambda_i) : 3.0;
            for (int k = 0; k <= 300; ++k) {
                double ri = (0.5 + (top - 0.5) * k / 300.0) * b.Ri, P, back;
                assert_int_equal(hp_iab_ik(&b, ri, &P), HP_OK);
                assert_int_equal(hp_iab_fk(&b, P, &back), HP_OK);
                hp_assert_close(back, ri, 1e-12, 0);
                if (fabs(back - ri) / ri > worst) worst = fabs(back - ri) / ri;
            }
        }
    printf("FK(IK(ri)) worst relative error in ri: %.3g\n", worst);
    /* P = 0 is the reference radius exactly */
    hp_iab b = {0.027, 0.03, 1.1e4, 2.2e4};
    double r;
    assert_int_equal(hp_iab_fk(&b, 0.0, &r), HP_OK);
    assert_true(r == 0.027);
    /* far up the paper material's branch (no limit point) and deep compression */
    double P;
    assert_int_equal(hp_iab_ik(&b, 30.0, &P), HP_OK);
    assert_int_equal(hp_iab_fk(&b, P, &r), HP_OK);
    hp_assert_close(r, 30.0, 1e-12, 0);
    assert_int_equal(hp_iab_ik(&b, 0.027 * 0.05, &P), HP_OK);
    assert_int_equal(hp_iab_fk(&b, P, &r), HP_OK);
    hp_assert_close(r, 0.027 * 0.05, 1e-12, 0);
}

/* At and above the limit-point pressure there is no stable radius; just below there is,
 * and it lies below the limit-point radius. The output is left untouched on failure. */
static void test_fk_no_stable(void **state)
{
    (void)state;
    hp_iab b = {0.027, 0.03, 1.1e4, 0};
    hp_iab_limit lp;
    assert_int_equal(hp_iab_limit_point(&b, &lp), HP_OK);
    double r = 123.0;
    assert_int_equal(hp_iab_fk(&b, lp.pressure, &r), HP_ERR_NO_STABLE);
    assert_int_equal(hp_iab_fk(&b, lp.pressure * 1.5, &r), HP_ERR_NO_STABLE);
    assert_int_equal(hp_iab_fk(&b, 1e300, &r), HP_ERR_NO_STABLE);
    assert_true(r == 123.0);
    assert_int_equal(hp_iab_fk(&b, lp.pressure * (1 - 1e-9), &r), HP_OK);
    assert_true(r < lp.ri && r > 0.027);
    /* the stable-branch root, not the one past the maximum: IK there gives the pressure */
    double P;
    assert_int_equal(hp_iab_ik(&b, r, &P), HP_OK);
    hp_assert_close(P, lp.pressure * (1 - 1e-9), 1e-12, 0);
    /* pressures the model cannot reach without leaving the double range */
    assert_int_equal(hp_iab_fk(&b, -1e300, &r), HP_ERR_DOMAIN);
    hp_iab paper = {0.027, 0.03, 1.1e4, 2.2e4};
    assert_int_equal(hp_iab_fk(&paper, 1e300, &r), HP_ERR_DOMAIN);
    assert_int_equal(hp_iab_fk(&paper, NAN, &r), HP_ERR_INVALID);
    assert_int_equal(hp_iab_fk(&paper, INFINITY, &r), HP_ERR_INVALID);
    assert_int_equal(hp_iab_fk(&paper, 1.0, NULL), HP_ERR_NULL);
    assert_true(r == r); /* never NaN */
}

/* Bladder m of three materials (C2/C1 = 0, neo-Hookean, and 0.1, both with a limit point;
 * 2, the paper's, without) and its limit point. */
#define N_MATERIALS 3
static void material(int m, hp_iab *b, hp_iab_limit *lp)
{
    const double c2s[N_MATERIALS] = {0.0, 0.1 * 1.1e4, 2.2e4};
    *b = (hp_iab){0.027, 0.030, 1.1e4, c2s[m]};
    assert_int_equal(hp_iab_limit_point(b, lp), HP_OK);
}

/* hp_iab_fk_limit with a precomputed limit point is the same computation as hp_iab_fk:
 * identical bits over compression, expansion, and up to the limit point; the same refusal
 * above it; and a limit point of another material is refused when it cannot belong. */
static void test_fk_limit_same_as_fk(void **state)
{
    (void)state;
    for (int m = 0; m < N_MATERIALS; ++m) {
        hp_iab b;
        hp_iab_limit lp;
        material(m, &b, &lp);
        double p_top = lp.exists ? lp.pressure : 2e4;
        for (int k = -200; k <= 200; ++k) {
            double P = k < 0 ? 40.0 * k : p_top * (k / 200.0) * (1.0 - 1e-9);
            double r1 = NAN, r2 = NAN;
            hp_error e1 = hp_iab_fk(&b, P, &r1), e2 = hp_iab_fk_limit(&b, &lp, P, &r2);
            assert_int_equal(e1, e2);
            if (e1 == HP_OK) assert_memory_equal(&r1, &r2, sizeof r1);
        }
        if (lp.exists) {
            double r;
            assert_int_equal(hp_iab_fk_limit(&b, &lp, lp.pressure * 1.001, &r), HP_ERR_NO_STABLE);
            hp_iab_limit bad = lp;
            bad.ri = b.Ri * 0.5; /* below Ri: cannot be an inflation limit point */
            assert_int_equal(hp_iab_fk_limit(&b, &bad, 10.0, &r), HP_ERR_INVALID);
        }
    }
    double r;
    hp_iab b = {0.027, 0.030, 1.1e4, 2.2e4};
    assert_int_equal(hp_iab_fk_limit(&b, NULL, 1.0, &r), HP_ERR_NULL);
}

/* The warm start (hpi_iab_fk_limit_warm, the planner's round trip): given the radius a
 * pressure came from (P = hp_iab_ik(ri)), it returns that radius bit for bit, over
 * compression and expansion up to the limit point; a guess that cannot be the stable root
 * (on the other side of Ri, beyond the limit point, NaN) changes nothing: the same bits as
 * the cold call. hpi_iab_fk_limit_warm_ro gives the same root and hp_iab_ro's bits at it. */
static void test_fk_warm(void **state)
{
    (void)state;
    for (int m = 0; m < N_MATERIALS; ++m) {
        hp_iab b;
        hp_iab_limit lp;
        material(m, &b, &lp);
        double top = lp.exists ? lp.ri : 2.0 * b.Ri;
        for (int k = -100; k <= 100; ++k) {
            if (k == 0) continue;
            double ri = k < 0 ? b.Ri * (1.0 + 0.004 * k) : b.Ri + (top - b.Ri) * k / 101.0;
            double P, w, cold, w2;
            assert_int_equal(hp_iab_ik(&b, ri, &P), HP_OK);
            assert_int_equal(hpi_iab_fk_limit_warm(&b, &lp, P, ri, &w), HP_OK);
            assert_memory_equal(&w, &ri, sizeof w);
            assert_int_equal(hp_iab_fk_limit(&b, &lp, P, &cold), HP_OK);
            const double bad[] = {k < 0 ? 1.5 * b.Ri : 0.5 * b.Ri, lp.exists ? 1.5 * lp.ri : -1.0,
                                  NAN, ri};
            for (int i = 0; i < 4; ++i) {
                assert_int_equal(hpi_iab_fk_limit_warm(&b, &lp, P, bad[i], &w2), HP_OK);
                assert_memory_equal(&w2, i < 3 ? &cold : &ri, sizeof w2);
                /* the round trip validated once: the same root, and hp_iab_ro's bits at it
                 * (for the exact guess, the outer radius the pressure's evaluation formed) */
                double r2, o1, o2;
                assert_int_equal(hp_iab_ro(&b, w2, &o1), HP_OK);
                assert_int_equal(hpi_iab_fk_limit_warm_ro(&b, &lp, P, bad[i], &r2, &o2), HP_OK);
                assert_memory_equal(&r2, &w2, sizeof r2);
                assert_memory_equal(&o2, &o1, sizeof o2);
            }
        }
    }
}

/* hpi_iab_fk_limit_warm_ro's refusals (NaN pressure, above the limit point, NULL), outputs
 * untouched, and P = 0 (the reference radii); its bits are checked in test_fk_warm. */
static void test_fk_warm_ro(void **state)
{
    (void)state;
    for (int m = 0; m < N_MATERIALS; ++m) {
        hp_iab b;
        hp_iab_limit lp;
        material(m, &b, &lp);
        double r = 7.0, o = 8.0;
        assert_int_equal(hpi_iab_fk_limit_warm_ro(&b, &lp, NAN, b.Ri, &r, &o), HP_ERR_INVALID);
        assert_int_equal(hpi_iab_fk_limit_warm_ro(&b, &lp, 1e4, b.Ri, NULL, &o), HP_ERR_NULL);
        assert_int_equal(hpi_iab_fk_limit_warm_ro(&b, &lp, 1e4, b.Ri, &r, NULL), HP_ERR_NULL);
        if (lp.exists)
            assert_int_equal(hpi_iab_fk_limit_warm_ro(&b, &lp, lp.pressure * 1.001, lp.ri, &r, &o),
                             HP_ERR_NO_STABLE);
        assert_true(r == 7.0 && o == 8.0);
        assert_int_equal(hpi_iab_fk_limit_warm_ro(&b, &lp, 0.0, NAN, &r, &o), HP_OK);
        assert_true(r == b.Ri && o == b.Ro);
    }
}

/* A seeded bladder, validated: thickness ratio 0.6..0.97, C2/C1 0..0.5. */
static hp_iab_s seeded_bladder(uint64_t *seed)
{
    double q = test_rng_uniform(seed, 0.6, 0.97), c = test_rng_uniform(seed, 0.0, 0.5);
    hp_iab b = {q * 0.03, 0.03, 1.1e4, c * 1.1e4};
    hp_iab_s s = {0};
    assert_int_equal(hpi_iab_scaled_init(&b, &s, NULL), HP_OK);
    return s;
}

/* The root find's evaluation (hpi_iab_s_pressure_slope: the pressure, the outer radius and
 * the slope in one pass, sharing the stretches the two formulas both form) gives the bits of
 * the two calls it stands for (hpi_iab_s_pressure_ro, then hpi_iab_s_slopes at that outer
 * radius), and their codes: seeded bladders (thickness ratio 0.6..0.97, C2/C1 0..0.5) at
 * inner radii from a twentieth of Ri to twenty times it (log-uniform), and the edges 0 and
 * a radius whose pressure overflows. */
static void test_pressure_slope_same_bits(void **state)
{
    (void)state;
    uint64_t seed = 0x51095;
    long n = 0;
    for (int t = 0; t < 2000; ++t) {
        hp_iab_s s = seeded_bladder(&seed);
        for (int i = 0; i < 50; ++i) {
            double ri = s.Ri * exp(test_rng_uniform(&seed, log(0.05), log(20.0)));
            if (i == 0) ri = 1e200;
            double p1, ro1, d1 = NAN, p2 = NAN, ro2 = NAN, d2 = NAN;
            hp_error e1 = hpi_iab_s_pressure_ro(&s, ri, &p1, &ro1);
            if (e1 == HP_OK) e1 = hpi_iab_s_slopes(&s, ri, ro1, &d1, NULL);
            hp_error e2 = hpi_iab_s_pressure_slope(&s, ri, &p2, &ro2, &d2);
            assert_int_equal(e1, e2);
            if (e1 != HP_OK) continue;
            assert_memory_equal(&p1, &p2, sizeof p1);
            assert_memory_equal(&ro1, &ro2, sizeof ro1);
            assert_memory_equal(&d1, &d2, sizeof d1);
            ++n;
        }
    }
    print_message("%ld evaluations, the two calls' bits each time\n", n);
    assert_true(n > 90000);
}

/* The root find's evaluations next to an earlier one (hpi_iab_s_pressure_slope_near and
 * hpi_iab_s_pressure_ro_near: the outer radius's cube root from a first-order step off the
 * earlier evaluation's) give the bits of the full ones: on seeded bladders as above, at
 * radii a Newton step (relative 1e-16 to 1e-7) from the earlier one, whose first-order start
 * is checked to lie within the 2^-40 the near cube root takes (so that path, not its fall
 * back, gave the bits), and from far (1e-2) and NaN earlier radii and outer radii no
 * evaluation gives (0, negative, infinite, 1e±300: the full cube root's fall back). The
 * near root is the correctly rounded one but within ~1e-7 ulp of a midpoint, as the full
 * one is, so the bits may differ there: none of these 600 000 do. */
static void test_pressure_near_same_bits(void **state)
{
    (void)state;
    static const double steps[] = {0.0, 1e-16, -3e-16, 1e-13, -1e-12, 1e-10, -1e-9, 1e-7, 1e-2};
    const int ns = (int)(sizeof steps / sizeof steps[0]);
    uint64_t seed = 0x4ea5;
    long n = 0, near = 0;
    for (int t = 0; t < 1000; ++t) {
        hp_iab_s s = seeded_bladder(&seed);
        for (int i = 0; i < 30; ++i) {
            double ri = s.Ri * exp(test_rng_uniform(&seed, log(0.3), log(3.0)));
            double p1, ro1, d1;
            if (hpi_iab_s_pressure_slope(&s, ri, &p1, &ro1, &d1) != HP_OK) continue;
            for (int j = 0; j <= ns; ++j) {
                /* j == ns: no earlier evaluation (NaN) */
                double ri0 = j < ns ? ri * (1.0 - steps[j]) : NAN, ro0 = hpi_iab_s_ro(&s, ri0);
                if (j < ns && fabs(steps[j]) <= 1e-7) {
                    double w = ri0 / ro0, y0 = ro0 + w * w * (ri - ri0);
                    assert_true(fabs(y0 - ro1) <= 0x1p-41 * ro1);
                    ++near;
                }
                double p2 = NAN, ro2 = NAN, d2 = NAN, p3 = NAN, ro3 = NAN;
                assert_int_equal(hpi_iab_s_pressure_slope_near(&s, ri, ri0, ro0, &p2, &ro2, &d2),
                                 HP_OK);
                assert_int_equal(hpi_iab_s_pressure_ro_near(&s, ri, ri0, ro0, &p3, &ro3), HP_OK);
                assert_memory_equal(&p1, &p2, sizeof p1);
                assert_memory_equal(&ro1, &ro2, sizeof ro1);
                assert_memory_equal(&d1, &d2, sizeof d1);
                assert_memory_equal(&p1, &p3, sizeof p1);
                assert_memory_equal(&ro1, &ro3, sizeof ro1);
                n += 2;
            }
            /* Outer radii no evaluation gives (zero, negative, infinite, out of range): the
             * full cube root's bits too. */
            static const double odd[] = {0.0, -1.0, INFINITY, -INFINITY, 1e-300, 1e300};
            for (int j = 0; j < (int)(sizeof odd / sizeof odd[0]); ++j) {
                double p2 = NAN, ro2 = NAN, d2 = NAN;
                assert_int_equal(hpi_iab_s_pressure_slope_near(&s, ri, ri, odd[j], &p2, &ro2, &d2),
                                 HP_OK);
                assert_memory_equal(&p1, &p2, sizeof p1);
                assert_memory_equal(&ro1, &ro2, sizeof ro1);
                assert_memory_equal(&d1, &d2, sizeof d1);
            }
        }
    }
    print_message("%ld near evaluations (%ld from a start within 2^-41), the full bits each time\n",
                  n, near);
    assert_true(n > 500000 && near > 200000);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_limit_point_neo_hookean),
        cmocka_unit_test(test_limit_point_mooney_rivlin),
        cmocka_unit_test(test_limit_point_threshold),
        cmocka_unit_test(test_fk_round_trip),
        cmocka_unit_test(test_fk_no_stable),
        cmocka_unit_test(test_fk_limit_same_as_fk),
        cmocka_unit_test(test_fk_warm),
        cmocka_unit_test(test_fk_warm_ro),
        cmocka_unit_test(test_pressure_slope_same_bits),
        cmocka_unit_test(test_pressure_near_same_bits),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
