/* Stretch limits hold to the last bit on every backend: an answer's inner radius ri is
 * inside [stretch_min · Ri, stretch_max · Ri] with the products taken EXACTLY (in
 * __float128, whose 113-bit significand holds the 106-bit product of two doubles without
 * rounding), not only after the division ri / Ri has been rounded. Rounded, stretch_min · Ri
 * lies below the exact product for about four pairs in ten, and a bound derived from it
 * returned a radius that exact arithmetic puts below the limit.
 *
 * Each plan gives every bladder its own seeded random (Ri, stretch_min, stretch_max), with
 * pressure limits wide enough that the stretch limits are the ones that bind, and asks for a
 * correction far beyond reach along ±Z, so that the base (or the side) bladders end on a
 * stretch limit. Every returned radius is compared in exact arithmetic, whatever the status,
 * and at least some answers must sit on the limit (else the test would show nothing).
 * The same at the load level (every backend that plans it, carrying 20 % of the head's
 * weight): its returned radii come from its own bounds, which must be as exact. */
#include "support/test_util.h"
#include "support/layout_fixture.h"
#include "support/load_fixture.h"

#include "common/exact_prod.h"

#include <quadmath.h>

static const hp_backend backends[4] = {HP_BACKEND_REALTIME, HP_BACKEND_IPOPT,
                                       HP_BACKEND_NLOPT_SLSQP, HP_BACKEND_NLOPT_COBYLA};

/* 1 when lo_factor · Ri <= ri <= hi_factor · Ri holds in exact arithmetic. */
static int inside_exactly(double ri, double Ri, double smin, double smax)
{
    __float128 r = ri, lo = (__float128)smin * Ri, hi = (__float128)smax * Ri;
    return r >= lo && r <= hi;
}

/* A pair where the rounded product differs from the exact one in the direction that
 * matters (below for the lower bound, above for the upper): the cases the test is for. */
static int rounds_outward(double Ri, double smin, double smax)
{
    double lo = smin * Ri, hi = smax * Ri;
    return (__float128)lo < (__float128)smin * Ri || (__float128)hi > (__float128)smax * Ri;
}

/* The campaign on every backend at one level (HP_LEVEL_SURFACE or HP_LEVEL_LOAD), with
 * plans_per_backend plans each. */
static void stretch_limits_exact_at(hp_level level, int plans_per_backend)
{
    uint64_t seed = 20261204;
    for (int bi = 0; bi < 4; ++bi) {
        if (level == HP_LEVEL_LOAD && backends[bi] == HP_BACKEND_NLOPT_COBYLA) continue;
        int on_limit = 0, outward = 0, checked = 0;
        for (int t = 0; t < plans_per_backend; ++t) {
            hp_layout L;
            assert_int_equal(lf_layout(&L), HP_OK);
            for (int k = 0; k < L.n; ++k) {
                hp_bladder *B = &L.bladders[k];
                /* Ri in [26, 28] mm (Ro 30 mm); stretch limits well around the nominal
                 * stretch (~1.0): [0.85, 0.95] and [1.05, 1.2]. */
                B->iab.Ri = 0.027 + 0.001 * lf_uniform(&seed);
                B->stretch_min = 0.9 + 0.05 * lf_uniform(&seed);
                B->stretch_max = 1.125 + 0.075 * lf_uniform(&seed);
                B->p_min = -60e3;
                B->p_max = 60e3;
                outward += rounds_outward(B->iab.Ri, B->stretch_min, B->stretch_max);
            }
            hp_diag d = {{0}};
            if (hp_layout_prepare(&L, &d) != HP_OK) print_error("prepare: %s\n", d.text);
            hp_settings s;
            hp_settings_default(&s);
            s.backend = backends[bi];
            s.level = HP_LEVEL_SURFACE;
            s.max_time = 60.0; /* outcomes must not depend on the machine's speed */
            hp_planner *p = NULL;
            hp_error e;
            if (level == HP_LEVEL_LOAD) {
                hp_load_spec spec;
                hp_load_spec_default(&L.head, &spec);
                spec.law =
                    HP_LOAD_LAW_CAP; /* the default bladders carry the head under the cap law only */
                spec.mass *= LOAD_LF_FRACTION;
                e = load_create(&L, &spec, &s, HP_TIE_LEAST_SQUEEZE, &p, &d);
            } else {
                e = hp_planner_create(&L, &s, &p, &d);
            }
            if (e != HP_OK) print_error("create: %s\n", d.text);
            assert_non_null(p);
            /* Down into the base bladders (their stretch_min), or up (their stretch_max),
             * with a little of every other axis so the answers differ. */
            double mm_deg[6], xi[6];
            for (int i = 0; i < 6; ++i) mm_deg[i] = 0.5 * lf_uniform(&seed);
            mm_deg[2] = t % 2 ? 12.0 : -12.0;
            lf_pose(mm_deg, xi);
            hp_result r;
            assert_int_equal(hp_plan(p, xi, &r), HP_OK);
            for (int k = 0; k < r.n; ++k) {
                const hp_bladder *B = &L.bladders[k];
                const hp_bladder_result *b = &r.bladders[k];
                if (!inside_exactly(b->ri, B->iab.Ri, B->stretch_min, B->stretch_max))
                    fail_msg("%s, plan %d, %s (%s): ri %a outside [%a, %a] * Ri %a exactly",
                             hp_backend_name(backends[bi]), t, B->name, hp_status_name(r.status),
                             b->ri, B->stretch_min, B->stretch_max, B->iab.Ri);
                on_limit += b->binding & (HP_BIND_STRETCH_MIN | HP_BIND_STRETCH_MAX) ? 1 : 0;
                ++checked;
            }
            hp_planner_destroy(p);
        }
        printf("%s, %s level: %d radii checked, %d on a stretch limit; %d of %d bladders round "
               "outward\n",
               hp_backend_name(backends[bi]), hp_level_name(level), checked, on_limit, outward,
               plans_per_backend * 8);
        /* The test must exercise the limit: answers on it, from pairs that round outward. */
        assert_true(on_limit >= plans_per_backend);
        assert_true(outward > 0);
    }
}

static void stretch_limits_exact_every_backend(void **st)
{
    (void)st;
    stretch_limits_exact_at(HP_LEVEL_SURFACE, HP_TEST_SMALL(64, 16));
}

static void stretch_limits_exact_load_level(void **st)
{
    (void)st;
    /* Fewer plans: a load plan costs several contact plans (the held-pose searches). */
    stretch_limits_exact_at(HP_LEVEL_LOAD, HP_TEST_SMALL(16, 6));
}

/* The directed products themselves, against __float128 (exact for a product of two
 * doubles): hpi_prod_up is the smallest double at or above the product, hpi_prod_down the
 * largest at or below, over seeded random pairs of the stretch and radius ranges and of
 * wider ones. */
static void directed_products_exact(void **st)
{
    (void)st;
    uint64_t seed = 7;
    int up_moved = 0, down_moved = 0;
    const int n = 200000;
    for (int t = 0; t < n; ++t) {
        double a = t % 2 ? 0.5 + 1.5 * (lf_uniform(&seed) + 1.0) : ldexp(lf_uniform(&seed), 40);
        double b = t % 2 ? 0.02 + 0.01 * lf_uniform(&seed) : ldexp(lf_uniform(&seed), -40);
        __float128 x = (__float128)a * b;
        double u = hpi_prod_up(a, b), dn = hpi_prod_down(a, b);
        if (!((__float128)u >= x && (__float128)nextafter(u, -INFINITY) < x))
            fail_msg("hpi_prod_up(%a, %a) = %a", a, b, u);
        if (!((__float128)dn <= x && (__float128)nextafter(dn, INFINITY) > x))
            fail_msg("hpi_prod_down(%a, %a) = %a", a, b, dn);
        up_moved += u != a * b;
        down_moved += dn != a * b;
    }
    /* Both directions are exercised: the rounded product is often on the wrong side. */
    printf("%d of %d rounded products below the exact one, %d above\n", up_moved, n, down_moved);
    assert_true(up_moved > n / 10 && down_moved > n / 10);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(directed_products_exact),
        cmocka_unit_test(stretch_limits_exact_every_backend),
        cmocka_unit_test(stretch_limits_exact_load_level),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
