/* The holding set's point at given pressures (hpi_load_hold_set_at_pressures: the forces,
 * pressures and inner radii the stable search starts from, planner/load_stable.c) against
 * the forward model: each carrying bladder's force there is the contact force hp_load_eval
 * gives at those pressures, and the point's pressures and radii are those of a point of the
 * set with those forces (hpi_load_hold_set_point, the scan's own path).
 *
 * The case this test was written for: a bladder whose pressure floor lies above its
 * touching pressure already carries at its lowest carrying pressure L (its least force Flo
 * is positive). A hold at exactly L is common (the scan's vertices put a bladder there);
 * its force is Flo, not 0, or the stable search's stiffness leaves a carrying bladder out.
 *
 * Layout: the load tests' default layout at stretch_max 1.6 under the cap law, carrying
 * 80 % of the head (as tests/scene/test_load_squeeze.c), at the nominal pose and at a 3 mm
 * lift; each carrying bladder's floor raised to 30 % of the way from touching to the top of
 * its carrying range, then each carrying bladder in turn put at its floor, the others at
 * 60 % of their ranges. */
#include "support/test_util.h"

#include "support/default_layout.h"
#include "support/load_fixture.h"
#include "headplan/hp_planner.h"
#include "planner/load_solve.h"

#include <string.h>

static void fixture(hp_layout *L, hp_load_spec *s)
{
    assert_int_equal(default_layout(L), 0);
    for (int k = 0; k < L->n; ++k) L->bladders[k].stretch_max = 1.6;
    assert_int_equal(hp_layout_prepare(L, NULL), HP_OK);
    hp_load_spec_default(&L->head, s);
    s->law = HP_LOAD_LAW_CAP;
    s->mass *= 0.8;
}

/* The forces hp_load_eval gives at pressures P: F[n] [N]. */
static void eval_forces(const hp_load_model *M, const double xi[6], const double *P, double *F)
{
    double Q[6];
    assert_int_equal(hp_load_eval(M, xi, P, Q, NULL, NULL, F, NULL), HP_OK);
}

static void test_forces_at_pressures(void **state)
{
    (void)state;
    hp_layout L;
    hp_load_spec spec;
    fixture(&L, &spec);
    hp_planner *p = NULL;
    assert_int_equal(load_create(&L, &spec, NULL, HP_TIE_LEAST_SQUEEZE, &p, NULL), HP_OK);
    const hp_load_model *M = hp_planner_load_model(p);
    const int n = L.n;
    double lo[HP_MAX_BLADDERS], hi[HP_MAX_BLADDERS], zero[HP_MAX_BLADDERS] = {0};
    assert_int_equal(hp_planner_pressure_bounds(p, lo, hi), HP_OK);
    static const double T[][6] = {{0, 0, 0, 0, 0, 0}, {0, 0, 3, 0, 0, 0}};
    int at_floor = 0;
    for (size_t t = 0; t < sizeof T / sizeof T[0]; ++t) {
        double xi[6];
        hp_pose_from_clinical(T[t], xi);
        hp_load_hold_set hs;
        assert_int_equal(hpi_load_hold_set_at(M, xi, lo, hi, zero, &hs), HP_LOAD_SOLVE_OK);
        assert_true(hs.m >= 2);
        /* Floors above touching: kept by pointer in the set, so a copy of lo. */
        double lo2[HP_MAX_BLADDERS];
        memcpy(lo2, lo, sizeof lo2);
        for (int j = 0; j < hs.m; ++j) {
            int k = hs.col[j];
            double pt = hs.L[k] > 0 ? hs.L[k] : 0.0;
            lo2[k] = pt + 0.3 * (hs.U[k] - pt);
        }
        hp_load_hold_set h2;
        assert_int_equal(hpi_load_hold_set_at(M, xi, lo2, hi, zero, &h2), HP_LOAD_SOLVE_OK);
        for (int jf = 0; jf < h2.m; ++jf) {
            int kf = h2.col[jf];
            assert_true(h2.Flo[kf] > 0.0); /* the floor lies above touching: it carries */
            double P[HP_MAX_BLADDERS], x[HP_MAX_BLADDERS], Pp[HP_MAX_BLADDERS], R[HP_MAX_BLADDERS];
            for (int k = 0; k < n; ++k) P[k] = lo2[k] > 0 ? lo2[k] : 0.0;
            for (int j = 0; j < h2.m; ++j) {
                int k = h2.col[j];
                P[k] = k == kf ? h2.L[k] : h2.L[k] + 0.6 * (h2.U[k] - h2.L[k]);
            }
            assert_int_equal(hpi_load_hold_set_at_pressures(&h2, P, x, Pp, R), 0);
            double F[HP_MAX_BLADDERS];
            eval_forces(M, xi, P, F);
            for (int j = 0; j < h2.m; ++j) {
                int k = h2.col[j];
                /* 1e-9 relative: the forward model's force at P and the set's at the
                 * inner radius its FK solve returns (to a few ulps) agree to rounding;
                 * 0 against Flo (~0.1 to 10 N here) fails by the whole force. */
                assert_true(x[k] > 0.0);
                assert_true(fabs(x[k] - F[k]) <= 1e-9 * F[k]);
                assert_true(Pp[k] == P[k]);
                assert_true(R[k] > 0.0);
            }
            /* The set's own point of those forces: the same pressures (tie_cost's solve of
             * each carrying bladder's pressure from its force, to its tolerance) and radii. */
            double e, Pq[HP_MAX_BLADDERS], Rq[HP_MAX_BLADDERS] = {0};
            assert_int_equal(hpi_load_hold_set_point(&h2, x, INFINITY, &e, Pq, Rq), 0);
            for (int j = 0; j < h2.m; ++j) {
                int k = h2.col[j];
                assert_true(fabs(Pq[k] - Pp[k]) <= 1e-6 * Pp[k]);
                assert_true(fabs(Rq[k] - R[k]) <= 1e-9 * R[k]);
            }
            assert_true(x[kf] == h2.Flo[kf]);
            assert_true(R[kf] == h2.ra[kf]);
            ++at_floor;
        }
    }
    assert_true(at_floor >= 4);
    hp_planner_destroy(p);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_forces_at_pressures),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
