/* Least squeeze is the least among the stable holds: at a reachable pose the load planner's
 * answer has the smallest sum of squared pressures among the pressures that hold the head
 * there inside every limit, stably (docs/load.md, "Stable holds"). The reference is a
 * multi-start: HOLD (realtime SQP and Ipopt) started from 24 seeded random pressures in each
 * bladder's range, each pick then made stable the way the planner makes its own
 * (hpi_load_stable_hold), each result kept only when it holds the pose (Q below 1e-9 N),
 * lies inside the bounds and inside the indentation range, and is stable with its smallest
 * stiffness eigenvalue at least the stable margin (K assembled here from hp_load_eval).
 * Before HOLD scanned the holding set's vertices, the planner's answer was beaten on 2 of
 * these 21 reached targets (by 0.96 % and 1.81 %: a bladder kept carrying where dropping it
 * and adding another was cheaper). HOLD's own scans run inside every reference start too,
 * so the reference is the planner's method from 24 other starts: it checks the starts, not
 * the scans' idea. The same on the catalogue's supine and tilted load scenes under the
 * fitted contact law (their own), where a reference result must also lie inside the law's
 * domain (as every answer does). */
#include "support/test_util.h"

#include "support/default_layout.h"
#include "common/units.h"
#include "headplan/hp_planner.h"
#include "support/load_fixture.h"
#include "support/load_stiffness.h"
#include "kinematics/linalg.h"
#include "kinematics/load_internal.h"
#include "planner/load_solve.h"
#include "planner/load_stable.h"
#include "kinematics/load_law_pick.h"
#include "headplan/hp_scene.h"

#include <stdlib.h>
#include <string.h>

static double lcg(unsigned long long *st)
{
    *st = *st * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(*st >> 11) / 9007199254740992.0;
}

static double squeeze(const double *P, int n)
{
    double s = 0.0;
    for (int k = 0; k < n; ++k) s += P[k] * P[k];
    return s;
}

/* Does P hold the head at xi inside [lo, hi] and the indentation range? */
static int valid(const hp_load_model *M, const double xi[6], const double *P, const double *lo,
                 const double *hi)
{
    double Q[6], ratio[HP_MAX_BLADDERS];
    if (hp_load_eval(M, xi, P, Q, NULL, NULL, NULL, NULL) != HP_OK ||
        hp_load_indentation(M, xi, P, ratio) != HP_OK)
        return 0;
    for (int i = 0; i < 6; ++i)
        if (!(fabs(Q[i]) * (i < 3 ? 1.0 : hpi_load_unit(i) / 1e-3) <= 1e-9)) return 0;
    for (int k = 0; k < M->layout.n; ++k)
        if (!(P[k] >= lo[k] && P[k] <= hi[k] && ratio[k] <= HP_LOAD_INDENT_MAX + 1e-9)) return 0;
    if (hpi_load_model_law(M) == HP_CLAW_LAW_FEM) {
        int k;
        hp_claw_domain g;
        if (hpi_load_fem_domain_at(M, xi, P, &k, &g) != HP_OK || k >= 0) return 0;
    }
    return 1;
}

/* The four layouts: the default one at stretch_max 1.6 carrying 80 % of the head along −Z,
 * and the same under gravity tilted 10° head-up (the cap law: these default-size bladders
 * carry the head under it only); then the catalogue's load_supine.yaml and load_tilted.yaml,
 * sized for the fitted law, with their own load (the fitted law). */
static void layout(int which, hp_layout *L, hp_load_spec *s)
{
    if (which >= 2) {
        hp_scene *sc = calloc(1, sizeof *sc);
        hp_diag d = {{0}};
        assert_non_null(sc);
        const char *path = which == 2 ? HP_SOURCE_DIR "/scenarios/load_supine.yaml"
                                      : HP_SOURCE_DIR "/scenarios/load_tilted.yaml";
        if (hp_scene_load(path, sc, &d) != HP_OK) {
            print_error("%s\n", d.text);
            fail();
        }
        *L = sc->layout;
        *s = sc->load;
        assert_int_equal(s->law, HP_LOAD_LAW_FEM);
        free(sc);
        return;
    }
    assert_int_equal(default_layout(L), 0);
    for (int k = 0; k < L->n; ++k) L->bladders[k].stretch_max = 1.6;
    assert_int_equal(hp_layout_prepare(L, NULL), HP_OK);
    hp_load_spec_default(&L->head, s);
    s->law = HP_LOAD_LAW_CAP; /* the default bladders carry the head under the cap law only */
    s->mass *= 0.8;
    if (which == 1) {
        double g = HP_GRAVITY, a = 10.0 * HP_PI / 180.0;
        s->gravity[0] = 0.0;
        s->gravity[1] = -g * sin(a);
        s->gravity[2] = -g * cos(a);
    }
}

static void test_least_squeeze_is_least(void **state)
{
    (void)state;
    /* Targets (mm, degrees): small corrections in every axis and some combinations. */
    static const double T[][6] = {
        {0, 0, 0, 0, 0, 0}, {1, 0, -0.5, 0.3, 0, -0.2}, {0, 0, 3, 0, 0, 0},   {0, 0, 6, 0, 0, 0},
        {2, 0, 0, 0, 0, 0}, {0, 2, 1, 0, 0, 0},         {0, -2, 1, 0, 0, 0},  {0, 0, 1, 2, 0, 0},
        {0, 0, 1, 0, 2, 0}, {0, 0, 1, 0, 0, 2},         {-3, 1, 2, 1, -1, 2}, {3, -1, 4, -1, 1, -2},
    };
    unsigned long long seed = 77ull;
    int reached = 0, reached_fem = 0, beaten = 0, compared = 0;
    double worst = 0.0;
    for (int which = 0; which < 4; ++which) {
        hp_layout L;
        hp_load_spec s;
        layout(which, &L, &s);
        hp_settings set;
        hp_settings_default(&set);
        set.max_time = 60.0; /* the outcome, not the clock, is asserted */
        set.level = HP_LEVEL_SURFACE;
        set.use_rate_limits = 0;
        for (size_t t = 0; t < sizeof T / sizeof T[0]; ++t) {
            hp_planner *p = NULL;
            assert_int_equal(load_create(&L, &s, &set, HP_TIE_LEAST_SQUEEZE, &p, NULL), HP_OK);
            const hp_load_model *M = hp_planner_load_model(p);
            const int n = L.n;
            double xi[6], lo[HP_MAX_BLADDERS], hi[HP_MAX_BLADDERS], P[HP_MAX_BLADDERS];
            hp_pose_from_clinical(T[t], xi);
            hp_result r;
            assert_int_equal(load_plan(p, xi, &r, NULL), HP_OK);
            assert_int_equal(hp_planner_pressure_bounds(p, lo, hi), HP_OK);
            if (r.status != HP_STATUS_REACHED) {
                hp_planner_destroy(p);
                continue;
            }
            ++reached;
            reached_fem += which >= 2;
            for (int k = 0; k < n; ++k) P[k] = r.bladders[k].pressure;
            assert_true(valid(M, xi, P, lo, hi));
            assert_true(test_load_smallest_stiffness(M, xi, P) >
                        0.0); /* a REACHED hold is stable */
            double mine = squeeze(P, n), best = INFINITY, zero[HP_MAX_BLADDERS] = {0};
            for (int start = 0; start < 24; ++start) {
                double P0[HP_MAX_BLADDERS], Pr[HP_MAX_BLADDERS], F[HP_MAX_BLADDERS];
                for (int k = 0; k < n; ++k)
                    P0[k] = fmax(lo[k], 0.0) + lcg(&seed) * (hi[k] - fmax(lo[k], 0.0));
                hpi_load_solve_status st = start % 2 ? hpi_load_hold_with(hpi_load_hold_ipopt, M,
                                                                          xi, lo, hi, zero, P0, 200,
                                                                          0, Pr, F, NULL, NULL)
                                                     : hpi_load_hold(M, xi, lo, hi, zero, P0, 200,
                                                                     Pr, F, NULL);
                if (st == HP_LOAD_SOLVE_OK)
                    st = hpi_load_stable_hold(M, xi, lo, hi, zero, Pr, F, NULL);
                if (st == HP_LOAD_SOLVE_OK && valid(M, xi, Pr, lo, hi) &&
                    test_load_smallest_stiffness(M, xi, Pr) >= HP_LOAD_STABLE_MARGIN)
                    best = fmin(best, squeeze(Pr, n));
            }
            compared += isfinite(best);
            /* 1e-9 relative: the SQP stops at 1e-9 kPa steps, ΣP² ~ 1e8 Pa². */
            double excess = (mine - best) / best;
            if (excess > 1e-9) {
                ++beaten;
                print_message("layout %d, target %zu: sum P^2 %.9g, multi-start %.9g (+%.3g %%)\n",
                              which, t, mine, best, 100.0 * excess);
            }
            worst = fmax(worst, excess);
            hp_planner_destroy(p);
        }
    }
    print_message("reached %d (%d under the fitted law), compared with a stable reference %d, "
                  "beaten by the multi-start %d, worst excess %.3g\n",
                  reached, reached_fem, compared, beaten, worst);
    assert_int_equal(compared, reached); /* every reached target has a stable reference */
    assert_true(reached - reached_fem >= 12);
    /* 3 measured: the fitted-law scenes hold few of these targets (most are CLOSEST there) */
    assert_true(reached_fem >= 3);
    assert_int_equal(beaten, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_least_squeeze_is_least),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
