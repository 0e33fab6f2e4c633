/* Rate limits of 1 mPa to 1 Pa per plan (log-uniform; radius windows of about 1e-6 to
 * 1e-3 mm: wider than the pinned windows plan.c holds without a solver, narrower than any
 * a correction needs). Holding or nearly holding the previous pressures is feasible, so
 * every backend must answer every plan: reached, uncommanded or closest (a closest answer
 * naming the rate limit), with every pressure inside its allowance. Anything else counts
 * as a failure (a solver-error, i.e. an answer refused by the planner's first-order check,
 * is counted apart). At the load level an answer must also be held (load_confirms: the
 * returned pressures hold the head at the achieved pose, the desired one when REACHED), and
 * a closest answer may name the load level's own limit instead of the rate limit: a
 * correction that needs a bladder to pull the head (cannot_pull: it carries nothing, at a
 * pressure <= 0) is out of reach whatever the rates. Seeded: per backend, 5 levels (linear,
 * plane, surface, auto, load; nlopt-cobyla does not plan the load level and is refused by
 * name) x 10 starts x a chain of 4 corrections (each from the planner's own previous
 * answer) = 200 plans.
 *
 * A plan that ends on a window end keeps |P − P_prev| <= rate_max as computed in floating
 * point, at every backend and level: the window's ends are rounded inward, so a rounded
 * end never lies half an ulp beyond the allowance (test_window_end_within_rate). */
#include "support/test_util.h"
#include "support/layout_fixture.h"
#include "support/load_fixture.h"
#include "planner/problem_setup.h"
#include "planner/backend_testing.h"

#define N_PLANS HP_TEST_SMALL(10, 3) /* seeded start poses and rates per backend and level */
#define N_CHAIN 4
#define SEED 0x5EEDu

/* A planner on the default layout with every rate_max = rate [Pa] (load_lf_planner: at
 * the load level carrying 20 % of the head's weight). NULL for a backend that does not plan
 * the load level, which create refuses by name. */
static hp_planner *limited(hp_backend bk, hp_level level, double rate)
{
    int refused = 0;
    hp_planner *p = load_lf_planner(bk, level, rate, &refused);
    if (!refused) assert_non_null(p);
    return p;
}

/* The pressures of a plan of pose xi without rate limits at level (realtime): reached at a
 * contact level; at the load level reached or, where the weight keeps the head from xi,
 * closest (held at the nearest pose it can be). */
static void pressures_of(hp_level level, const double xi[6], double P[HP_MAX_BLADDERS])
{
    hp_planner *p = limited(HP_BACKEND_REALTIME, level, INFINITY);
    hp_result r;
    assert_int_equal(hp_plan(p, xi, &r), HP_OK);
    int ok = r.status == HP_STATUS_REACHED ||
             (level == HP_LEVEL_LOAD && r.status == HP_STATUS_CLOSEST);
    if (!ok) print_error("start: %s\n", hp_status_name(r.status));
    assert_true(ok);
    for (int k = 0; k < r.n; ++k) P[k] = r.bladders[k].pressure;
    hp_planner_destroy(p);
}

/* A pose within ±amp mm / deg on every axis, in SI. */
static void random_pose(uint64_t *s, double amp, double xi[6])
{
    double mm_deg[6];
    for (int i = 0; i < 6; ++i) mm_deg[i] = amp * lf_uniform(s);
    lf_pose(mm_deg, xi);
}

/* Plans of one backend at one level; returns how many were not answered as they must be
 * (printing each), and adds the solver-errors to *n_err. */
static int run(hp_backend bk, hp_level level, int *n_err)
{
    uint64_t s = SEED + 7919u * (uint64_t)level; /* the same plans for every backend */
    int failed = 0;
    for (int t = 0; t < N_PLANS; ++t) {
        /* Rate log-uniform in [1e-3, 1] Pa. */
        double rate = pow(10.0, -1.5 + 1.5 * lf_uniform(&s));
        double x0[6], d[6], P0[HP_MAX_BLADDERS];
        random_pose(&s, 1.0, x0);
        pressures_of(level, x0, P0);
        hp_planner *p = limited(bk, level, rate);
        if (!p) return 0; /* refused by name: this backend does not plan the level */
        assert_int_equal(hp_planner_set_previous(p, P0), HP_OK);
        for (int c = 0; c < N_CHAIN; ++c) {
            /* The correction: the start pose moved by up to 1e-3 .. 2 mm / deg
             * (log-uniform), so that some bladders end inside their windows and some at
             * an edge. */
            double amp = pow(10.0, -1.35 + 1.65 * lf_uniform(&s));
            random_pose(&s, amp, d);
            for (int i = 0; i < 6; ++i) d[i] += x0[i];
            hp_result r;
            assert_int_equal(hp_plan(p, d, &r), HP_OK);
            int ok = r.status == HP_STATUS_REACHED || r.status == HP_STATUS_CLOSEST ||
                     r.status == HP_STATUS_UNCOMMANDED;
            unsigned rate_flags = 0;
            const unsigned may = HP_BIND_RATE_DOWN | HP_BIND_RATE_UP |
                                 (level == HP_LEVEL_LOAD ? HP_BIND_CANNOT_PULL : 0u);
            for (int k = 0; ok && k < r.n; ++k) {
                double P = r.bladders[k].pressure;
                ok = P >= P0[k] - rate && P <= P0[k] + rate;
                if (r.bladders[k].binding & HP_BIND_CANNOT_PULL) ok = ok && P <= 0.0;
                rate_flags |= r.bladders[k].binding & may;
            }
            if (ok && r.status == HP_STATUS_CLOSEST && !rate_flags) ok = 0;
            char why[160] = "";
            if (ok && level == HP_LEVEL_LOAD) ok = load_confirms(p, d, &r, why, sizeof why);
            if (!ok) {
                ++failed;
                *n_err += r.status == HP_STATUS_SOLVER_ERROR;
                print_error("%s, %s level, plan %d.%d, rate %.3g Pa: %s: %s%s\n",
                            hp_backend_name(bk), hp_level_name(level), t, c, rate,
                            hp_status_name(r.status), hp_planner_error(p), why);
            }
            for (int k = 0; k < r.n; ++k) P0[k] = r.bladders[k].pressure;
        }
        hp_planner_destroy(p);
    }
    return failed;
}

static void test_every_backend_answers(void **st)
{
    (void)st;
    const hp_level levels[5] = {HP_LEVEL_LINEAR, HP_LEVEL_PLANE, HP_LEVEL_SURFACE, HP_LEVEL_AUTO,
                                HP_LEVEL_LOAD};
    int failed = 0;
    for (int b = 0; b < HP_BACKEND_COUNT_; ++b) {
        int f = 0, n_err = 0;
        for (int l = 0; l < 5; ++l) f += run((hp_backend)b, levels[l], &n_err);
        print_message("%s: %d plans unanswered (%d solver-error)\n", hp_backend_name((hp_backend)b),
                      f, n_err);
        failed += f;
    }
    assert_int_equal(failed, 0);
}

/* A rate in [40, 80) Pa for which the plainly rounded window ends around P lie beyond it in
 * floating point: fl(fl(P + r) − P) > r and fl(P − fl(P − r)) > r (half an ulp of P beyond,
 * as the horizon's drift trace met at 61.2 Pa); both when a few thousand draws find such a
 * rate, else one, else neither (a sum that is exact cannot overshoot: |P| small against r).
 * Seeded. */
static double overshooting_rate(uint64_t *s, double P)
{
    for (int i = 0; i < 100000; ++i) {
        double r = 60.0 + 20.0 * lf_uniform(s);
        int up = (P + r) - P > r, down = P - (P - r) > r;
        if (up && down) return r;
        if ((i >= 4000 && (up || down)) || i >= 20000) return r;
    }
    return NAN;
}

/* Every backend at every level it plans: from a start's pressures, rates chosen so that
 * both plainly rounded window ends overshoot, then corrections far beyond the windows (every
 * bladder ends on a window end or a static limit), a chain of 4 from the planner's own
 * answers. Every returned pressure P must satisfy fabs(P − P_prev) <= rate, as computed. */
static void test_window_end_within_rate(void **st)
{
    (void)st;
    const hp_level levels[4] = {HP_LEVEL_LINEAR, HP_LEVEL_PLANE, HP_LEVEL_SURFACE, HP_LEVEL_LOAD};
    long over = 0, on_end = 0, plans = 0;
    for (int b = 0; b < HP_BACKEND_COUNT_; ++b) {
        for (int l = 0; l < 4; ++l) {
            uint64_t s = SEED + 31u * (uint64_t)l;
            double x0[6], d[6], P0[HP_MAX_BLADDERS], rate[HP_MAX_BLADDERS];
            random_pose(&s, 1.0, x0);
            pressures_of(levels[l], x0, P0);
            hp_planner *p = limited((hp_backend)b, levels[l], INFINITY);
            if (!p) continue; /* refused by name */
            assert_int_equal(hp_planner_set_previous(p, P0), HP_OK);
            const int n = hp_planner_layout(p)->n;
            for (int c = 0; c < N_CHAIN; ++c) {
                for (int k = 0; k < n; ++k) rate[k] = overshooting_rate(&s, P0[k]);
                assert_int_equal(hp_planner_set_rate_max(p, rate), HP_OK);
                random_pose(&s, 3.0, d);
                for (int i = 0; i < 6; ++i) d[i] += x0[i];
                hp_result r;
                assert_int_equal(hp_plan(p, d, &r), HP_OK);
                ++plans;
                for (int k = 0; k < n; ++k) {
                    double P = r.bladders[k].pressure;
                    on_end += (r.bladders[k].binding & (HP_BIND_RATE_DOWN | HP_BIND_RATE_UP)) != 0;
                    if (!(fabs(P - P0[k]) <= rate[k])) {
                        ++over;
                        print_error("%s, %s level, plan %d, bladder %d (%s): |P - P_prev| = "
                                    "%.17g Pa > rate %.17g Pa\n",
                                    hp_backend_name((hp_backend)b), hp_level_name(levels[l]), c, k,
                                    hp_status_name(r.status), fabs(P - P0[k]), rate[k]);
                    }
                }
                for (int k = 0; k < n; ++k) P0[k] = r.bladders[k].pressure;
            }
            hp_planner_destroy(p);
        }
    }
    print_message("%ld plans, %ld bladders on a rate window's end, %ld beyond the rate\n", plans,
                  on_end, over);
    assert_true(on_end >= 100);
    assert_int_equal(over, 0);
}

/* hpi_rate_window over seeded previous pressures (uniform in ±10 kPa) and rates
 * (log-uniform 1e-3 Pa .. 20 kPa): each end keeps fabs(end − prev) <= rate as computed, is
 * the outermost double that does (the next one out breaks it, or the end is the plain
 * rounding of prev ± rate), and prev lies inside. The plain ends break the property on a
 * good share of the draws (counted: that is what the inward rounding is for). */
static void test_window_ends_inward(void **st)
{
    (void)st;
    uint64_t s = SEED;
    long plain_over = 0;
    const int n = 100000;
    for (int i = 0; i < n; ++i) {
        double prev = 1e4 * lf_uniform(&s), rate = pow(10.0, 0.65 + 3.65 * lf_uniform(&s));
        double lo, hi, pl = prev - rate, ph = prev + rate;
        hpi_rate_window(prev, rate, &lo, &hi);
        assert_true(fabs(lo - prev) <= rate && fabs(hi - prev) <= rate);
        assert_true(lo <= prev && prev <= hi);
        assert_true(lo == pl || !(fabs(nextafter(lo, -INFINITY) - prev) <= rate));
        assert_true(hi == ph || !(fabs(nextafter(hi, INFINITY) - prev) <= rate));
        plain_over += !(fabs(pl - prev) <= rate) || !(fabs(ph - prev) <= rate);
    }
    double lo, hi;
    hpi_rate_window(5.0, INFINITY, &lo, &hi);
    assert_true(lo == -INFINITY && hi == INFINITY);
    print_message("%ld of %d plainly rounded windows have an end beyond the rate\n", plain_over, n);
    assert_true(plain_over > n / 20);
}

/* The loop benchmark's step trace at the linear level (bench/bench_loop.c): a new seeded
 * target within ±3 mm / ±2° every WALK_HOLD plans, rate_max 500 Pa, so that after each new
 * target the plans walk toward it binding several rate limits, plan after plan; with
 * measured = 1 the pressures come back through hp_planner_set_measured with ±3 Pa of seeded
 * noise. Consecutive binding plans mostly bind the same limits, so the realtime backend
 * starts each plan's QP from the previous plan's active set (hpi_qp_solve_warm): counted
 * through the planner (backend_testing.h), the warm start must answer most binding plans
 * (without the kept active set none is, at this level), and a refused one starts the
 * Goldfarb–Idnani loop from the guessed rows it keeps. The answers against a solve of
 * the same plan by a new planner given the same previous (or measured) pressures (no
 * active set kept):
 * the same status and binding flags, every pressure within 1e-9 Pa (a warm-started x agrees
 * with the full solve's to rounding, qp.h; measured up to 1.7e-11 Pa apart on pressures of
 * ~1 kPa, and a binding flag's pressure is the answer radius's, within the binding
 * tolerance of the limit, not the limit's bits) and, fed back its own answers, within the
 * rate of the previous one. */
#define WALK_TARGETS 6
#define WALK_HOLD 40
static void binding_walk(int measured, long *binding, long *warm, long *cold_warm, long *steps)
{
    uint64_t s = SEED + 101u * (uint64_t)measured;
    hp_planner *p = limited(HP_BACKEND_REALTIME, HP_LEVEL_LINEAR, 500.0);
    const int n = hp_planner_layout(p)->n;
    double tgt[6] = {0}, P0[HP_MAX_BLADDERS] = {0};
    hp_test_rt_counts c0, c1;
    for (int t = 0; t < WALK_TARGETS; ++t) {
        random_pose(&s, 1.0, tgt);
        for (int i = 0; i < 6; ++i) tgt[i] *= i < 3 ? 3.0 : 2.0;
        for (int j = 0; j < WALK_HOLD; ++j) {
            hp_result r, rc;
            hpi_test_realtime_count(1);
            assert_int_equal(hp_plan(p, tgt, &r), HP_OK);
            hpi_test_realtime_count(0);
            hpi_test_realtime_counts(&c0);
            unsigned any = 0;
            for (int k = 0; k < n; ++k)
                any |= r.bladders[k].binding & (HP_BIND_RATE_DOWN | HP_BIND_RATE_UP);
            *binding += any != 0 && c0.solves > 0;
            *warm += c0.qp_warm;
            *steps += c0.qp_steps;
            if (t > 0 || j > 0) { /* the cold solve of the same plan */
                hp_planner *q = limited(HP_BACKEND_REALTIME, HP_LEVEL_LINEAR, 500.0);
                assert_int_equal(measured ? hp_planner_set_measured(q, P0, NULL)
                                          : hp_planner_set_previous(q, P0),
                                 HP_OK);
                hpi_test_realtime_count(1);
                assert_int_equal(hp_plan(q, tgt, &rc), HP_OK);
                hpi_test_realtime_count(0);
                hpi_test_realtime_counts(&c1);
                *cold_warm += c1.qp_warm;
                assert_int_equal(r.status, rc.status);
                for (int k = 0; k < n; ++k) {
                    assert_int_equal(r.bladders[k].binding, rc.bladders[k].binding);
                    hp_assert_close(r.bladders[k].pressure, rc.bladders[k].pressure, 0, 1e-9);
                    /* a reading a hair beyond a limit is clamped first (the window's centre) */
                    if (!measured) assert_true(fabs(r.bladders[k].pressure - P0[k]) <= 500.0);
                }
                hp_planner_destroy(q);
            }
            for (int k = 0; k < n; ++k) {
                P0[k] = r.bladders[k].pressure;
                if (measured) P0[k] += 3.0 * lf_uniform(&s);
            }
            if (measured) assert_int_equal(hp_planner_set_measured(p, P0, NULL), HP_OK);
        }
    }
    hp_planner_destroy(p);
}

static void test_binding_walk_warm(void **st)
{
    (void)st;
    for (int measured = 0; measured < 2; ++measured) {
        long binding = 0, warm = 0, cold_warm = 0, steps = 0;
        binding_walk(measured, &binding, &warm, &cold_warm, &steps);
        print_message("%s: %ld plans binding a rate limit, %ld QPs warm-started from the last "
                      "plan's active set (%ld in the new planners' plans), %ld Goldfarb-Idnani "
                      "steps\n",
                      measured ? "measured" : "own answers", binding, warm, cold_warm, steps);
        assert_true(binding >= WALK_TARGETS * 5);
        assert_true(warm >= binding * 3 / 4);
        assert_int_equal(cold_warm, 0); /* the warm starts are the kept active set's */
        /* A refused warm start's loop starts from the guessed rows it keeps (qp.h): fewer
         * Goldfarb–Idnani steps than binding plans (counted 37 of 51, 58 of 87), where a
         * loop from the unconstrained minimum re-adds every binding row (81, 170). */
        assert_true(steps < binding);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_backend_answers),
        cmocka_unit_test(test_window_ends_inward),
        cmocka_unit_test(test_window_end_within_rate),
        cmocka_unit_test(test_binding_walk_warm),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
