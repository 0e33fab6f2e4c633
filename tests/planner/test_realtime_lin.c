/* The realtime backend's linearisation point (hp_backend_result's has_lin, lin_x, lin_rho,
 * lin_J), which the round trip's certificate takes as the model at lin_x: whenever it is
 * handed over, a fresh evaluation of the model at lin_x (hpi_contact_eval_g) gives the same
 * distances and Jacobian to rounding, lin_x is a rounding-level step from the answer, and
 * the answer's own distances are handed over too. Cold and warm solves (each target
 * started from the last answer), reachable and binding targets, plane and surface levels,
 * and with NaN faults injected (what is handed over is still the clean model). */
#include "support/test_util.h"
#include "planner/backend_testing.h"
#include "planner/problem.h"
#include "planner/problem_setup.h"
#include "support/backend_fixture.h"
#include "kinematics/kin_geom.h"

static long handed, checked;

static void check_lin(const hp_problem *pb, const double *x, const hp_backend_result *r, int fault)
{
    if (!r->has_lin) return;
    ++handed;
    /* With a late NaN fault the answer's distances are NaN (has_rho 0) while the first QP's
     * point was clean: the core takes lin_* only with has_rho (plan.c). */
    if (fault == HP_TEST_FAULT_NONE) assert_true(r->has_rho);
    double xi[6], rho[HP_MAX_BLADDERS], J[HP_MAX_BLADDERS * 6], step = 0.0, jmax = 0.0;
    hpi_setup_pose_from_scaled(r->lin_x, xi);
    assert_int_equal(hpi_contact_eval_g(pb->layout, pb->geom, pb->level, xi, rho, J, NULL), HP_OK);
    for (int i = 0; i < 6; ++i) step = fmax(step, fabs(x[i] - r->lin_x[i]));
    /* "a rounding-level step": the backend's RT_FULL_STEP is far below 1e-3 mm/deg */
    assert_true(step <= 1e-3);
    for (int k = 0; k < pb->n; ++k) {
        /* mm; 1e-12 relative: a few ulps of the distance, far below a changed point (a
         * step of 1e-9 mm moves it by ~1e-9 mm) */
        double want = rho[k] * 1e3;
        if (!(fabs(r->lin_rho[k] - want) <= 1e-12 * fabs(want)))
            fail_msg("bladder %d: lin_rho %.17g, model at lin_x %.17g", k, r->lin_rho[k], want);
        for (int i = 0; i < 6; ++i) jmax = fmax(jmax, fabs(J[k * 6 + i]));
    }
    for (int k = 0; k < pb->n; ++k)
        for (int i = 0; i < 6; ++i)
            if (!(fabs(r->lin_J[k * 6 + i] - J[k * 6 + i]) <= 1e-12 * jmax))
                fail_msg("J[%d][%d]: lin_J %.17g, model at lin_x %.17g", k, i, r->lin_J[k * 6 + i],
                         J[k * 6 + i]);
    ++checked;
}

static void run(hp_level level, int fault)
{
    hp_layout L;
    hp_geom G;
    assert_int_equal(fx_layout(&L), HP_OK);
    hp_settings s;
    memset(&s, 0, sizeof s);
    s.backend = HP_BACKEND_REALTIME;
    s.level = level;
    s.tolerance = 1e-9;
    s.max_iter = 200;
    s.max_time = 10.0;
    s.weight_mm_per_deg = 1.0;
    s.warm_start = 1;
    const double d0[6] = {0};
    hp_problem pb;
    assert_int_equal(fx_problem(&L, &G, level, d0, &pb), HP_OK);
    void *state = NULL;
    hp_diag dg = {{0}};
    assert_int_equal(hpi_backend_realtime_ops.create(&state, &pb, &s, &dg), HP_OK);
    hpi_test_realtime_fault(fault);
    double x[HP_PROBLEM_NX_MAX] = {0}, xprev[HP_PROBLEM_NX_MAX] = {0};
    int have_prev = 0;
    for (int t = 0; t < 120; ++t) {
        /* a slow drift out to ~12 mm/deg and back: reachable, then binding */
        double a = 12.0 * sin(t / 19.0), dir[6] = {1.0, -0.6, 0.45, 0.3, -0.2, 0.15};
        for (int i = 0; i < 6; ++i) pb.d[i] = a * dir[i] * (t % 7 == 3 ? -1.0 : 1.0);
        hp_backend_result r;
        hp_error e = hpi_backend_realtime_ops.solve(state, &pb, have_prev && t % 5 ? xprev : NULL,
                                                    x, &r, &dg);
        if (fault != HP_TEST_FAULT_NONE) {
            check_lin(&pb, x, &r, fault); /* the model itself is clean */
            continue;
        }
        if (e != HP_OK) continue;
        check_lin(&pb, x, &r, fault);
        memcpy(xprev, x, sizeof xprev);
        have_prev = 1;
    }
    hpi_test_realtime_fault(HP_TEST_FAULT_NONE);
    hpi_backend_realtime_ops.destroy(state);
}

static void lin_point_is_the_model(void **st)
{
    (void)st;
    const int faults[3] = {HP_TEST_FAULT_NONE, HP_TEST_FAULT_NAN_CONTACT,
                           HP_TEST_FAULT_NAN_CONTACT_LATE};
    for (int f = 0; f < 3; ++f) {
        run(HP_LEVEL_PLANE, faults[f]);
        run(HP_LEVEL_SURFACE, faults[f]);
    }
    print_message("%ld linearisation points handed over, %ld checked\n", handed, checked);
    assert_true(checked >= 50);
}

int main(void)
{
    const struct CMUnitTest tests[] = {cmocka_unit_test(lin_point_is_the_model)};
    return cmocka_run_group_tests(tests, NULL, NULL);
}
