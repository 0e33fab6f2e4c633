/* A horizon plan's row statuses mean what hp_plan's mean: reached = the commanded part of the
 * row's own desired pose is met to the tolerance; closest = it is not, because a limit binds;
 * uncommanded = only the part the layout cannot observe is missed. Each row is classified
 * here from the plan's output alone: its pose against the commanded part of its desired
 * pose (hp_pose_commanded_part), and the limits recomputed from its pressures. */
#include "support/test_util.h"
#include "tests/horizon/horizon_fixture.h"
#include "horizon/horizon_internal.h"

/* 1 when some bladder of row t sits on a limit: a pressure bound, or a rate allowance
 * min(rate_max, rate_max_per_s·dt) used to within 1e-2 Pa (hp_plan's binding tolerance is
 * 1e-6 mm of outer radius, a few mPa of pressure here), or a stretch bound to 1e-9. */
static int binds(const hf_case *c, const hp_horizon_settings *hs, const hp_horizon_row *o, size_t t)
{
    double dt = t ? c->rows[t].t - c->rows[t - 1].t : hs->start_interval_s;
    for (int k = 0; k < c->sc.layout.n; ++k) {
        const hp_bladder *B = &c->sc.layout.bladders[k];
        double P = o[t].pressure[k], prev = t ? o[t - 1].pressure[k] : c->p0[k];
        double s = o[t].ri[k] / B->iab.Ri;
        if (P <= B->p_min + 1e-2 || P >= B->p_max - 1e-2 || s <= B->stretch_min + 1e-9 ||
            s >= B->stretch_max - 1e-9 ||
            fabs(P - prev) >= fmin(B->rate_max, hs->rate_max_per_s * dt) - 1e-2)
            return 1;
    }
    return 0;
}

/* Checks every row's status against the classification above, to the tolerance tol (mm or
 * degrees); with need_bind a closest row must bind a limit of its own (greedy and receding
 * with hold; the offline plan also leaves rows early for a limit ahead). Returns the counts
 * of reached, closest and uncommanded rows in n[0..2]. */
static void check_labels(const hf_case *c, const hp_horizon_settings *hs, const hp_horizon_row *o,
                         const char *name, double tol, int need_bind, int n[3])
{
    hp_planner *p = NULL;
    assert_int_equal(hp_planner_create(&c->sc.layout, &c->s, &p, NULL), HP_OK);
    const hp_identifiable *id = hp_planner_identifiable(p);
    n[0] = n[1] = n[2] = 0;
    for (size_t t = 0; t < c->T; ++t) {
        double xc[6], err = 0, unc = 0;
        assert_int_equal(hp_pose_commanded_part(&c->sc.layout, id, hp_planner_level(p),
                                                c->rows[t].correction, xc),
                         HP_OK);
        for (int i = 0; i < 6; ++i) {
            double s = i < 3 ? 1e3 : 57.295779513082320877;
            if (id->commanded[i]) err = fmax(err, fabs(o[t].achieved[i] - xc[i]) * s);
            unc = fmax(unc, fabs(c->rows[t].correction[i] - xc[i]) * s);
        }
        hp_status want = err <= tol ? (unc > tol ? HP_STATUS_UNCOMMANDED : HP_STATUS_REACHED)
                                    : HP_STATUS_CLOSEST;
        int ok = o[t].status == want &&
                 (want != HP_STATUS_CLOSEST || !need_bind || binds(c, hs, o, t));
        if (!ok) {
            print_error("%s: line %ld: status %s, want %s (commanded error %.3g, uncommanded "
                        "%.3g, a limit binds: %d)\n",
                        name, c->rows[t].line, hp_status_name(o[t].status), hp_status_name(want),
                        err, unc, binds(c, hs, o, t));
            fail();
        }
        n[want == HP_STATUS_REACHED ? 0 : want == HP_STATUS_CLOSEST ? 1 : 2]++;
    }
    hp_planner_destroy(p);
}

/* The rate-limited step trace, receding with hold and with velocity: rows far inside the
 * tolerance with nothing binding were all called closest (every row of the trace). */
static void test_receding_step(void **st)
{
    (void)st;
    hf_case *c = hf_load("horizon/step.yaml", "step.csv", 150);
    assert_non_null(c);
    hp_horizon_settings hs;
    hp_horizon_settings_default(&hs);
    hp_horizon_row *o = calloc(c->T, sizeof *o);
    hp_diag d = {{0}};
    for (int pr = 0; pr < 2; ++pr) {
        hs.prediction = pr ? HP_PREDICT_VELOCITY : HP_PREDICT_HOLD;
        assert_int_equal(
            hp_horizon_receding(&c->sc.layout, &c->s, &hs, c->rows, c->T, c->p0, o, &d), HP_OK);
        int n[3];
        check_labels(c, &hs, o, pr ? "receding velocity" : "receding hold", c->s.tolerance, 1, n);
        print_message("%s: %d reached, %d closest\n", pr ? "velocity" : "hold", n[0], n[1]);
        assert_true(n[0] > 0 && n[1] > 0); /* both kinds occur: the test can tell them apart */
    }
    free(o);
    free(c);
}

/* A sphere head turned about a pivot 70 mm below its centre: the layout commands x, y, z
 * only, a pitch moves the centre (its commanded part) and leaves a part it cannot observe.
 * Receding with a rate limit that binds for the first rows: rows that miss the commanded part
 * are closest, never uncommanded; once it is met they are uncommanded. */
static void test_receding_uncommanded(void **st)
{
    (void)st;
    hf_case *c = hf_load("sphere_head.yaml", "step.csv", 40);
    assert_non_null(c);
    c->sc.layout.pivot[2] = -0.070;
    for (size_t t = 0; t < c->T; ++t) {
        const double want[6] = {0.0005, 0, 0, 1.0 * 3.14159265358979323846 / 180, 0, 0};
        memcpy(c->rows[t].correction, want, sizeof want);
    }
    assert_int_equal(hp_horizon_nominal_pressures(&c->sc.layout, c->p0, NULL), HP_OK);
    hp_horizon_settings hs;
    hp_horizon_settings_default(&hs);
    hs.rate_max_per_s = 2500.0;
    hp_horizon_row *o = calloc(c->T, sizeof *o);
    hp_diag d = {{0}};
    assert_int_equal(hp_horizon_receding(&c->sc.layout, &c->s, &hs, c->rows, c->T, c->p0, o, &d),
                     HP_OK);
    int n[3];
    check_labels(c, &hs, o, "receding sphere", c->s.tolerance, 1, n);
    print_message("sphere, receding: %d closest, %d uncommanded\n", n[1], n[2]);
    assert_true(n[1] > 0 && n[2] > 0);
    /* The offline plan aims at the same commanded parts and labels its rows the same way, to
     * its solve's accuracy (1e-6 mm / degree); before, it aimed at the raw components (a
     * pose 1.2 mm away from the commanded part here) and called its rows reached. */
    hp_horizon_info info;
    assert_int_equal(
        hp_horizon_offline(&c->sc.layout, &c->s, &hs, c->rows, c->T, c->p0, o, &info, &d), HP_OK);
    check_labels(c, &hs, o, "offline sphere", fmax(c->s.tolerance, 1e-6), 0, n);
    print_message("sphere, offline: %d closest, %d uncommanded\n", n[1], n[2]);
    assert_true(n[2] > 0);
    free(o);
    free(c);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_receding_step),
        cmocka_unit_test(test_receding_uncommanded),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
