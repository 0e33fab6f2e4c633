/* The holding set's point at given pressures (hpi_load_hold_set_at_pressures: the forces,
 * pressures and inner radii the stable search starts from, planner/load_stable.c) against
 * the forward model: each carrying bladder's force there is the contact force hp_load_eval
 * gives at those pressures, its inner radius the bladder's FK of its pressure, and the
 * point's pressures and radii are those of a point of the set with those forces
 * (hpi_load_hold_set_point, the scan's own path).
 *
 * The case this test was written for: a bladder whose pressure floor lies above its
 * touching pressure already carries at its lowest carrying pressure L (its least force Flo
 * is positive). A hold at exactly L is common (a least-squeeze hold puts a bladder on its
 * floor wherever it can); its force is Flo, not 0, or the stable search's stiffness leaves
 * a carrying bladder out. The second test checks that consequence: a stable hold with
 * bladders on their floors is kept without a search, and the smallest stiffness eigenvalue
 * the stable search reports is the tests' own (tests/support/load_stiffness.h, from
 * hp_load_eval's Jacobian).
 *
 * Layout: the load tests' default layout at stretch_max 1.6 under the cap law, carrying
 * 80 % of the head (as tests/scene/test_load_squeeze.c); each carrying bladder's floor
 * raised to 30 % of the way from the bottom of its carrying range L (touching, here) to its
 * top. The first test at the nominal pose and a 3 mm lift, the second at nine small
 * corrections. */
#include "support/test_util.h"

#include "support/default_layout.h"
#include "support/load_fixture.h"
#include "support/load_stiffness.h"
#include "headplan/hp_planner.h"
#include "planner/load_solve.h"
#include "planner/load_stable.h"

#include <string.h>

/* The fixture's planner (p, to destroy), its load model and pressure bounds. */
static const hp_load_model *fixture(hp_layout *L, hp_planner **p, double *lo, double *hi)
{
    hp_load_spec s;
    assert_int_equal(default_layout(L), 0);
    for (int k = 0; k < L->n; ++k) L->bladders[k].stretch_max = 1.6;
    assert_int_equal(hp_layout_prepare(L, NULL), HP_OK);
    hp_load_spec_default(&L->head, &s);
    s.law = HP_LOAD_LAW_CAP;
    s.mass *= 0.8;
    assert_int_equal(load_create(L, &s, NULL, HP_TIE_LEAST_SQUEEZE, p, NULL), HP_OK);
    assert_int_equal(hp_planner_pressure_bounds(*p, lo, hi), HP_OK);
    return hp_planner_load_model(*p);
}

/* The forces hp_load_eval gives at pressures P: F[n] [N]. */
static void eval_forces(const hp_load_model *M, const double xi[6], const double *P, double *F)
{
    double Q[6];
    assert_int_equal(hp_load_eval(M, xi, P, Q, NULL, NULL, F, NULL), HP_OK);
}

/* The set at the clinical correction c (xi gets its pose) with each carrying bladder's floor
 * raised 30 % of the way from L (the bottom of its carrying pressures under lo) to U: lo2
 * (kept by pointer in h2) and h2. */
static void raised_set(const hp_load_model *M, const double c[6], const double *lo,
                       const double *hi, const double *zero, double xi[6], double *lo2,
                       hp_load_hold_set *h2)
{
    hp_load_hold_set hs;
    hp_pose_from_clinical(c, xi);
    assert_int_equal(hpi_load_hold_set_at(M, xi, lo, hi, zero, &hs), HP_LOAD_SOLVE_OK);
    assert_true(hs.m >= 2);
    memcpy(lo2, lo, (size_t)hs.n * sizeof *lo2);
    for (int j = 0; j < hs.m; ++j) {
        int k = hs.col[j];
        lo2[k] = hs.L[k] + 0.3 * (hs.U[k] - hs.L[k]);
    }
    assert_int_equal(hpi_load_hold_set_at(M, xi, lo2, hi, zero, h2), HP_LOAD_SOLVE_OK);
}

static void test_forces_at_pressures(void **state)
{
    (void)state;
    hp_layout L;
    hp_planner *p = NULL;
    double lo[HP_MAX_BLADDERS], hi[HP_MAX_BLADDERS], zero[HP_MAX_BLADDERS] = {0};
    const hp_load_model *M = fixture(&L, &p, lo, hi);
    const int n = L.n;
    static const double T[][6] = {{0, 0, 0, 0, 0, 0}, {0, 0, 3, 0, 0, 0}};
    int at_floor = 0;
    for (size_t t = 0; t < sizeof T / sizeof T[0]; ++t) {
        double xi[6], lo2[HP_MAX_BLADDERS];
        hp_load_hold_set h2;
        raised_set(M, T[t], lo, hi, zero, xi, lo2, &h2);
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
                /* The forward model's force at P and the set's at the inner radius its FK
                 * solve returns: measured equal, bit for bit (the same FK and law); 1e-13
                 * relative leaves room for an FK root a few ulps apart (the force's
                 * relative slope in ri is O(10-100)). 0 against Flo (~0.1 to 10 N here)
                 * fails by the whole force. */
                assert_true(x[k] > 0.0);
                assert_true(fabs(x[k] - F[k]) <= 1e-13 * F[k]);
                assert_true(Pp[k] == P[k]);
                /* The radius the FK gives for P: measured equal; 1e-14 relative is a few
                 * ulps, for a root found from another start. */
                double ri;
                assert_int_equal(hp_iab_fk(&L.bladders[k].iab, P[k], &ri), HP_OK);
                assert_true(fabs(R[k] - ri) <= 1e-14 * ri);
            }
            /* The set's own point of those forces: the same pressures and radii. Its
             * pressure solve from a force stops after a Newton step of at most 1e-8 of the
             * radius, which leaves an error of the order of that step squared (1e-16 of the
             * radius, O(1e-14) of the pressure): measured 1.5e-15 (pressures) and 2.1e-16
             * (radii); 1e-12 and 1e-13 relative are far below any force error (0 against
             * Flo moves the floor bladder's pressure by its whole floor). */
            double e, Pq[HP_MAX_BLADDERS], Rq[HP_MAX_BLADDERS] = {0};
            assert_int_equal(hpi_load_hold_set_point(&h2, x, INFINITY, &e, Pq, Rq), 0);
            for (int j = 0; j < h2.m; ++j) {
                int k = h2.col[j];
                assert_true(fabs(Pq[k] - Pp[k]) <= 1e-12 * Pp[k]);
                assert_true(fabs(Rq[k] - R[k]) <= 1e-13 * R[k]);
            }
            ++at_floor;
        }
    }
    assert_true(at_floor >= 4);
    hp_planner_destroy(p);
}

/* Least-squeeze holds with raised floors (HOLD puts bladders on them) through the stable
 * search. Where the tests' own stiffness at HOLD's pick (tests/support/load_stiffness.h,
 * from hp_load_eval's Jacobian) passes the search's margin, the search keeps the pick bit
 * for bit without searching, and the smallest eigenvalue it reports is the tests' own. Every
 * carrying bladder here outlasts the search's contact test (force >= its normal stiffness x
 * 1e-4 mm), so both count the same bladders and differ only by how K is assembled: 1e-12
 * N/mm absolute (K's entries are O(10 N/mm), formed to rounding either way: measured
 * 3.8e-16). With the floor
 * bladders at force 0 the search left them out of K: it searched at the nominal pose, the
 * 3 mm lift and a 2 mm shift in x, and at {0, 2, 1} mm reported 0.0103 N/mm against 0.0212. */
static void test_stable_search_counts_floor(void **state)
{
    (void)state;
    hp_layout L;
    hp_planner *p = NULL;
    double lo[HP_MAX_BLADDERS], hi[HP_MAX_BLADDERS], zero[HP_MAX_BLADDERS] = {0};
    const hp_load_model *M = fixture(&L, &p, lo, hi);
    /* mm, degrees: test_load_squeeze's small corrections */
    static const double T[][6] = {
        {0, 0, 0, 0, 0, 0}, {0, 0, 3, 0, 0, 0},   {2, 0, 1, 0, 0, 0},
        {0, 2, 1, 0, 0, 0}, {0, 0, 1, 2, 0, 0},   {0, 0, 1, 0, 2, 0},
        {0, 0, 1, 0, 0, 2}, {-3, 1, 2, 1, -1, 2}, {1, 0, -0.5, 0.3, 0, -0.2},
    };
    int kept = 0;
    for (size_t t = 0; t < sizeof T / sizeof T[0]; ++t) {
        double xi[6], lo2[HP_MAX_BLADDERS];
        hp_load_hold_set h2;
        raised_set(M, T[t], lo, hi, zero, xi, lo2, &h2);
        double P[HP_MAX_BLADDERS], F[HP_MAX_BLADDERS], P0[HP_MAX_BLADDERS], lam = NAN;
        if (hpi_load_hold(M, xi, lo2, hi, zero, NULL, 200, P, F, NULL) != HP_LOAD_SOLVE_OK)
            continue;
        int on_floor = 0;
        for (int j = 0; j < h2.m; ++j) {
            int k = h2.col[j];
            on_floor += P[k] == h2.L[k] && h2.Flo[k] > 0.0;
        }
        memcpy(P0, P, sizeof P0);
        double ref0 = test_load_smallest_stiffness(M, xi, P0);
        hp_test_stable_counts c0, c1;
        hpi_test_stable_counts(&c0);
        assert_int_equal(hpi_load_stable_hold(M, xi, lo2, hi, zero, P, F, &lam), HP_LOAD_SOLVE_OK);
        hpi_test_stable_counts(&c1);
        print_message("pose %zu: %d of %d carrying bladders on their floor, lam_min %.9g, "
                      "reference at the pick %.9g N/mm, searches %lu\n",
                      t, on_floor, h2.m, lam, ref0, c1.searches - c0.searches);
        assert_true(fabs(lam - test_load_smallest_stiffness(M, xi, P)) <= 1e-12);
        if (!(ref0 >= HP_LOAD_STABLE_MARGIN + 1e-6) || on_floor == 0) continue;
        assert_true(c1.searches == c0.searches);
        assert_memory_equal(P, P0, sizeof P0);
        ++kept;
    }
    assert_true(kept >= 6);
    hp_planner_destroy(p);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_forces_at_pressures),
        cmocka_unit_test(test_stable_search_counts_floor),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
