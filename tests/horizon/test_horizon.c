/* The horizon planners on the rate-limited step trace and the irregularly sampled drift:
 * offline <= greedy and receding in cost (it is the optimum of their common problem), every
 * row of every plan inside every limit (recomputed here from the radii with the public bladder
 * model, not taken from the planner), windows against the whole solve, receding with N = 1
 * against greedy, and the checks on settings and time stamps. */
#include "support/test_util.h"
#include "tests/horizon/horizon_fixture.h"
#include "horizon/horizon_internal.h"

/* Rows of the step trace used: the first two shifts (at 5 s and 12 s) and their settling. */
#define STEP_ROWS 150

typedef struct plans {
    hp_horizon_row g[HF_MAX_ROWS], r[HF_MAX_ROWS], o[HF_MAX_ROWS];
    hp_horizon_metrics mg, mr, mo;
} plans;

static void plan_all(const hf_case *c, const hp_horizon_settings *hs, plans *p)
{
    hp_diag d = {{0}};
    const hp_layout *L = &c->sc.layout;
    assert_int_equal(hp_horizon_greedy(L, &c->s, hs, c->rows, c->T, c->p0, p->g, &d), HP_OK);
    assert_int_equal(hp_horizon_receding(L, &c->s, hs, c->rows, c->T, c->p0, p->r, &d), HP_OK);
    hp_horizon_info info;
    hp_error e = hp_horizon_offline(L, &c->s, hs, c->rows, c->T, c->p0, p->o, &info, &d);
    if (e != HP_OK) print_error("%s\n", d.text);
    assert_int_equal(e, HP_OK);
    assert_true(info.windows >= 1 && info.iterations > 0);
    assert_int_equal(hp_horizon_measure(p->g, c->T, L->n, c->p0, &c->s, hs, 0.5, 0.5, &p->mg),
                     HP_OK);
    assert_int_equal(hp_horizon_measure(p->r, c->T, L->n, c->p0, &c->s, hs, 0.5, 0.5, &p->mr),
                     HP_OK);
    assert_int_equal(hp_horizon_measure(p->o, c->T, L->n, c->p0, &c->s, hs, 0.5, 0.5, &p->mo),
                     HP_OK);
}

/* Every row inside every limit, from the radii alone: P = hp_iab_ik(ri) inside
 * [p_min, p_max], ri/Ri inside [stretch_min, stretch_max], |P_t − P_t−1| <= min(rate_max,
 * rate_max_per_s·dt) (row 0 against the start pressures, dt the start interval), and the
 * contact kept: hp_iab_ro(ri) equals the contact distance of the achieved pose at the
 * planner's level to 1e-9 m (1e-6 mm: the offline solver's contact tolerance). Returns the
 * number of (row, bladder) pairs whose rate limit binds (to 10 mPa: the offline plan keeps
 * 1 mPa inside). */
static int check_limits(const hf_case *c, const hp_horizon_settings *hs, const hp_horizon_row *o,
                        const char *name)
{
    const hp_layout *L = &c->sc.layout;
    hp_planner *p = NULL;
    assert_int_equal(hp_planner_create(L, &c->s, &p, NULL), HP_OK);
    hp_level level = hp_planner_level(p);
    hp_planner_destroy(p);
    double prev[HP_MAX_BLADDERS];
    memcpy(prev, c->p0, sizeof prev);
    int binds = 0;
    for (size_t t = 0; t < c->T; ++t) {
        double dt = t ? c->rows[t].t - c->rows[t - 1].t : hs->start_interval_s;
        double rho[HP_MAX_BLADDERS];
        assert_int_equal(hp_contact_eval(L, level, o[t].achieved, rho, NULL, NULL), HP_OK);
        for (int k = 0; k < L->n; ++k) {
            const hp_bladder *B = &L->bladders[k];
            double P, ro, ri = o[t].ri[k];
            assert_int_equal(hp_iab_ik(&B->iab, ri, &P), HP_OK);
            assert_int_equal(hp_iab_ro(&B->iab, ri, &ro), HP_OK);
            double rate = fmin(B->rate_max, hs->rate_max_per_s * dt);
            int ok = P >= B->p_min && P <= B->p_max && ri / B->iab.Ri >= B->stretch_min &&
                     ri / B->iab.Ri <= B->stretch_max && fabs(P - prev[k]) <= rate &&
                     fabs(ro - rho[k]) <= 1e-9;
            if (!ok) {
                print_error("%s: line %ld bladder %s: P %.17g (%g..%g), stretch %.17g, "
                            "|dP| %.17g > %.17g?, contact %.3g m\n",
                            name, c->rows[t].line, B->name, P, B->p_min, B->p_max, ri / B->iab.Ri,
                            fabs(P - prev[k]), rate, fabs(ro - rho[k]));
                fail();
            }
            binds += fabs(P - prev[k]) >= rate - 1e-2;
            prev[k] = P;
        }
    }
    return binds;
}

static hp_horizon_settings defaults(void)
{
    hp_horizon_settings hs;
    hp_horizon_settings_default(&hs);
    hs.start_interval_s = 0.1; /* the traces' sampling interval */
    return hs;
}

/* On the rate-limited step trace the offline plan's cost is no larger than greedy's and the
 * receding horizon's: both are feasible points of its problem and it is the optimum. The
 * relative slack 1e-4 covers the offline NLP keeping its rate limits 1 mPa inside (out of
 * 250 Pa per row) and Ipopt's tolerance 1e-8. Where the limits bind (measured: offline pose
 * cost 14, greedy 46 on the whole trace) it is strictly smaller: at most half. */
static void test_offline_not_worse_step(void **st)
{
    (void)st;
    hf_case *c = hf_load("horizon/step.yaml", "step.csv", STEP_ROWS);
    assert_non_null(c);
    assert_int_equal((int)c->T, STEP_ROWS);
    hp_horizon_settings hs = defaults();
    plans *p = calloc(1, sizeof *p);
    plan_all(c, &hs, p);
    assert_true(p->mo.cost <= p->mg.cost * (1 + 1e-4));
    assert_true(p->mo.cost <= p->mr.cost * (1 + 1e-4));
    assert_true(p->mo.pose_cost < 0.5 * p->mg.pose_cost);
    assert_true(p->mo.pose_cost < 0.5 * p->mr.pose_cost);
    assert_true(p->mo.time_outside < p->mg.time_outside);
    /* every plan inside every limit, and the rate limits do bind in each */
    assert_true(check_limits(c, &hs, p->g, "greedy") > 0);
    assert_true(check_limits(c, &hs, p->r, "receding") > 0);
    assert_true(check_limits(c, &hs, p->o, "offline") > 0);
    free(p);
    free(c);
}

/* Per-second rate limits on irregular time stamps (the drift trace: 10 Hz with ±20 ms
 * jitter and dropped frames): the limit of a row is rate_max_per_s times its own interval;
 * the per-row limit is lifted so only the per-second one acts. Same ordering and checks. */
static void test_per_second_irregular(void **st)
{
    (void)st;
    hf_case *c = hf_load("horizon/drift_long.yaml", "drift_long.csv", 600);
    assert_non_null(c);
    int irregular = 0;
    for (size_t t = 1; t < c->T; ++t)
        irregular += fabs(c->rows[t].t - c->rows[t - 1].t - 0.1) > 1e-3;
    assert_true(irregular > 100);
    for (int k = 0; k < c->sc.layout.n; ++k) c->sc.layout.bladders[k].rate_max = INFINITY;
    hp_horizon_settings hs = defaults();
    hs.rate_max_per_s = 600.0; /* Pa/s */
    plans *p = calloc(1, sizeof *p);
    plan_all(c, &hs, p);
    assert_true(p->mo.cost <= p->mg.cost * (1 + 1e-4));
    assert_true(p->mo.cost <= p->mr.cost * (1 + 1e-4));
    assert_true(check_limits(c, &hs, p->g, "greedy") > 0);
    assert_true(check_limits(c, &hs, p->r, "receding") > 0);
    assert_true(check_limits(c, &hs, p->o, "offline") > 0);
    free(p);
    free(c);
}

/* Overlapping windows against one whole solve on the same trace: every row's pose within
 * WINDOW_POSE_TOL (mm or degrees) and the cost within 1e-4 relative. Measured: 1.6e-6 mm and
 * 1e-9 relative — a 20-row overlap (2 s) is far longer than the limits' reach back in time
 * here (a step is caught up within about 1.5 s). */
#define WINDOW_POSE_TOL 1e-3
static void test_windows_agree(void **st)
{
    (void)st;
    hf_case *c = hf_load("horizon/step.yaml", "step.csv", STEP_ROWS);
    assert_non_null(c);
    hp_horizon_settings hs = defaults();
    hp_horizon_row *whole = calloc(c->T, sizeof *whole), *win = calloc(c->T, sizeof *win);
    hp_horizon_info iw, iv;
    hp_diag d = {{0}};
    assert_int_equal(
        hp_horizon_offline(&c->sc.layout, &c->s, &hs, c->rows, c->T, c->p0, whole, &iw, &d), HP_OK);
    hs.window = 60;
    hs.overlap = 20;
    assert_int_equal(
        hp_horizon_offline(&c->sc.layout, &c->s, &hs, c->rows, c->T, c->p0, win, &iv, &d), HP_OK);
    assert_int_equal(iw.windows, 1);
    assert_int_equal(iv.windows, 4); /* rows 0-59, 40-99, 80-139, 120-149 */
    double worst = 0;
    for (size_t t = 0; t < c->T; ++t)
        for (int i = 0; i < 6; ++i)
            worst = fmax(worst, fabs(win[t].achieved[i] - whole[t].achieved[i]) *
                                    (i < 3 ? 1e3 : 57.295779513082320877));
    print_message("windowed vs whole: largest pose difference %.3g, cost %.9g vs %.9g\n", worst,
                  iv.cost, iw.cost);
    assert_true(worst <= WINDOW_POSE_TOL);
    hp_assert_close(iv.cost, iw.cost, 1e-4, 0);
    assert_true(iv.cost >= iw.cost * (1 - 1e-6)); /* the whole solve is the optimum */
    free(whole);
    free(win);
    free(c);
}

/* A receding horizon of one row with a held prediction solves each row's own problem: the
 * greedy plan (second method: hp_plan's QP). Rows agree to 1e-5 mm / degree (the interior
 * point stops after 20 iterations; measured well below). */
static void test_receding_one_row_is_greedy(void **st)
{
    (void)st;
    hf_case *c = hf_load("horizon/step.yaml", "step.csv", STEP_ROWS);
    assert_non_null(c);
    hp_horizon_settings hs = defaults();
    hs.horizon = 1;
    hp_horizon_row *g = calloc(c->T, sizeof *g), *r = calloc(c->T, sizeof *r);
    hp_diag d = {{0}};
    assert_int_equal(hp_horizon_greedy(&c->sc.layout, &c->s, &hs, c->rows, c->T, c->p0, g, &d),
                     HP_OK);
    assert_int_equal(hp_horizon_receding(&c->sc.layout, &c->s, &hs, c->rows, c->T, c->p0, r, &d),
                     HP_OK);
    double worst = 0;
    for (size_t t = 0; t < c->T; ++t)
        for (int i = 0; i < 6; ++i)
            worst = fmax(worst, fabs(r[t].achieved[i] - g[t].achieved[i]) *
                                    (i < 3 ? 1e3 : 57.295779513082320877));
    print_message("receding N=1 vs greedy: largest pose difference %.3g\n", worst);
    assert_true(worst <= 1e-5);
    free(g);
    free(r);
    free(c);
}

static void test_settings_checked(void **st)
{
    (void)st;
    hp_horizon_settings hs;
    hp_diag d = {{0}};
    hp_horizon_settings_default(&hs);
    assert_int_equal(hp_horizon_settings_validate(&hs, &d), HP_OK);
    assert_int_equal(hp_horizon_settings_validate(NULL, &d), HP_ERR_NULL);
#define BAD(field, value, name)                                                                    \
    do {                                                                                           \
        hp_horizon_settings b_ = hs;                                                               \
        b_.field = value;                                                                          \
        assert_int_equal(hp_horizon_settings_validate(&b_, &d), HP_ERR_INVALID);                   \
        assert_non_null(strstr(d.text, name));                                                     \
    } while (0)
    BAD(rate_max_per_s, NAN, "rate_max_per_s");
    BAD(rate_max_per_s, 0.0, "rate_max_per_s");
    BAD(rate_max_per_s, -1.0, "rate_max_per_s");
    BAD(smooth, NAN, "smooth");
    BAD(smooth, -1e-9, "smooth");
    BAD(start_interval_s, INFINITY, "start_interval_s");
    BAD(start_interval_s, 0.0, "start_interval_s");
    BAD(horizon, 0, "horizon");
    BAD(horizon, HP_HORIZON_MAX + 1, "horizon");
    BAD(velocity_rows, 1, "velocity_rows");
    BAD(rh_max_iter, 0, "rh_max_iter");
    BAD(window, -1, "window");
    BAD(overlap, 3, "overlap"); /* without a window */
    BAD(offline_tol, 0.0, "offline_tol");
    BAD(offline_max_iter, 0, "offline_max_iter");
    BAD(offline_max_time, NAN, "offline_max_time");
    hs.window = 10;
    BAD(overlap, 10, "overlap");
#undef BAD
    hp_prediction pr;
    assert_int_equal(hp_prediction_parse("velocity", &pr), HP_OK);
    assert_int_equal(pr, HP_PREDICT_VELOCITY);
    assert_int_equal(hp_prediction_parse("Hold", &pr), HP_ERR_INVALID);
    assert_string_equal(hp_prediction_name(HP_PREDICT_HOLD), "hold");
}

/* Time stamps: a row not after the previous one, or not finite, is refused with its line. */
static void test_time_stamps_checked(void **st)
{
    (void)st;
    hf_case *c = hf_load("horizon/step.yaml", "step.csv", 20);
    assert_non_null(c);
    hp_horizon_settings hs = defaults();
    double delta[20 * HP_MAX_BLADDERS];
    hp_diag d = {{0}};
    assert_int_equal(hp_horizon_rates(&c->sc.layout, &hs, c->rows, c->T, delta, &d), HP_OK);
    hp_assert_close(delta[0], 250.0, 1e-12, 0); /* rate_max_kpa 0.25 per row */
    hs.rate_max_per_s = 1000.0;
    assert_int_equal(hp_horizon_rates(&c->sc.layout, &hs, c->rows, c->T, delta, &d), HP_OK);
    hp_assert_close(delta[5 * c->sc.layout.n], 100.0, 1e-9, 0); /* 1000 Pa/s · 0.1 s */
    c->rows[7].t = c->rows[6].t;
    assert_int_equal(hp_horizon_rates(&c->sc.layout, &hs, c->rows, c->T, delta, &d),
                     HP_ERR_INVALID);
    char want[32];
    snprintf(want, sizeof want, "line %ld", c->rows[7].line);
    assert_non_null(strstr(d.text, want));
    hp_horizon_row out[20];
    assert_int_equal(hp_horizon_greedy(&c->sc.layout, &c->s, &hs, c->rows, c->T, c->p0, out, &d),
                     HP_ERR_INVALID);
    assert_int_equal(
        hp_horizon_offline(&c->sc.layout, &c->s, &hs, c->rows, c->T, c->p0, out, NULL, &d),
        HP_ERR_INVALID);
    assert_int_equal(hp_horizon_receding(&c->sc.layout, &c->s, &hs, c->rows, c->T, c->p0, out, &d),
                     HP_ERR_INVALID);
    c->rows[7].t = NAN;
    assert_int_equal(hp_horizon_rates(&c->sc.layout, &hs, c->rows, c->T, delta, &d),
                     HP_ERR_INVALID);
    free(c);
}

/* A correction hp_plan refuses (outside the identifiable range, or beyond its caps) is refused
 * by every horizon planner before planning, with its line and hp_plan's words: greedy and
 * receding planned the trace with that row as invalid-input, and offline planned it as
 * closest (a 200 deg pitch), while solve and batch refuse it. */
static void test_rows_outside_the_request_range(void **st)
{
    (void)st;
    hf_case *c = hf_load("horizon/step.yaml", "step.csv", 10);
    assert_non_null(c);
    hp_horizon_settings hs = defaults();
    hp_horizon_row out[10];
    hp_diag d = {{0}};
    char want[96];
    /* hp_plan's own words for the row, from a planner of the same scene */
    hp_planner *p = NULL;
    assert_int_equal(hp_planner_create(&c->sc.layout, &c->s, &p, NULL), HP_OK);
    const double pitched[6] = {0, 0, 0, 200.0 * 3.14159265358979323846 / 180, 0, 0};
    const double far[6] = {0.2, 0, 0, 0, 0, 0};
    const double *bad[2] = {pitched, far};
    for (int b = 0; b < 2; ++b) {
        memcpy(c->rows[4].correction, bad[b], sizeof c->rows[4].correction);
        hp_result r;
        assert_int_equal(hp_plan(p, bad[b], &r), HP_OK);
        assert_int_equal(r.status, HP_STATUS_INVALID_INPUT);
        snprintf(want, sizeof want, "line %ld: %.40s", c->rows[4].line, hp_planner_error(p));
        size_t at = 99;
        assert_int_equal(hp_horizon_check_rows(&c->sc.layout, c->rows, c->T, &at, &d),
                         HP_ERR_INVALID);
        assert_int_equal(at, 4);
        assert_string_equal(d.text, hp_planner_error(p));
        for (int m = 0; m < 3; ++m) {
            hp_error e = m == 0 ? hp_horizon_greedy(&c->sc.layout, &c->s, &hs, c->rows, c->T, c->p0,
                                                    out, &d)
                         : m == 1 ? hp_horizon_receding(&c->sc.layout, &c->s, &hs, c->rows, c->T,
                                                        c->p0, out, &d)
                                  : hp_horizon_offline(&c->sc.layout, &c->s, &hs, c->rows, c->T,
                                                       c->p0, out, NULL, &d);
            if (e != HP_ERR_INVALID || strncmp(d.text, want, strlen(want)) != 0) {
                print_error("plan %d: %d '%s', want '%s'\n", m, e, d.text, want);
                fail();
            }
        }
    }
    hp_planner_destroy(p);
    free(c);
}

/* hp_planner_set_rate_max (hp_planner.h) lifting every limit after a tight one: the
 * next plan is the plan of a planner created without rate limits, to the bit (hp_plan no
 * longer sets the bounds of a rate-free planner, so lifting the limits must restore them).
 * Cold plans, so the previous answer enters only through the rate limits. */
static void test_rate_max_lifted(void **st)
{
    (void)st;
    hf_case *c = hf_load("horizon/drift_long.yaml", "drift_long.csv", 1);
    assert_non_null(c);
    const hp_layout *L = &c->sc.layout;
    hp_settings s = c->s;
    s.warm_start = 0;
    s.max_time = 60.0; /* no verdict may hang on the machine's speed */
    s.use_rate_limits = 1;
    hp_planner *p = NULL, *q = NULL;
    assert_int_equal(hp_planner_create(L, &s, &p, NULL), HP_OK);
    s.use_rate_limits = 0;
    assert_int_equal(hp_planner_create(L, &s, &q, NULL), HP_OK);
    const double target[6] = {0.006, -0.004, 0.003, 0.05, -0.03, 0.04};
    double tight[HP_MAX_BLADDERS], none[HP_MAX_BLADDERS], p0[HP_MAX_BLADDERS];
    assert_int_equal(hp_planner_nominal_pressures(p, p0), HP_OK);
    for (int k = 0; k < L->n; ++k) {
        tight[k] = 1.0; /* Pa */
        none[k] = INFINITY;
    }
    hp_result r1, r2, rq;
    assert_int_equal(hp_planner_set_rate_max(p, tight), HP_OK);
    assert_int_equal(hp_plan(p, target, &r1), HP_OK);
    for (int k = 0; k < L->n; ++k) assert_true(fabs(r1.bladders[k].pressure - p0[k]) <= 1.0 + 1e-9);
    assert_int_equal(hp_planner_set_rate_max(p, none), HP_OK);
    assert_int_equal(hp_plan(p, target, &r2), HP_OK);
    assert_int_equal(hp_plan(q, target, &rq), HP_OK);
    assert_int_equal(r2.status, rq.status);
    for (int k = 0; k < L->n; ++k)
        assert_memory_equal(&r2.bladders[k].pressure, &rq.bladders[k].pressure, sizeof(double));
    int moved = 0; /* the lifted plan left the tight window somewhere */
    for (int k = 0; k < L->n; ++k)
        moved |= fabs(r2.bladders[k].pressure - r1.bladders[k].pressure) > 10.0;
    assert_true(moved);
    hp_planner_destroy(p);
    hp_planner_destroy(q);
    free(c);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_offline_not_worse_step),
        cmocka_unit_test(test_per_second_irregular),
        cmocka_unit_test(test_windows_agree),
        cmocka_unit_test(test_receding_one_row_is_greedy),
        cmocka_unit_test(test_settings_checked),
        cmocka_unit_test(test_time_stamps_checked),
        cmocka_unit_test(test_rate_max_lifted),
        cmocka_unit_test(test_rows_outside_the_request_range),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
