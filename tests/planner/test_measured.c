/* Measured pressures fed back into a planner (hp_planner_set_measured):
 * - a noisy reading inside the limits is taken as it is (no bladder reported), and the
 *   planner's previous answer then holds exactly those pressures at the pose their forward
 *   model gives (hp_iab_fk, the volume law, hp_contact_fk from the nominal pose, within
 *   1e-7 m / 1e-6 rad);
 * - a reading beyond the pressures its bladder's limits allow (pressure and stretch) by at
 *   most HP_MEASURED_TOL_REL of p_max − p_min (a sensor's noise at a limit) is clamped onto
 *   the limit and reported in the mask, not refused;
 * - a reading beyond that, or not finite, is refused (HP_ERR_INVALID) with the bladder named
 *   in hp_planner_error, and nothing changes;
 * - the next plan's rate windows are centred on the taken pressures;
 * - in a control loop (a plan, its pressures read back with ±3 Pa of noise, and again) each
 *   reading's radii are the cold FK's of the reading (hp_iab_fk) to 2 ulps, and the FK,
 *   started from the previous answer, spends few closed-form evaluations (counted);
 * - a reading's radii and pose are derived only when something needs them: set_measured
 *   evaluates no bladder FK, a plan the direct chain answers none either, and a solve
 *   neither while the previous answer is a feasible start for the reading's windows; plans
 *   are bit for bit what they are when the reading is derived at once wherever the start
 *   is the same, and otherwise exact in their limits and windows, confirmed by the forward
 *   model and no farther from the desired pose beyond the pose tolerance;
 * - a reading that cannot be derived is dropped when a plan first needs it. */
#include "support/test_util.h"
#include "support/layout_fixture.h"
#include "support/load_fixture.h"
#include "support/same_result.h"
#include "planner/planner_internal.h"
#include "planner/clock.h"

static hp_planner *planner(hp_level level, double rate)
{
    hp_planner *p = NULL;
    assert_int_equal(lf_planner(level, rate, &p), HP_OK);
    return p;
}

/* The pressures of a plan of mm_deg (reached or closest); returns 1 when no limit binds. */
static int pressures_of(hp_planner *p, const double mm_deg[6], double *P)
{
    double d[6];
    hp_result r;
    lf_pose(mm_deg, d);
    assert_int_equal(hp_plan(p, d, &r), HP_OK);
    assert_true(r.status == HP_STATUS_REACHED || r.status == HP_STATUS_CLOSEST);
    unsigned any = 0;
    for (int k = 0; k < r.n; ++k) P[k] = r.bladders[k].pressure, any |= r.bladders[k].binding;
    return any == 0;
}

/* The previous answer (the safe output of a plan refused at once: a NaN request). */
static void previous(hp_planner *p, hp_result *r)
{
    double bad[6] = {NAN, 0, 0, 0, 0, 0};
    assert_int_equal(hp_plan(p, bad, r), HP_OK);
    assert_int_equal(r->status, HP_STATUS_INVALID_INPUT);
}

static void test_noisy_readings(void **state)
{
    (void)state;
    const hp_level levels[] = {HP_LEVEL_LINEAR, HP_LEVEL_PLANE, HP_LEVEL_SURFACE};
    uint64_t seed = 0x3ea5;
    for (int l = 0; l < 3; ++l) {
        hp_planner *p = planner(levels[l], INFINITY);
        const hp_layout *L = hp_planner_layout(p);
        int noisy = 0;
        for (int t = 0; t < 20; ++t) {
            double mm_deg[6], P[HP_MAX_BLADDERS];
            for (int i = 0; i < 6; ++i) mm_deg[i] = 1.5 * lf_uniform(&seed);
            if (!pressures_of(p, mm_deg, P)) continue; /* noise at a limit: the next test */
            ++noisy;
            for (int k = 0; k < L->n; ++k) P[k] += 5.0 * lf_uniform(&seed); /* ±5 Pa noise */
            unsigned clamped = 99;
            assert_int_equal(hp_planner_set_measured(p, P, &clamped), HP_OK);
            assert_int_equal(clamped, 0);
            hp_result r;
            previous(p, &r);
            for (int k = 0; k < L->n; ++k) assert_true(r.bladders[k].pressure == P[k]);
            double xi[6];
            assert_int_equal(lf_round_trip(L, levels[l], &r, xi), HP_OK);
            for (int i = 0; i < 6; ++i)
                hp_assert_close(xi[i], r.achieved[i], 0, i < 3 ? 1e-7 : 1e-6);
        }
        assert_true(noisy >= 10);
        hp_planner_destroy(p);
    }
}

static void test_readings_at_and_beyond_limits(void **state)
{
    (void)state;
    hp_planner *p = planner(HP_LEVEL_SURFACE, 500.0);
    const hp_layout *L = hp_planner_layout(p);
    double P[HP_MAX_BLADDERS];
    const double zero[6] = {0};
    pressures_of(p, zero, P);
    const hp_bladder *B = &L->bladders[2];
    double tol = HP_MEASURED_TOL_REL * (B->p_max - B->p_min);
    /* The highest pressure the bladder's limits allow: here its stretch limit's (5.8 kPa,
     * below p_max 10 kPa), the pressure of stretch_max·Ri. */
    double p_top;
    assert_int_equal(hp_iab_ik(&B->iab, B->stretch_max * B->iab.Ri, &p_top), HP_OK);
    p_top = fmin(p_top, B->p_max);

    /* A hair above it (half the tolerance): clamped onto the limit, reported. */
    double Q[HP_MAX_BLADDERS];
    memcpy(Q, P, sizeof Q);
    Q[2] = p_top + 0.5 * tol;
    unsigned clamped = 0;
    /* The reading's pose need not be near the nominal: the limit is far from it. */
    hp_error e = hp_planner_set_measured(p, Q, &clamped);
    assert_int_equal(e, HP_OK);
    assert_int_equal(clamped, 1u << 2);
    hp_result r;
    previous(p, &r);
    assert_true(r.bladders[2].pressure <= p_top);
    hp_assert_close(r.bladders[2].pressure, p_top, 1e-9, 0);
    assert_true(r.bladders[3].pressure == Q[3]);

    /* The next plan's windows are centred there: no pressure moves more than the rate. */
    double d[6];
    lf_pose((const double[6]){0.5, 0, 0, 0, 0, 0}, d);
    hp_result a;
    assert_int_equal(hp_plan(p, d, &a), HP_OK);
    for (int k = 0; k < a.n; ++k)
        assert_true(fabs(a.bladders[k].pressure - r.bladders[k].pressure) <= 500.0);

    /* A hair below p_min on another bladder: clamped too. */
    memcpy(Q, P, sizeof Q);
    Q[5] = L->bladders[5].p_min - 0.9 * tol;
    assert_int_equal(hp_planner_set_measured(p, Q, &clamped), HP_OK);
    assert_int_equal(clamped, 1u << 5);

    /* Beyond the tolerance, or not finite: refused, the bladder named, nothing changed. */
    hp_result before;
    previous(p, &before);
    const double far[3] = {p_top + 2.0 * tol, NAN, INFINITY};
    for (int j = 0; j < 3; ++j) {
        memcpy(Q, P, sizeof Q);
        Q[2] = far[j];
        clamped = 7;
        assert_int_equal(hp_planner_set_measured(p, Q, &clamped), HP_ERR_INVALID);
        assert_non_null(strstr(hp_planner_error(p), B->name));
        assert_non_null(strstr(hp_planner_error(p), "set_measured"));
        hp_result after;
        previous(p, &after);
        for (int k = 0; k < after.n; ++k)
            assert_true(after.bladders[k].pressure == before.bladders[k].pressure);
    }
    assert_int_equal(hp_planner_set_measured(p, NULL, &clamped), HP_ERR_NULL);
    hp_planner_destroy(p);
}

/* The load level reads a measurement against its own pressure bounds
 * (hp_planner_pressure_bounds), with the same clamp, report and refusal. */
static void test_load_level_readings(void **state)
{
    (void)state;
    hp_layout L;
    assert_int_equal(lf_layout(&L), HP_OK);
    hp_load_spec spec;
    hp_load_spec_default(&L.head, &spec);
    spec.law = HP_LOAD_LAW_CAP; /* the default bladders carry the head under the cap law only */
    spec.mass *= 0.2;           /* light enough for the layout to carry */
    hp_planner *p = NULL;
    hp_diag d = {{0}};
    assert_int_equal(load_create(&L, &spec, NULL, HP_TIE_LEAST_SQUEEZE, &p, &d), HP_OK);
    const double zero[6] = {0};
    hp_result r;
    assert_int_equal(hp_plan(p, zero, &r), HP_OK);
    assert_true(r.status == HP_STATUS_REACHED || r.status == HP_STATUS_CLOSEST);
    double lo[HP_MAX_BLADDERS], hi[HP_MAX_BLADDERS], Q[HP_MAX_BLADDERS];
    assert_int_equal(hp_planner_pressure_bounds(p, lo, hi), HP_OK);
    for (int k = 0; k < r.n; ++k) Q[k] = r.bladders[k].pressure;
    const hp_bladder *B = &L.bladders[2];
    double tol = HP_MEASURED_TOL_REL * (B->p_max - B->p_min);
    /* Half the tolerance above the load level's upper bound: clamped, reported. */
    Q[2] = hi[2] + 0.5 * tol;
    unsigned clamped = 0;
    assert_int_equal(hp_planner_set_measured(p, Q, &clamped), HP_OK);
    assert_int_equal(clamped, 1u << 2);
    /* Twice the tolerance above: refused, the bladder named, the mask untouched. */
    Q[2] = hi[2] + 2.0 * tol;
    clamped = 77u;
    assert_int_equal(hp_planner_set_measured(p, Q, &clamped), HP_ERR_INVALID);
    assert_int_equal(clamped, 77u);
    assert_non_null(strstr(hp_planner_error(p), B->name));
    hp_planner_destroy(p);
}

/* The loop of the loop benchmark's measured mode at every level: a seeded target held for
 * 40 cycles, then another (rate limits of 500 Pa a plan bind on the way), each plan's
 * pressures read back with ±3 Pa of noise. Every reading inside the limits (clamped ones
 * apart) gives the radii of the cold FK of the reading (hp_iab_fk, no start) within 2 ulps
 * (the root to rounding: the start changes the steps only), and the FK evaluations per
 * bladder, spent when the safe output asks for the reading's radii, are counted (hpi_test_measured_fk_evals; a function of the seeded loop alone). */
static void test_loop_readings(void **state)
{
    (void)state;
    const hp_level levels[] = {HP_LEVEL_LINEAR, HP_LEVEL_PLANE, HP_LEVEL_SURFACE};
    uint64_t seed = 0x10097;
    unsigned long evals = 0, fks = 0;
    long worst = 0, checked = 0;
    for (int l = 0; l < 3; ++l) {
        hp_planner *p = planner(levels[l], 500.0);
        const hp_layout *L = hp_planner_layout(p);
        double mm_deg[6] = {0}, d[6];
        for (int t = 0; t < 400; ++t) {
            if (t % 40 == 0)
                for (int i = 0; i < 6; ++i) mm_deg[i] = (i < 3 ? 3.0 : 2.0) * lf_uniform(&seed);
            lf_pose(mm_deg, d);
            hp_result r;
            assert_int_equal(hp_plan(p, d, &r), HP_OK);
            double P[HP_MAX_BLADDERS];
            for (int k = 0; k < L->n; ++k) P[k] = r.bladders[k].pressure + 3.0 * lf_uniform(&seed);
            unsigned clamped = 0;
            unsigned long e0 = hpi_test_measured_fk_evals();
            assert_int_equal(hp_planner_set_measured(p, P, &clamped), HP_OK);
            previous(p, &r); /* derives the reading's radii */
            evals += hpi_test_measured_fk_evals() - e0;
            fks += (unsigned long)L->n;
            for (int k = 0; k < L->n; ++k) {
                if (clamped & (1u << k)) continue;
                double cold;
                assert_int_equal(hp_iab_fk(&L->bladders[k].iab, P[k], &cold), HP_OK);
                long u = hp_test_ulps_apart(r.bladders[k].ri, cold);
                worst = u > worst ? u : worst;
                ++checked;
            }
        }
        hp_planner_destroy(p);
    }
    double per_fk = (double)evals / (double)fks;
    print_message("loop readings: %ld radii checked, at most %ld ulps from the cold FK; %.2f "
                  "evaluations per bladder FK\n",
                  checked, worst, per_fk);
    assert_true(worst <= 2);
    assert_true(per_fk <= 3.5);
}

/* One cycle's reading: the plan's pressures with ±3 Pa of noise, except that a bladder the
 * plan left on one of its static bounds reads half the tolerance beyond it, as a sensor at
 * a limit reads (clamped and reported). */
static void reading(hp_planner *p, const hp_result *r, uint64_t *seed, double *P)
{
    const hp_layout *L = hp_planner_layout(p);
    double lo[HP_MAX_BLADDERS], hi[HP_MAX_BLADDERS];
    assert_int_equal(hp_planner_pressure_bounds(p, lo, hi), HP_OK);
    for (int k = 0; k < L->n; ++k) {
        double tol = HP_MEASURED_TOL_REL * (L->bladders[k].p_max - L->bladders[k].p_min);
        P[k] = r->bladders[k].pressure + 3.0 * lf_uniform(seed);
        if (r->bladders[k].pressure == hi[k]) P[k] = hi[k] + 0.5 * tol;
        if (r->bladders[k].pressure == lo[k]) P[k] = lo[k] - 0.5 * tol;
    }
}

/* A reading's radii and pose are derived only when a plan truly needs them. Two planners
 * run the same loop at every contact level (a seeded target held 30 cycles, then another,
 * so that the 500 Pa rate limits bind; noisy readings, some a hair beyond a limit, every
 * fifth cycle a second reading before the plan): "eager" asks for its previous answer
 * right after each reading (the safe output of a refused plan, which needs the radii and
 * pose then: the derivation at once, and every solve starts from the reading's answer),
 * "lazy" plans at once. The lazy planner's solves start from its previous answer whenever
 * that answer's pressures lie inside the reading's rate windows and limits (a pressure-space
 * test), which the readings here (±3 Pa of noise around it, 500 Pa windows) always leave:
 * no plan of it derives a reading (counted), and set_measured derives none unless a
 * reading no plan used is still underived (the second reading: the first one's radii start
 * the second's FK). Where the start is the same (the direct chain, every plan before the
 * first solve from the previous answer) the two plans are the same bits, clamp reports
 * too. Every lazy answer is reached or closest, its pressures inside their limits and the
 * reading's rate windows to the last bit, the forward model gives its pose back (the FK of
 * its pressures, the contact fit from the nominal pose: 1e-7 m / 1e-6 rad, as for a
 * reading), and its pose error is never larger than the eager plan's by more than the
 * pose tolerance (settings.tolerance, 1e-9 mm/deg): a start is only a start, both solves
 * stop where a step is below a thousandth of it, and a reached answer is within it. */
static void test_lazy_readings_warm_from_answer(void **state)
{
    (void)state;
    const hp_level levels[] = {HP_LEVEL_LINEAR, HP_LEVEL_PLANE, HP_LEVEL_SURFACE};
    for (int l = 0; l < 3; ++l) {
        hp_planner *eager = planner(levels[l], 500.0), *lazy = planner(levels[l], 500.0);
        const hp_layout *L = hp_planner_layout(lazy);
        double lo[HP_MAX_BLADDERS], hi[HP_MAX_BLADDERS], centre[HP_MAX_BLADDERS];
        assert_int_equal(hp_planner_pressure_bounds(lazy, lo, hi), HP_OK);
        hp_result re, rl;
        previous(lazy, &rl);
        for (int k = 0; k < L->n; ++k) centre[k] = rl.bladders[k].pressure;
        uint64_t seed = 0x1a2b + (uint64_t)l;
        double mm_deg[6] = {0}, d[6], worse = 0.0;
        long direct = 0, none_in_set = 0, solved = 0, derived = 0, clamped_n = 0, same = 0,
             differ = 0;
        int same_hist = 1; /* every answer so far the same bits in both planners */
        unsigned long set_evals = 0, direct_evals = 0;
        for (int t = 0; t < 240; ++t) {
            if (t % 30 == 0)
                for (int i = 0; i < 6; ++i) mm_deg[i] = (i < 3 ? 3.0 : 2.0) * lf_uniform(&seed);
            lf_pose(mm_deg, d);
            assert_int_equal(hp_plan(eager, d, &re), HP_OK);
            unsigned long e0 = hpi_test_measured_fk_evals();
            assert_int_equal(hp_plan(lazy, d, &rl), HP_OK);
            unsigned long plan_evals = hpi_test_measured_fk_evals() - e0;
            unsigned binding = 0;
            for (int k = 0; k < rl.n; ++k) binding |= rl.bladders[k].binding;
            int is_direct = rl.status == HP_STATUS_REACHED && rl.iterations == 0 && !binding;
            if (is_direct) {
                ++direct;
                direct_evals += plan_evals;
            } else {
                ++solved;
                derived += plan_evals > 0;
            }
            int bits = hp_test_same_result(&re, &rl);
            if (same_hist && (is_direct || plan_evals > 0) && !bits)
                fail_msg("%s cycle %d: the same start, different plans (status %s / %s)",
                         hp_level_name(levels[l]), t, hp_status_name(re.status),
                         hp_status_name(rl.status));
            same += bits;
            differ += !bits;
            same_hist &= bits;
            if (!(rl.status == HP_STATUS_REACHED || rl.status == HP_STATUS_CLOSEST))
                fail_msg("%s cycle %d: status %s (%s)", hp_level_name(levels[l]), t,
                         hp_status_name(rl.status), hp_planner_message(lazy));
            for (int k = 0; k < rl.n; ++k) {
                double a = rl.bladders[k].pressure, wl, wh;
                hpi_rate_window(centre[k], L->bladders[k].rate_max, &wl, &wh);
                if (!(a >= lo[k] && a <= hi[k] && a >= wl && a <= wh))
                    fail_msg("%s cycle %d: bladder %d pressure %.17g outside [%.17g, %.17g] or "
                             "its window [%.17g, %.17g]",
                             hp_level_name(levels[l]), t, k, a, lo[k], hi[k], wl, wh);
            }
            double xi[6];
            assert_int_equal(lf_round_trip(L, levels[l], &rl, xi), HP_OK);
            for (int i = 0; i < 6; ++i)
                hp_assert_close(xi[i], rl.achieved[i], 0, i < 3 ? 1e-7 : 1e-6);
            worse = fmax(worse, rl.pose_error - re.pose_error);
            if (!(rl.pose_error <= re.pose_error + HP_DEFAULT_TOLERANCE))
                fail_msg("%s cycle %d: pose error %.17g, derive-first %.17g",
                         hp_level_name(levels[l]), t, rl.pose_error, re.pose_error);
            for (int twice = 0; twice < 1 + (t % 5 == 4); ++twice) {
                double P[HP_MAX_BLADDERS];
                reading(lazy, &rl, &seed, P);
                unsigned ce = 0, cl = 0;
                assert_int_equal(hp_planner_set_measured(eager, P, &ce), HP_OK);
                previous(eager, &re);
                e0 = hpi_test_measured_fk_evals();
                assert_int_equal(hp_planner_set_measured(lazy, P, &cl), HP_OK);
                unsigned long ev = hpi_test_measured_fk_evals() - e0;
                if (same_hist) assert_int_equal(ce, cl);
                clamped_n += cl != 0;
                for (int k = 0; k < L->n; ++k) centre[k] = fmin(fmax(P[k], lo[k]), hi[k]);
                if (!twice) {
                    set_evals += ev;
                    none_in_set += ev == 0;
                } else {
                    assert_true(ev > 0); /* the first reading derived now, from its start */
                }
            }
        }
        hp_result pe, pl;
        previous(eager, &pe);
        previous(lazy, &pl);
        if (same_hist) assert_true(hp_test_same_result(&pe, &pl));
        for (int k = 0; k < L->n; ++k) assert_true(pl.bladders[k].pressure == centre[k]);
        print_message("%s: %ld direct plans (%lu FK evaluations in them), %ld solved (%ld "
                      "derived a reading), %ld plans the same bits as derive-first, %ld not "
                      "(pose error worse by at most %.3g mm/deg), %ld readings clamped, %lu FK "
                      "evaluations in set_measured (%ld of 240 readings none)\n",
                      hp_level_name(levels[l]), direct, direct_evals, solved, derived, same, differ,
                      worse, clamped_n, set_evals, none_in_set);
        assert_true(set_evals == 0);
        assert_true(direct_evals == 0);
        assert_true(derived == 0);
        assert_true(direct >= 60); /* the loop exercises both kinds of plan */
        assert_true(solved >= 10);
        assert_true(clamped_n >= 20);
        hp_planner_destroy(eager);
        hp_planner_destroy(lazy);
    }
}

/* After a plan stopped by its time budget, the next solve of a backend that is not
 * real-time derives the reading (where the bladders are, which carries the cycles'
 * progress) rather than starting from the stored iterate: started from the iterate, NLopt
 * SLSQP in the loop benchmark's deadline mode (20 us) ran out of time on 1 659 of 3 000
 * noisy-trace plans at the linear level, against 147 when it starts from the reading. The
 * realtime backend starts from its iterate when the iterate lies inside the reading's
 * windows, as from any answer of its own: the derivation, a fit before the solve's budget
 * begins, made the plans after a time-limit overrun it (docs/control-loop.md, A time budget
 * that holds). A 1 ns budget on the test clock (hpi_test_plan_clock: 1 us a reading) makes
 * every realtime solve stop by time, whatever the machine's clock or load, and NLopt's own
 * clock is past 1 ns at its first check; counted: the derivations (FK evaluations of
 * hpi_plan_previous_from) in the plan after each reading. */
static void reading_after_time_limit(hp_backend backend, int want_derived)
{
    static const double far[][6] = {
        {30, 0, 0, 0, 0, 0}, {0, -25, 0, 0, 0, 0}, {0, 0, 20, 10, 0, 0}, {12, 8, -9, 6, -7, 5}};
    hp_settings s;
    hp_settings_default(&s);
    s.backend = backend;
    s.level = HP_LEVEL_PLANE;
    s.max_time = 1e-9;
    hp_planner *p = NULL;
    assert_int_equal(lf_planner_settings(&s, 500.0, &p), HP_OK);
    hpi_test_plan_clock(1e-6); /* every reading moves 1 us: the budget is past at its check */
    const int n = hp_planner_layout(p)->n;
    int after_budget = 0;
    for (int t = 0; t < 4; ++t) {
        double d[6], P[HP_MAX_BLADDERS];
        hp_result r;
        lf_pose(far[t], d);
        assert_int_equal(hp_plan(p, d, &r), HP_OK);
        if (p->prev.status != HP_STATUS_TIME_LIMIT) continue; /* a safe output: no iterate */
        for (int k = 0; k < n; ++k) P[k] = r.bladders[k].pressure + (k % 2 ? 2.0 : -2.0);
        assert_int_equal(hp_planner_set_measured(p, P, NULL), HP_OK);
        lf_pose(far[(t + 1) % 4], d);
        unsigned long e0 = hpi_test_measured_fk_evals();
        assert_int_equal(hp_plan(p, d, &r), HP_OK);
        if ((hpi_test_measured_fk_evals() > e0) != want_derived)
            fail_msg("%s, target %d: the reading after a budget's iterate was %sderived",
                     hp_backend_name(backend), t, want_derived ? "not " : "");
        ++after_budget;
    }
    print_message("%s: %d plans after a budget's iterate, each %s its reading\n",
                  hp_backend_name(backend), after_budget,
                  want_derived ? "deriving" : "starting from the iterate, not deriving");
    hpi_test_plan_clock(0.0);
    assert_true(after_budget >= 1);
    hp_planner_destroy(p);
}

static void test_reading_after_time_limit(void **state)
{
    (void)state;
    reading_after_time_limit(HP_BACKEND_NLOPT_SLSQP, 1);
    reading_after_time_limit(HP_BACKEND_REALTIME, 0);
}

/* A reading whose radii or pose cannot be derived (forced by the test hook, as one with no
 * stable radius or no pose) is dropped when a plan first needs it: that plan returns
 * INVALID_INPUT with the answer before the reading as its safe output, bit for bit, and the
 * reading named after the plan's own cause; the next plan's windows are centred on that
 * answer's pressures again. A plan the direct chain answers needs no derivation, so it is
 * answered even then. */
static void test_reading_dropped(void **state)
{
    (void)state;
    hp_planner *p = planner(HP_LEVEL_PLANE, 500.0);
    const hp_layout *L = hp_planner_layout(p);
    double d[6], P[HP_MAX_BLADDERS];
    hp_result r0, r, q;
    lf_pose((const double[6]){0.3, 0, 0, 0, 0, 0}, d);
    assert_int_equal(hp_plan(p, d, &r0), HP_OK);
    assert_int_equal(r0.status, HP_STATUS_REACHED);
    /* A reading 600 Pa from the answer: outside the reading's 500 Pa windows, so the answer
     * is no start for a solve, which derives the reading to start from its answer. */
    for (int k = 0; k < L->n; ++k) P[k] = r0.bladders[k].pressure + 600.0;
    /* A far correction: the solver runs. */
    assert_int_equal(hp_planner_set_measured(p, P, NULL), HP_OK);
    hpi_test_measured_refuse(1);
    lf_pose((const double[6]){4.0, 0, 0, 3.0, 0, 0}, d);
    assert_int_equal(hp_plan(p, d, &r), HP_OK);
    assert_int_equal(r.status, HP_STATUS_INVALID_INPUT);
    assert_non_null(strstr(hp_planner_error(p), "the reading is dropped"));
    for (int k = 0; k < L->n; ++k) {
        assert_true(r.bladders[k].pressure == r0.bladders[k].pressure);
        assert_true(r.bladders[k].ri == r0.bladders[k].ri);
    }
    assert_memory_equal(r.achieved, r0.achieved, sizeof r.achieved);
    /* The safe output of a refused request: the plan's cause first, then the reading. */
    assert_int_equal(hp_planner_set_measured(p, P, NULL), HP_OK);
    previous(p, &q);
    assert_non_null(strstr(hp_planner_error(p), "desired"));
    assert_non_null(strstr(hp_planner_error(p), "; set_measured: "));
    for (int k = 0; k < L->n; ++k) assert_true(q.bladders[k].pressure == r0.bladders[k].pressure);
    /* A direct answer needs no derivation: reached, from the windows of a reading near the
     * answer (the direct chain's pressures lie inside them). */
    double Pn[HP_MAX_BLADDERS];
    for (int k = 0; k < L->n; ++k) Pn[k] = r0.bladders[k].pressure + 2.0;
    assert_int_equal(hp_planner_set_measured(p, Pn, NULL), HP_OK);
    lf_pose((const double[6]){0.31, 0, 0, 0, 0, 0}, d);
    assert_int_equal(hp_plan(p, d, &r), HP_OK);
    assert_int_equal(r.status, HP_STATUS_REACHED);
    hpi_test_measured_refuse(0);
    /* A far reading dropped after that direct answer: the windows are centred on the answer
     * again, so a far plan moves no pressure more than 500 Pa from it. */
    assert_int_equal(hp_planner_set_measured(p, P, NULL), HP_OK);
    hpi_test_measured_refuse(1);
    lf_pose((const double[6]){4.0, 0, 0, 3.0, 0, 0}, d);
    assert_int_equal(hp_plan(p, d, &q), HP_OK);
    hpi_test_measured_refuse(0);
    assert_int_equal(q.status, HP_STATUS_INVALID_INPUT);
    assert_int_equal(hp_plan(p, d, &q), HP_OK);
    assert_true(q.status == HP_STATUS_CLOSEST || q.status == HP_STATUS_REACHED);
    for (int k = 0; k < L->n; ++k)
        assert_true(fabs(q.bladders[k].pressure - r.bladders[k].pressure) <= 500.0);
    hp_planner_destroy(p);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_noisy_readings),
        cmocka_unit_test(test_readings_at_and_beyond_limits),
        cmocka_unit_test(test_load_level_readings),
        cmocka_unit_test(test_loop_readings),
        cmocka_unit_test(test_lazy_readings_warm_from_answer),
        cmocka_unit_test(test_reading_after_time_limit),
        cmocka_unit_test(test_reading_dropped),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
