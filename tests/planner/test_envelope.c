/* One home for a bladder's safe envelope (hpi_bladder_envelope, planner/problem_setup.h): the
 * pressure, stretch, hoop-stress and limit-point limits as inner-radius bounds that hold in
 * floating point, and the pressures there.
 * - Its bounds hold: IK(ri_lo) >= p_min, IK(ri_hi) <= p_max, ri_lo >= stretch_min·Ri and
 *   ri_hi <= stretch_max·Ri in exact arithmetic (hpi_prod_up/down), the hoop stress at ri_hi
 *   within stress_max (1e-9 relative: the stress radius's bisection side), the flags naming
 *   what set each bound.
 * - The kinematic planner's static bounds are its bounds, bit for bit.
 * - The load planner's pressure bounds (hp_planner_pressure_bounds at the load level) are its pressures, bit for
 *   bit: before, the load planner computed its own with the stable-branch cap hard-coded
 *   and without the exact-bound nudges (p_min and p_max themselves where the kinematic
 *   planner's bound pressures lie a few ulps inside them).
 * On the default layout, the soft layout whose limit point caps it, and the default layout
 * with a hoop-stress limit below its stretch cap's stress. */
#include "support/test_util.h"
#include "support/layout_fixture.h"
#include "planner/problem_setup.h"
#include "common/exact_prod.h"
#include "support/load_fixture.h"

static void check_layout(const hp_layout *L, const char *what, unsigned want_hi_flag)
{
    hp_static_bounds sb;
    assert_int_equal(hpi_setup_static_bounds(L, &sb, NULL), HP_OK);
    unsigned seen_hi = 0;
    for (int k = 0; k < L->n; ++k) {
        const hp_bladder *B = &L->bladders[k];
        hp_envelope e;
        assert_int_equal(hpi_bladder_envelope(B, &e, NULL), HP_OK);
        double plo, phi;
        assert_int_equal(hp_iab_ik(&B->iab, e.ri_lo, &plo), HP_OK);
        assert_int_equal(hp_iab_ik(&B->iab, e.ri_hi, &phi), HP_OK);
        assert_true(plo >= B->p_min && phi <= B->p_max);
        assert_true(e.ri_lo >= hpi_prod_up(B->stretch_min, B->iab.Ri));
        assert_true(e.ri_hi <= hpi_prod_down(B->stretch_max, B->iab.Ri));
        assert_true(e.p_lo >= B->p_min && e.p_hi <= B->p_max && e.p_lo < e.p_hi);
        if (B->stress_max > 0 && isfinite(B->stress_max)) {
            double h;
            assert_int_equal(hp_iab_hoop_stress_inner(&B->iab, e.ri_hi, &h), HP_OK);
            assert_true(h <= B->stress_max * (1 + 1e-9));
        }
        seen_hi |= e.hi_flags;
        /* The kinematic planner's bounds are the envelope's. */
        assert_true(memcmp(&sb.ri_lo[k], &e.ri_lo, sizeof e.ri_lo) == 0);
        assert_true(memcmp(&sb.ri_hi[k], &e.ri_hi, sizeof e.ri_hi) == 0);
        assert_true(memcmp(&sb.p_lo[k], &e.p_lo, sizeof e.p_lo) == 0);
        assert_true(memcmp(&sb.p_hi[k], &e.p_hi, sizeof e.p_hi) == 0);
        assert_int_equal(sb.lo_flags[k], e.lo_flags);
        assert_int_equal(sb.hi_flags[k], e.hi_flags);
    }
    assert_true(seen_hi & want_hi_flag);

    /* The load planner's pressure bounds are the envelope's pressures. */
    hp_load_spec spec;
    hp_load_spec_default(&L->head, &spec);
    spec.law = HP_LOAD_LAW_CAP; /* the default bladders carry the head under the cap law only */
    spec.mass *= 0.2;           /* light enough for every layout here to carry */
    hp_planner *lp = NULL;
    hp_diag d = {{0}};
    hp_error err = load_create(L, &spec, NULL, HP_TIE_LEAST_SQUEEZE, &lp, &d);
    if (err != HP_OK) print_error("%s: load planner: %s\n", what, d.text);
    assert_int_equal(err, HP_OK);
    double lo[HP_MAX_BLADDERS], hi[HP_MAX_BLADDERS];
    assert_int_equal(hp_planner_pressure_bounds(lp, lo, hi), HP_OK);
    for (int k = 0; k < L->n; ++k)
        if (memcmp(&lo[k], &sb.p_lo[k], sizeof lo[k]) ||
            memcmp(&hi[k], &sb.p_hi[k], sizeof hi[k])) {
            print_error("%s bladder %d: load bounds [%.17g, %.17g], envelope [%.17g, %.17g]\n",
                        what, k, lo[k], hi[k], sb.p_lo[k], sb.p_hi[k]);
            fail();
        }
    hp_planner_destroy(lp);
}

static void test_envelope_everywhere(void **state)
{
    (void)state;
    hp_layout L;
    assert_int_equal(lf_layout(&L), HP_OK);
    check_layout(&L, "default", HP_BIND_STRETCH_MAX);

    hp_iab_limit lim;
    assert_int_equal(lf_soft_layout(&L, 2.0, &lim), HP_OK);
    check_layout(&L, "soft", HP_BIND_LIMIT_POINT);

    assert_int_equal(lf_layout(&L), HP_OK);
    double s_cap;
    assert_int_equal(
        hp_iab_hoop_stress_inner(&L.bladders[0].iab, 1.2 * L.bladders[0].iab.Ri, &s_cap), HP_OK);
    for (int k = 0; k < L.n; ++k) L.bladders[k].stress_max = s_cap;
    assert_int_equal(hp_layout_prepare(&L, NULL), HP_OK);
    check_layout(&L, "stress", HP_BIND_STRESS_MAX);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_envelope_everywhere),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
