/* Every domain and argument error of the bladder API: a specific code, a message naming the
 * field (hp_iab_validate), outputs untouched, never NaN returned as a result. Also the
 * material-convention strings and conversion. */
#include "support/test_util.h"
#include "headplan/hp_iab.h"
#include "iab/iab_internal.h"

#include <string.h>

static const hp_iab good = {0.027, 0.03, 1.1e4, 2.2e4};

static void expect_invalid(hp_iab b, hp_error code, const char *field)
{
    hp_diag d;
    memset(&d, 0, sizeof d);
    assert_int_equal(hp_iab_validate(&b, &d), code);
    if (!strstr(d.text, field)) {
        print_error("message '%s' does not name '%s'\n", d.text, field);
        fail();
    }
    /* every entry point refuses the same bladder, leaving outputs untouched */
    double out = 42.0, o2 = 43.0, o3 = 44.0;
    int ev = 7;
    hp_iab_limit lp = {5, 1, 2, 3};
    assert_int_equal(hp_iab_ik(&b, 0.03, &out), code);
    assert_int_equal(hp_iab_ik_derivs(&b, 0.03, &out, &o2, &o3), code);
    assert_int_equal(hp_iab_ro(&b, 0.03, &out), code);
    assert_int_equal(hp_iab_ri(&b, 0.03, &out), code);
    assert_int_equal(hp_iab_fk(&b, 100.0, &out), code);
    assert_int_equal(hp_iab_ik_gauss(&b, 0.03, HP_QUAD_CURRENT, 8, &out), code);
    assert_int_equal(hp_iab_ik_adaptive(&b, 0.03, HP_QUAD_REFERENCE, 1e-8, &out, &o2, &ev), code);
    assert_int_equal(hp_iab_wall_stress(&b, 0.03, 0.03, &out, &o2), code);
    assert_int_equal(hp_iab_limit_point(&b, &lp), code);
    assert_int_equal(hpi_iab_fk_limit_warm_ro(&b, &lp, 100.0, 0.03, &out, &o2), code);
    assert_true(out == 42.0 && o2 == 43.0 && o3 == 44.0 && ev == 7 && lp.exists == 5);
}

static void test_bladder_errors(void **state)
{
    (void)state;
    hp_iab b;
    assert_int_equal(hp_iab_validate(&good, NULL), HP_OK);
    b = good;
    b.Ri = NAN;
    expect_invalid(b, HP_ERR_INVALID, "Ri");
    b = good;
    b.Ri = INFINITY;
    expect_invalid(b, HP_ERR_INVALID, "Ri");
    b = good;
    b.Ro = NAN;
    expect_invalid(b, HP_ERR_INVALID, "Ro");
    b = good;
    b.Ro = -INFINITY;
    expect_invalid(b, HP_ERR_INVALID, "Ro");
    b = good;
    b.C1 = NAN;
    expect_invalid(b, HP_ERR_INVALID, "C1");
    b = good;
    b.C2 = INFINITY;
    expect_invalid(b, HP_ERR_INVALID, "C2");
    b = good;
    b.Ri = 0;
    expect_invalid(b, HP_ERR_INVALID, "Ri");
    b = good;
    b.Ri = -0.027;
    expect_invalid(b, HP_ERR_INVALID, "Ri");
    b = good;
    b.Ro = b.Ri;
    expect_invalid(b, HP_ERR_DOMAIN, "Ro");
    b = good;
    b.Ro = 0.02;
    expect_invalid(b, HP_ERR_DOMAIN, "Ro");
    b = good;
    b.Ri = 1e-12;
    expect_invalid(b, HP_ERR_DOMAIN, "Ri");
    b = good;
    b.C1 = 0;
    expect_invalid(b, HP_ERR_INVALID, "C1");
    b = good;
    b.C1 = -1;
    expect_invalid(b, HP_ERR_INVALID, "C1");
    b = good;
    b.C2 = -1e-300;
    expect_invalid(b, HP_ERR_INVALID, "C2");
    b = good;
    b.C2 = 0;
    assert_int_equal(hp_iab_validate(&b, NULL), HP_OK);
    hp_diag d;
    assert_int_equal(hp_iab_validate(NULL, &d), HP_ERR_NULL);
}

static void test_radius_errors(void **state)
{
    (void)state;
    double out = 42.0, o2 = 43.0;
    const double bad[] = {0.0, -0.01, -0.0};
    for (int i = 0; i < 3; ++i) {
        assert_int_equal(hp_iab_ik(&good, bad[i], &out), HP_ERR_DOMAIN);
        assert_int_equal(hp_iab_ro(&good, bad[i], &out), HP_ERR_DOMAIN);
        assert_int_equal(hp_iab_ri(&good, bad[i], &out), HP_ERR_DOMAIN);
        assert_int_equal(hp_iab_ik_gauss(&good, bad[i], HP_QUAD_REFERENCE, 8, &out), HP_ERR_DOMAIN);
    }
    assert_int_equal(hp_iab_ik(&good, NAN, &out), HP_ERR_INVALID);
    assert_int_equal(hp_iab_ik(&good, INFINITY, &out), HP_ERR_INVALID);
    assert_int_equal(hp_iab_ro(&good, NAN, &out), HP_ERR_INVALID);
    assert_int_equal(hp_iab_ik_derivs(&good, -INFINITY, &out, &o2, NULL), HP_ERR_INVALID);
    /* collapsed cavity: ro³ <= Ro³ − Ri³ */
    double ro_min = cbrt(0.03 * 0.03 * 0.03 - 0.027 * 0.027 * 0.027);
    assert_int_equal(hp_iab_ri(&good, ro_min * 0.999, &out), HP_ERR_DOMAIN);
    assert_int_equal(hp_iab_ri(&good, 0.001, &out), HP_ERR_DOMAIN);
    /* a radius so small that P overflows: an error, not −inf */
    assert_int_equal(hp_iab_ik(&good, 1e-290, &out), HP_ERR_DOMAIN);
    assert_int_equal(hp_iab_ik(&good, 1e290, &out), HP_ERR_DOMAIN);
    assert_true(out == 42.0 && o2 == 43.0);
    /* tiny but representable: finite and very negative */
    assert_int_equal(hp_iab_ik(&good, 0.027 * 1e-6, &out), HP_OK);
    assert_true(isfinite(out) && out < -1e20);
    /* NULL outputs */
    assert_int_equal(hp_iab_ik(&good, 0.03, NULL), HP_ERR_NULL);
    assert_int_equal(hp_iab_ik_derivs(&good, 0.03, NULL, &o2, NULL), HP_ERR_NULL);
    assert_int_equal(hp_iab_ro(&good, 0.03, NULL), HP_ERR_NULL);
    assert_int_equal(hp_iab_ri(&good, 0.03, NULL), HP_ERR_NULL);
    assert_int_equal(hp_iab_limit_point(&good, NULL), HP_ERR_NULL);
    assert_int_equal(hp_iab_wall_stress(&good, 0.03, 0.03, NULL, &o2), HP_ERR_NULL);
}

static void test_conventions(void **state)
{
    (void)state;
    hp_material_convention c = HP_MATERIAL_FE;
    assert_string_equal(hp_material_convention_name(HP_MATERIAL_PAPER), "paper");
    assert_string_equal(hp_material_convention_name(HP_MATERIAL_FE), "fe");
    assert_string_equal(hp_material_convention_name((hp_material_convention)9), "unknown");
    assert_int_equal(hp_material_convention_parse("paper", &c), HP_OK);
    assert_int_equal(c, HP_MATERIAL_PAPER);
    assert_int_equal(hp_material_convention_parse("fe", &c), HP_OK);
    assert_int_equal(c, HP_MATERIAL_FE);
    assert_int_equal(hp_material_convention_parse("FE", &c), HP_ERR_INVALID);
    assert_int_equal(hp_material_convention_parse("", &c), HP_ERR_INVALID);
    assert_int_equal(hp_material_convention_parse("paper ", &c), HP_ERR_INVALID);
    assert_int_equal(hp_material_convention_parse(NULL, &c), HP_ERR_NULL);
    for (int i = 0; i < 2; ++i) {
        hp_material_convention cc = (hp_material_convention)i, back;
        assert_int_equal(hp_material_convention_parse(hp_material_convention_name(cc), &back),
                         HP_OK);
        assert_int_equal(back, cc);
    }
    double C1 = 0, C2 = 0;
    assert_int_equal(hp_iab_moduli_to_paper(HP_MATERIAL_PAPER, 1.1e4, 2.2e4, &C1, &C2), HP_OK);
    assert_true(C1 == 1.1e4 && C2 == 2.2e4);
    /* W = C10(I1−3) + C01(I2−3) = ½(2C10)(I1−3) + ½(2C01)(I2−3) */
    assert_int_equal(hp_iab_moduli_to_paper(HP_MATERIAL_FE, 5.5e3, 1.1e4, &C1, &C2), HP_OK);
    assert_true(C1 == 1.1e4 && C2 == 2.2e4);
    assert_int_equal(hp_iab_moduli_to_paper(HP_MATERIAL_FE, NAN, 1, &C1, &C2), HP_ERR_INVALID);
    assert_int_equal(hp_iab_moduli_to_paper(HP_MATERIAL_FE, 1e308, 1, &C1, &C2), HP_ERR_INVALID);
    assert_int_equal(hp_iab_moduli_to_paper((hp_material_convention)5, 1, 1, &C1, &C2),
                     HP_ERR_INVALID);
    assert_int_equal(hp_iab_moduli_to_paper(HP_MATERIAL_PAPER, 1, 1, NULL, &C2), HP_ERR_NULL);
    assert_true(C1 == 1.1e4 && C2 == 2.2e4);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_bladder_errors),
        cmocka_unit_test(test_radius_errors),
        cmocka_unit_test(test_conventions),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
