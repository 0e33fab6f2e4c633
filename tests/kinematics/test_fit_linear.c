/* The linear level's direct fit (hpi_kin_linear_fit_prepare / _solve, fit_linear.c), the
 * one set_measured uses at that level:
 * - on seeded targets that no pose fits exactly (radii of a pose plus ±10 µm noise), with
 *   all six components free and with the translations only, it ends where the iterative
 *   fit (hpi_kin_fit, Levenberg–Marquardt) ends, within 1e-12 m or rad: both solve the same
 *   normal equations, whose scaled condition on the default layout is ~30, so they differ
 *   by ~1e-16 of a pose of 1e-2; and its residual is orthogonal to every free column of the
 *   model (the least-squares optimality, written out here with the rows of hp_geom);
 * - with no free component or a column the model does not see (a zero column), prepare
 *   refuses (-1, ready 0) and solve answers HP_ERR_INVALID, so the caller falls back to the
 *   iterative fit. */
#include "support/test_util.h"

#include "support/default_layout.h"
#include "kin_test_util.h"
#include "kinematics/fit_internal.h"

#include <string.h>

static hp_layout LAY;
static hp_geom G;

static int setup(void **state)
{
    (void)state;
    if (default_layout(&LAY) != 0) return -1;
    return hpi_geom_derive(&LAY, &G, NULL) == HP_OK ? 0 : -1;
}

static void check_mask(const int free_[6], uint64_t seed)
{
    hp_kin_linear_fit f;
    assert_int_equal(hpi_kin_linear_fit_prepare(&LAY, &G, free_, &f), 0);
    assert_int_equal(f.ready, 1);
    double worst = 0;
    for (int t = 0; t < 200; ++t) {
        double xi[6], ro[HP_MAX_BLADDERS], got[6], ref[6], res, res_ref, zero[6] = {0};
        kin_rng_pose(&seed, 0.01, 0.09, 0, xi);
        assert_int_equal(hp_contact_eval(&LAY, HP_LEVEL_LINEAR, xi, ro, NULL, NULL), HP_OK);
        for (int k = 0; k < LAY.n; ++k) ro[k] += test_rng_uniform(&seed, -1e-5, 1e-5);
        assert_int_equal(hpi_kin_linear_fit_solve(&f, &LAY, &G, ro, got, &res), HP_OK);
        assert_int_equal(hpi_kin_fit(&LAY, &G, HP_LEVEL_LINEAR, ro, free_, zero, NULL, NULL, ref,
                                     &res_ref, NULL),
                         HP_OK);
        for (int i = 0; i < 6; ++i) {
            if (!free_[i]) assert_true(got[i] == 0.0);
            hp_assert_close(got[i], ref[i], 0, 1e-12);
            worst = fmax(worst, fabs(got[i] - ref[i]));
        }
        hp_assert_close(res, res_ref, 0, 1e-15);
        /* Optimality: each free column's cosine with the residual is at rounding level. */
        for (int i = 0; i < 6; ++i) {
            if (!free_[i]) continue;
            double g = 0, nc = 0, nr = 0;
            for (int k = 0; k < LAY.n; ++k) {
                double r = hpi_geom_linear(&G, k, got) - ro[k];
                g += G.row[k][i] * r;
                nc += G.row[k][i] * G.row[k][i];
                nr += r * r;
            }
            assert_true(fabs(g) <= 1e-10 * sqrt(nc * nr));
        }
    }
    print_message("largest difference to hpi_kin_fit: %.2e (m or rad)\n", worst);
}

static void test_equals_iterative_fit(void **state)
{
    (void)state;
    const int all[6] = {1, 1, 1, 1, 1, 1}, trans[6] = {1, 1, 1, 0, 0, 0};
    check_mask(all, 0x11f);
    check_mask(trans, 0x22f);
}

static void test_refuses(void **state)
{
    (void)state;
    const int none[6] = {0}, all[6] = {1, 1, 1, 1, 1, 1};
    hp_kin_linear_fit f;
    double ro[HP_MAX_BLADDERS] = {0}, xi[6];
    for (int k = 0; k < LAY.n; ++k) ro[k] = G.rho0[k];
    assert_int_equal(hpi_kin_linear_fit_prepare(&LAY, &G, none, &f), -1);
    assert_int_equal(f.ready, 0);
    assert_int_equal(hpi_kin_linear_fit_solve(&f, &LAY, &G, ro, xi, NULL), HP_ERR_INVALID);
    hp_geom g2 = G;
    for (int k = 0; k < LAY.n; ++k) g2.row[k][4] = 0.0; /* roll unseen */
    assert_int_equal(hpi_kin_linear_fit_prepare(&LAY, &g2, all, &f), -1);
    assert_int_equal(f.ready, 0);
    assert_int_equal(hpi_kin_linear_fit_solve(&f, &LAY, &g2, ro, xi, NULL), HP_ERR_INVALID);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_equals_iterative_fit),
        cmocka_unit_test(test_refuses),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
