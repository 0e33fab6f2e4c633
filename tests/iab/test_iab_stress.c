/* Wall stress as a limit: the inner hoop stress in closed form against the paper's stress
 * components written out here, its monotonicity on the stable branch (which is what makes
 * a stress bound a radius bound), and the radius the bound maps to. */
#include "support/test_util.h"

#include "headplan/hp_iab.h"

/* sigma_tt(ri) = −P + C1(l² − l⁻⁴) − C2(l⁻² − l⁴), l = ri/Ri, from the stress difference
 * and sigma_rr(ri) = −P. */
static double hoop_by_hand(const hp_iab *b, double ri)
{
    double P, l = ri / b->Ri;
    assert_int_equal(hp_iab_ik(b, ri, &P), HP_OK);
    return -P + b->C1 * (l * l - 1.0 / (l * l * l * l)) - b->C2 * (1.0 / (l * l) - l * l * l * l);
}

static const hp_iab MATS[3] = {
    {0.027, 0.030, 1.1e4, 2.2e4}, /* the paper's */
    {0.027, 0.030, 1.1e4, 0.0},   /* neo-Hookean: a limit point near l = 1.43 */
    {0.020, 0.030, 1.1e4, 2.2e4}, /* thick wall */
};

/* On [1, cap] (cap = 3 or 0.999 of the limit point) the hoop stress rises strictly at
 * every one of 4000 samples, and matches the hand formula to 1e-9 relative (both are
 * closed forms; the library's removes the cancellation near l = 1, so near 1 the
 * comparison is absolute, 1e-9 of C1). */
static void test_monotone_and_closed_form(void **state)
{
    (void)state;
    for (int m = 0; m < 3; ++m) {
        const hp_iab *b = &MATS[m];
        hp_iab_limit lp;
        assert_int_equal(hp_iab_limit_point(b, &lp), HP_OK);
        double cap = lp.exists ? 0.999 * lp.lambda_i : 3.0, prev = -INFINITY;
        for (int i = 0; i <= 4000; ++i) {
            double l = 1.0 + (cap - 1.0) * i / 4000.0, s;
            assert_int_equal(hp_iab_hoop_stress_inner(b, l * b->Ri, &s), HP_OK);
            hp_assert_close(s, hoop_by_hand(b, l * b->Ri), 1e-9, 1e-9 * b->C1);
            if (i > 0) assert_true(s > prev);
            prev = s;
        }
    }
}

/* The stress bound maps to the radius where the stress equals it (to 1e-12 relative), and
 * to the cap itself when the cap's stress is below the bound. */
static void test_stress_radius(void **state)
{
    (void)state;
    const hp_iab *b = &MATS[0];
    double cap = 1.6 * b->Ri, s_cap, ri, s;
    assert_int_equal(hp_iab_hoop_stress_inner(b, cap, &s_cap), HP_OK);
    assert_int_equal(hp_iab_stress_radius(b, 0.5 * s_cap, cap, &ri), HP_OK);
    assert_true(ri > b->Ri && ri < cap);
    assert_int_equal(hp_iab_hoop_stress_inner(b, ri, &s), HP_OK);
    hp_assert_close(s, 0.5 * s_cap, 1e-12, 0.0);
    assert_true(s <= 0.5 * s_cap);
    assert_int_equal(hp_iab_stress_radius(b, 2.0 * s_cap, cap, &ri), HP_OK);
    assert_true(ri == cap);
    assert_int_equal(hp_iab_stress_radius(b, NAN, cap, &ri), HP_ERR_INVALID);
    assert_int_equal(hp_iab_stress_radius(b, -1.0, cap, &ri), HP_ERR_INVALID);
    assert_int_equal(hp_iab_stress_radius(b, 1e3, 0.5 * b->Ri, &ri), HP_ERR_INVALID);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_monotone_and_closed_form),
        cmocka_unit_test(test_stress_radius),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
