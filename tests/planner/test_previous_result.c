/* hp_planner_set_previous_result: the state before a plan as a function of a previous
 * result's fields alone (headplan batch sets every row's state this way, docs/batch.md).
 *   - every field it reads is checked: each refusal names the field (and bladder), returns
 *     HP_ERR_INVALID and changes nothing;
 *   - the state does not depend on history: after any other plans, the same result gives
 *     the next plan bit for bit;
 *   - it is the state a sequential warm run has after that result: the next plan is the
 *     same bit for bit after a direct-chain answer, and the same answer to the solver's
 *     tolerance after a backend's answer (whose multipliers the sequential run keeps);
 *   - every answer of hp_plan passes the full checks, which the call skips for the
 *     planner's own last answer. */
#include "support/test_util.h"
#include "support/layout_fixture.h"
#include "support/load_fixture.h"
#include "common/units.h"
#include "support/ident_layouts.h"
#include "support/spd.h"

/* Every field of a result that hp_plan computes, solve_time excluded (a measurement). */
static void same_result(const hp_result *a, const hp_result *b, int row)
{
    int same = a->status == b->status && a->raw_code == b->raw_code &&
               a->iterations == b->iterations && a->n == b->n &&
               memcmp(a->achieved, b->achieved, sizeof a->achieved) == 0 &&
               memcmp(a->uncommanded, b->uncommanded, sizeof a->uncommanded) == 0 &&
               memcmp(&a->pose_error, &b->pose_error, sizeof a->pose_error) == 0;
    for (int k = 0; same && k < a->n; ++k) {
        const hp_bladder_result *x = &a->bladders[k], *y = &b->bladders[k];
        same = memcmp(&x->ri, &y->ri, sizeof x->ri) == 0 &&
               memcmp(&x->ro, &y->ro, sizeof x->ro) == 0 &&
               memcmp(&x->pressure, &y->pressure, sizeof x->pressure) == 0 &&
               memcmp(&x->stretch, &y->stretch, sizeof x->stretch) == 0 && x->binding == y->binding;
    }
    if (!same) fail_msg("row %d: results differ (status %d / %d)", row, a->status, b->status);
}

/* Row i of a drift that leaves the reachable set on about half its rows (the fixture's
 * limits bind beyond ~4 mm along this direction), SI. */
static void walk_row(int i, double d[6])
{
    double s = 4.0 * (1.0 + sin(i / 6.0));
    const double dir[6] = {1.0, 0.6, -0.75, 0.25, 0.1, -0.15}; /* mm and degrees */
    for (int j = 0; j < 6; ++j) d[j] = s * dir[j] / (j < 3 ? HP_MM_PER_M : HP_DEG_PER_RAD);
}

#define WALK_ROWS 80

static hp_planner *make(hp_level level, double rate_max)
{
    hp_planner *p = NULL;
    assert_int_equal(lf_planner(level, rate_max, &p), HP_OK);
    return p;
}

/* Plans the walk sequentially (plain hp_plan, warm) into seq[]. Returns how many rows a
 * backend answered. */
static int plan_sequential(hp_planner *p, hp_result *seq)
{
    int backend = 0;
    for (int i = 0; i < WALK_ROWS; ++i) {
        double d[6];
        walk_row(i, d);
        assert_int_equal(hp_plan(p, d, &seq[i]), HP_OK);
        assert_true(seq[i].status == HP_STATUS_REACHED || seq[i].status == HP_STATUS_CLOSEST);
        backend += seq[i].iterations > 0;
    }
    return backend;
}

/* Both halves of the claim at one level and rate limit: history independence (a second
 * planner that planned other corrections in between) and agreement with the sequential
 * warm run. */
static void check_level(hp_level level, double rate_max)
{
    hp_planner *seq_p = make(level, rate_max), *a = make(level, rate_max);
    hp_planner *b = make(level, rate_max);
    static hp_result seq[WALK_ROWS];
    int backend = plan_sequential(seq_p, seq);
    /* Both kinds of row occur, so both paths are exercised. */
    assert_true(backend >= 10 && backend <= WALK_ROWS - 10);
    double worst_mm = 0, worst_pa = 0;
    for (int i = 1; i < WALK_ROWS; ++i) {
        double d[6], other[6];
        walk_row(i, d);
        /* b first plans something unrelated (a far, binding correction: warm multipliers
         * and a different previous answer), a plans nothing else. */
        walk_row(i + 17, other);
        for (int j = 0; j < 6; ++j) other[j] = -other[j];
        hp_result ra, rb, junk;
        assert_int_equal(hp_plan(b, other, &junk), HP_OK);
        assert_int_equal(hp_planner_set_previous_result(a, &seq[i - 1]), HP_OK);
        assert_int_equal(hp_planner_set_previous_result(b, &seq[i - 1]), HP_OK);
        assert_int_equal(hp_plan(a, d, &ra), HP_OK);
        assert_int_equal(hp_plan(b, d, &rb), HP_OK);
        same_result(&ra, &rb, i);
        if (seq[i - 1].iterations == 0) {
            /* After a direct-chain answer the sequential run's state is exactly this one. */
            same_result(&ra, &seq[i], i);
            continue;
        }
        /* After a backend's answer the sequential run starts from the backend's own point
         * and multipliers: the same optimum, to the solver's tolerance (HP_DEFAULT_TOLERANCE,
         * 1e-9 mm/deg) on every outer radius and pose component, and 1e-9 relative on every
         * pressure (measured: 2.4e-13 and 2.9e-13). */
        assert_int_equal(ra.status, seq[i].status);
        for (int j = 0; j < 6; ++j) {
            double sc = j < 3 ? HP_MM_PER_M : HP_DEG_PER_RAD;
            worst_mm = fmax(worst_mm, fabs(ra.achieved[j] - seq[i].achieved[j]) * sc);
        }
        for (int k = 0; k < ra.n; ++k) {
            worst_mm = fmax(worst_mm, fabs(ra.bladders[k].ro - seq[i].bladders[k].ro) * 1e3);
            worst_pa = fmax(worst_pa, fabs(ra.bladders[k].pressure - seq[i].bladders[k].pressure) /
                                          fmax(1.0, fabs(seq[i].bladders[k].pressure)));
        }
    }
    print_message("level %s, rate_max %g: after backend rows, worst %.3g mm/deg, %.3g rel Pa\n",
                  hp_level_name(level), rate_max, worst_mm, worst_pa);
    assert_true(worst_mm <= HP_DEFAULT_TOLERANCE);
    assert_true(worst_pa <= 1e-9);
    hp_planner_destroy(seq_p);
    hp_planner_destroy(a);
    hp_planner_destroy(b);
}

static void test_linear(void **st)
{
    (void)st;
    check_level(HP_LEVEL_LINEAR, INFINITY);
    check_level(HP_LEVEL_LINEAR, 1500.0);
}

static void test_surface(void **st)
{
    (void)st;
    check_level(HP_LEVEL_SURFACE, INFINITY);
    check_level(HP_LEVEL_SURFACE, 1500.0);
}

/* An answer of the load walk, checked independently of the planner: its pressures inside
 * the static bounds and (rate < INFINITY, prev not NULL) inside the rate window around the
 * previous row's returned pressures, exactly (prev - rate <= P <= prev + rate as computed);
 * its pose a stable rest of those pressures: K from hp_load_eval's Jacobian positive
 * definite by Cholesky (tests/support/spd.h), and the forward statics started 0.01 mm /
 * 0.01° away (all six components) back within 1e-6 mm/deg of it (the reached claim's
 * tolerance of hp_planner.h). 1 when it passes, else 0 with the reason in why. */
static int load_row_ok(const hp_planner *p, const hp_result *r, const double *prev, double rate,
                       char *why, size_t len)
{
    const hp_load_model *M = hp_planner_load_model(p);
    double lo[HP_MAX_BLADDERS], hi[HP_MAX_BLADDERS], P[HP_MAX_BLADDERS];
    assert_int_equal(hp_planner_pressure_bounds(p, lo, hi), HP_OK);
    for (int k = 0; k < r->n; ++k) {
        P[k] = r->bladders[k].pressure;
        if (!(P[k] >= lo[k] && P[k] <= hi[k]) ||
            (prev && !(P[k] - prev[k] <= rate && prev[k] - P[k] <= rate))) {
            snprintf(why, len, "bladder %d: %.17g Pa outside its bounds or window", k, P[k]);
            return 0;
        }
    }
    double Q[6], dQ[36], K[36], x0[6], rest[6];
    assert_int_equal(hp_load_eval(M, r->achieved, P, Q, dQ, NULL, NULL, NULL), HP_OK);
    for (int i = 0; i < 6; ++i)
        for (int j = 0; j < 6; ++j)
            K[i * 6 + j] = -0.5 * (dQ[i * 6 + j] + dQ[j * 6 + i]) *
                           (i < 3 ? 1e-3 : HP_RAD_PER_DEG) * (j < 3 ? 1e-3 : HP_RAD_PER_DEG);
    if (!test_positive_definite6(K)) {
        snprintf(why, len, "%s, K not positive definite", hp_status_name(r->status));
        return 0;
    }
    for (int i = 0; i < 6; ++i) x0[i] = r->achieved[i] + 0.01 * (i < 3 ? 1e-3 : HP_RAD_PER_DEG);
    if (hp_load_rest(M, P, x0, rest, NULL) != HP_OK) {
        snprintf(why, len, "%s, no rest of its pressures", hp_status_name(r->status));
        return 0;
    }
    for (int i = 0; i < 6; ++i)
        if (!(fabs(rest[i] - r->achieved[i]) * (i < 3 ? HP_MM_PER_M : HP_DEG_PER_RAD) <= 1e-6)) {
            snprintf(why, len, "%s, its pressures rest %.3g mm/deg away (component %d)",
                     hp_status_name(r->status),
                     fabs(rest[i] - r->achieved[i]) * (i < 3 ? HP_MM_PER_M : HP_DEG_PER_RAD), i);
            return 0;
        }
    return 1;
}

/* The load level (20 % of the head's weight, surface geometry): the same walk, where the
 * weight makes the far rows CLOSEST. Its state is the previous pressures and pose alone (no
 * solver's warm point), so both halves hold bit for bit: the planner that planned other
 * corrections in between, and the sequential run. Every answer (REACHED or CLOSEST) is a
 * stable rest of its pressures inside the windows (load_row_ok), and a row refused is refused
 * as held only at a saddle. status[] gets each row's status. */
static void check_load(double rate_max, int rows, hp_status *status)
{
    hp_planner *p[3];
    for (int j = 0; j < 3; ++j) {
        p[j] = load_lf_planner(HP_BACKEND_REALTIME, HP_LEVEL_LOAD, rate_max, NULL);
        assert_non_null(p[j]);
    }
    static hp_result seq[WALK_ROWS];
    int closest = 0, unstable = 0;
    for (int i = 0; i < rows; ++i) {
        double d[6], prev[HP_MAX_BLADDERS];
        char why[160] = "";
        walk_row(i, d);
        assert_int_equal(hp_plan(p[0], d, &seq[i]), HP_OK);
        status[i] = seq[i].status;
        /* A row held only at an unstable equilibrium is refused by name with the safe
         * output (docs/load.md, "Stable holds"); the others are answers. */
        if (seq[i].status == HP_STATUS_SOLVER_ERROR &&
            strstr(hp_planner_error(p[0]), "only at an unstable equilibrium")) {
            ++unstable;
            continue;
        }
        assert_true(seq[i].status == HP_STATUS_REACHED || seq[i].status == HP_STATUS_CLOSEST);
        if (!load_confirms(p[0], d, &seq[i], why, sizeof why)) fail_msg("row %d: %s", i, why);
        for (int k = 0; i > 0 && k < seq[i].n; ++k) prev[k] = seq[i - 1].bladders[k].pressure;
        if (!load_row_ok(p[0], &seq[i], i > 0 ? prev : NULL, rate_max, why, sizeof why))
            fail_msg("row %d: %s", i, why);
        closest += seq[i].status == HP_STATUS_CLOSEST;
    }
    print_message(
        "load level, rate_max %g: %d rows held only at a saddle (refused), %d closest of %d\n",
        rate_max, unstable, closest, rows);
    for (int i = 1; i < rows; ++i) {
        double d[6], other[6];
        walk_row(i, d);
        walk_row(i + 17, other);
        for (int j = 0; j < 6; ++j) other[j] = -other[j];
        hp_result ra, rb, junk;
        assert_int_equal(hp_plan(p[2], other, &junk), HP_OK);
        assert_int_equal(hp_planner_set_previous_result(p[1], &seq[i - 1]), HP_OK);
        assert_int_equal(hp_planner_set_previous_result(p[2], &seq[i - 1]), HP_OK);
        assert_int_equal(hp_plan(p[1], d, &ra), HP_OK);
        assert_int_equal(hp_plan(p[2], d, &rb), HP_OK);
        same_result(&ra, &rb, i);
        same_result(&ra, &seq[i], i);
    }
    for (int j = 0; j < 3; ++j) hp_planner_destroy(p[j]);
}

static void test_load(void **st)
{
    (void)st;
    /* Fewer rows than at the contact levels: a load plan costs ~100 contact plans, and with
     * the rate limits the rate origin (what set_previous_result sets) is exercised too. */
    enum { ROWS = 32 };
    hp_status free_st[ROWS], rate_st[ROWS];
    check_load(INFINITY, ROWS, free_st);
    check_load(1500.0, ROWS, rate_st);
    /* With the rate windows, a saddle the windows cause is answered by the stable walk (a
     * CLOSEST rest of pressures inside the windows) or by a stable hold along gravity, and
     * the next row starts from that answer, so the walk closes in on the stable hold the
     * windows cut off instead of staying refused (the next window centred on the last
     * answer, which cannot reach the stable hold either: 16 of these 32 rows were refused
     * so, and every row after the first refusal). What this guarantees here: every row the
     * unlimited walk reaches is reached within one row under the windows, and a refusal is
     * a row where no stable candidate inside the windows passes an answer's checks.
     * Measured: refused none with the windows or without (2, rows 7 and 15, while a
     * candidate limited only by stability named no binding limit: HP_BIND_STABILITY); every
     * row reached in the same row as without the windows. */
    int refused = 0, reached = 0, closest = 0, late = 0, free_refused = 0;
    for (int i = 0; i < ROWS; ++i) {
        refused += rate_st[i] == HP_STATUS_SOLVER_ERROR;
        free_refused += free_st[i] == HP_STATUS_SOLVER_ERROR;
        reached += rate_st[i] == HP_STATUS_REACHED;
        closest += rate_st[i] == HP_STATUS_CLOSEST;
        if (free_st[i] == HP_STATUS_REACHED && rate_st[i] != HP_STATUS_REACHED) {
            ++late;
            if (i + 1 >= ROWS || rate_st[i + 1] != HP_STATUS_REACHED)
                fail_msg("row %d: reached without the rate limits, not within a row with them", i);
        }
    }
    print_message("load walk, rate_max 1500: refused %d (without the windows %d), closest %d, "
                  "reached %d (a row late %d)\n",
                  refused, free_refused, closest, reached, late);
    assert_true(free_refused <= 1 && refused <= 4 && closest >= 5 && reached >= 10);
}

/* The safe output after a plan that fails: the bladders and pose of the result set. */
static void expect_state(hp_planner *p, const hp_result *want)
{
    const double nan6[6] = {NAN, NAN, NAN, NAN, NAN, NAN};
    hp_result r;
    assert_int_equal(hp_plan(p, nan6, &r), HP_OK);
    assert_int_equal(r.status, HP_STATUS_INVALID_INPUT);
    assert_memory_equal(r.achieved, want->achieved, sizeof r.achieved);
    for (int k = 0; k < r.n; ++k) {
        assert_true(r.bladders[k].ri == want->bladders[k].ri);
        assert_true(r.bladders[k].ro == want->bladders[k].ro);
        assert_true(r.bladders[k].pressure == want->bladders[k].pressure);
        assert_true(r.bladders[k].stretch == want->bladders[k].stretch);
    }
}

typedef struct spoil_case {
    const char *field, *bladder; /* both must be in the message (bladder may be NULL) */
    void (*spoil)(hp_result *r);
} spoil_case;

static void s_n(hp_result *r) { r->n = 7; }
static void s_pose_nan(hp_result *r) { r->achieved[1] = NAN; }
static void s_pose_inf(hp_result *r) { r->achieved[4] = INFINITY; }
static void s_pose_far(hp_result *r) { r->achieved[0] = 0.2; }  /* > the smallest semi-axis */
static void s_pose_turn(hp_result *r) { r->achieved[5] = 1.7; } /* 97 degrees */
static void s_p_nan(hp_result *r) { r->bladders[2].pressure = NAN; }
static void s_p_high(hp_result *r) { r->bladders[2].pressure = 2e4; }
static void s_p_low(hp_result *r) { r->bladders[2].pressure = -6e3; }
static void s_ri_nan(hp_result *r) { r->bladders[3].ri = NAN; }
static void s_ri_low(hp_result *r) { r->bladders[3].ri = 0.8 * 0.027 * (1 - 1e-9); }
/* 1e-7 of the 15 kPa range (100x the tolerance), towards 0 so that it stays inside the
 * limits even from a bound. */
static void s_p_of_ri(hp_result *r)
{
    r->bladders[5].pressure -= copysign(1.5e-3, r->bladders[5].pressure);
}
static void s_ro_of_ri(hp_result *r) { r->bladders[6].ro += 2e-9; }
static void s_ro_inf(hp_result *r) { r->bladders[6].ro = INFINITY; }

static void test_refusals(void **st)
{
    (void)st;
    hp_planner *p = make(HP_LEVEL_LINEAR, INFINITY);
    hp_result good, r;
    double d[6];
    walk_row(9, d); /* beyond reach: a CLOSEST answer with a limit binding */
    assert_int_equal(hp_plan(p, d, &good), HP_OK);
    assert_int_equal(good.status, HP_STATUS_CLOSEST);
    hp_planner_reset(p);
    assert_int_equal(hp_planner_set_previous_result(p, &good), HP_OK);
    expect_state(p, &good);
    /* The fields it does not read may be anything. */
    r = good;
    r.status = (hp_status)99;
    r.pose_error = NAN;
    for (int k = 0; k < r.n; ++k) {
        r.bladders[k].stretch = NAN;
        r.bladders[k].binding = ~0u;
    }
    assert_int_equal(hp_planner_set_previous_result(p, &r), HP_OK);
    expect_state(p, &good);

    const spoil_case cases[] = {
        {"n", NULL, s_n},
        {"achieved: not finite: y", NULL, s_pose_nan},
        {"achieved: not finite: roll", NULL, s_pose_inf},
        {"achieved: translation", NULL, s_pose_far},
        {"achieved: rotation", NULL, s_pose_turn},
        {"pressure outside", "base_skull_left", s_p_nan},
        {"pressure outside", "base_skull_left", s_p_high},
        {"pressure outside", "base_skull_left", s_p_low},
        {"ri outside", "base_skull_right", s_ri_nan},
        {"ri outside", "base_skull_right", s_ri_low},
        {"pressure is not the pressure of ri", "side_fore_right", s_p_of_ri},
        {"ro is not the outer radius of ri", "side_chin_left", s_ro_of_ri},
        {"ro is not the outer radius of ri", "side_chin_left", s_ro_inf},
    };
    /* From the nominal answer, so that "nothing changes" is visible. */
    hp_planner_reset(p);
    hp_result nominal;
    const double nan6[6] = {NAN, NAN, NAN, NAN, NAN, NAN};
    assert_int_equal(hp_plan(p, nan6, &nominal), HP_OK);
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; ++c) {
        r = good;
        cases[c].spoil(&r);
        assert_int_equal(hp_planner_set_previous_result(p, &r), HP_ERR_INVALID);
        const char *msg = hp_planner_error(p);
        if (!strstr(msg, "set_previous_result") || !strstr(msg, cases[c].field) ||
            (cases[c].bladder && !strstr(msg, cases[c].bladder)))
            fail_msg("case %zu: message '%s' does not name '%s'", c, msg, cases[c].field);
        assert_null(strchr(msg, '\n'));
        expect_state(p, &nominal);
    }
    /* A turn whose pitch, roll and yaw sum beyond 90 degrees but whose angle is 60: the
     * cheap bound does not decide, the exact angle accepts it. */
    r = good;
    for (int i = 3; i < 6; ++i) r.achieved[i] = 0.6;
    assert_int_equal(hp_planner_set_previous_result(p, &r), HP_OK);
    /* Just inside the consistency tolerances is accepted. */
    r = good;
    r.bladders[6].ro += 0.5e-9;
    r.bladders[5].pressure -= copysign(0.5 * 1.5e-5, r.bladders[5].pressure);
    assert_int_equal(hp_planner_set_previous_result(p, &r), HP_OK);

    assert_int_equal(hp_planner_set_previous_result(NULL, &good), HP_ERR_NULL);
    assert_int_equal(hp_planner_set_previous_result(p, NULL), HP_ERR_NULL);
    assert_non_null(strstr(hp_planner_error(p), "result is NULL"));
    hp_planner_destroy(p);
}

/* A layout that cannot command rotations (a sphere turned about its centre looks the same):
 * a pose with a rotation there is refused, naming the component. */
static void test_uncommanded_component(void **st)
{
    (void)st;
    hp_layout L;
    assert_int_equal(lf_layout_ex(&L, 1, 2.2e4), HP_OK);
    hp_planner *p = NULL;
    assert_int_equal(hp_planner_create(&L, NULL, &p, NULL), HP_OK);
    hp_result r;
    const double d[6] = {1e-3, 0, 0, 0, 0, 0};
    assert_int_equal(hp_plan(p, d, &r), HP_OK);
    assert_int_equal(r.status, HP_STATUS_REACHED);
    assert_int_equal(hp_planner_set_previous_result(p, &r), HP_OK);
    r.achieved[3] = 1e-3;
    assert_int_equal(hp_planner_set_previous_result(p, &r), HP_ERR_INVALID);
    assert_non_null(strstr(hp_planner_error(p), "does not command: pitch"));
    hp_planner_destroy(p);
}

/* Every answer hp_plan returns passes the full checks (what the shortcut for the planner's
 * own last answer relies on): 60 seeded corrections per case (reachable, binding, far
 * beyond reach), at every level, on the default layout with and without rate limits and on
 * the soft layout whose stable-branch cap binds; each answer is handed to a second planner
 * whose previous answer differs, so nothing is skipped there. */
static void test_answers_pass_the_checks(void **st)
{
    (void)st;
    uint64_t seed = 4242;
    int answers = 0;
    for (int c = 0; c < 9; ++c) {
        hp_level level = (hp_level)(HP_LEVEL_LINEAR + c % 3);
        hp_layout L;
        if (c < 6) {
            assert_int_equal(lf_layout(&L), HP_OK);
            for (int k = 0; k < L.n; ++k) L.bladders[k].rate_max = c < 3 ? INFINITY : 700.0;
        } else {
            hp_iab_limit lp;
            assert_int_equal(lf_soft_layout(&L, 2.0, &lp), HP_OK);
        }
        hp_settings s;
        hp_settings_default(&s);
        s.level = level;
        hp_planner *p = NULL, *chk = NULL;
        assert_int_equal(hp_planner_create(&L, &s, &p, NULL), HP_OK);
        assert_int_equal(hp_planner_create(&L, &s, &chk, NULL), HP_OK);
        for (int t = 0; t < 60; ++t) {
            double mm_deg[6], d[6];
            double scale = (t % 3 == 0) ? 0.5 : (t % 3 == 1) ? 8.0 : 40.0;
            for (int i = 0; i < 6; ++i) mm_deg[i] = scale * lf_uniform(&seed);
            lf_pose(mm_deg, d);
            hp_result r;
            assert_int_equal(hp_plan(p, d, &r), HP_OK);
            if (!isfinite(r.pose_error)) continue; /* the safe output: no new answer */
            hp_planner_reset(chk);
            if (hp_planner_set_previous_result(chk, &r) != HP_OK)
                fail_msg("case %d, plan %d (%s): %s", c, t, hp_status_name(r.status),
                         hp_planner_error(chk));
            ++answers;
        }
        hp_planner_destroy(p);
        hp_planner_destroy(chk);
    }
    print_message("%d answers passed the checks\n", answers);
    assert_true(answers >= 400);
}

/* Every result hp_plan hands back, whatever it ends in, is accepted by a planner of the
 * same settings (headplan batch and run_trace set the next row's state from it and stop the
 * run on a refusal): answers cut short by the iteration budget (max_iter 1..3, so the
 * realtime SQP stops at its first iterates; most of them have no usable iterate and carry
 * the safe output), and closest answers to targets out to the edge of the identifiable
 * range (translation norm 0.05 to 1 of the limit, rotations to 28 degrees per axis), at
 * every level. */
static void test_every_result_is_accepted(void **st)
{
    (void)st;
    uint64_t seed = 777;
    int budget = 0, answers = 0;
    for (int c = 0; c < 12; ++c) {
        hp_layout L;
        assert_int_equal(lf_layout(&L), HP_OK);
        hp_settings s;
        hp_settings_default(&s);
        s.level = (hp_level)(HP_LEVEL_LINEAR + c % 3);
        s.max_iter = c < 9 ? 1 + c / 3 : 100;
        hp_planner *p = NULL, *chk = NULL;
        assert_int_equal(hp_planner_create(&L, &s, &p, NULL), HP_OK);
        assert_int_equal(hp_planner_create(&L, &s, &chk, NULL), HP_OK);
        const double lim = hp_planner_identifiable(p)->trans_limit * HP_MM_PER_M;
        for (int t = 0; t < 100; ++t) {
            double mm_deg[6], d[6], nt = 0;
            for (int i = 0; i < 6; ++i) mm_deg[i] = lf_uniform(&seed);
            for (int i = 0; i < 3; ++i) nt += mm_deg[i] * mm_deg[i];
            double f = (0.05 + 0.95 * fabs(lf_uniform(&seed))) * lim / sqrt(nt);
            for (int i = 0; i < 3; ++i) mm_deg[i] *= f;
            for (int i = 3; i < 6; ++i) mm_deg[i] *= t % 3 ? 28.0 : 2.0;
            lf_pose(mm_deg, d);
            hp_result r;
            hp_error e = hp_plan(p, d, &r);
            assert_true(e == HP_OK || r.status == HP_STATUS_INVALID_INPUT);
            hp_planner_reset(chk);
            if (hp_planner_set_previous_result(chk, &r) != HP_OK)
                fail_msg("case %d, plan %d (%s, pose error %g): %s", c, t, hp_status_name(r.status),
                         r.pose_error, hp_planner_error(chk));
            budget += r.status == HP_STATUS_ITERATION_LIMIT && isfinite(r.pose_error);
            answers += isfinite(r.pose_error);
        }
        hp_planner_destroy(p);
        hp_planner_destroy(chk);
    }
    print_message("%d answers (%d cut short by the budget) accepted\n", answers, budget);
    assert_true(budget >= 30 && answers >= 300);
}

/* hp_planner_set_previous states the pose its pressures hold (the safe output's achieved):
 * it must be the pose hp_contact_fk fits to their outer radii, computed here from the
 * bladder laws and the public FK. Before, pressures whose fit from the nominal pose did not
 * converge (a few in a hundred at the plane level) were accepted with the nominal pose. */
static void test_set_previous_states_a_fitted_pose(void **st)
{
    (void)st;
    hp_planner *p = make(HP_LEVEL_PLANE, INFINITY);
    const hp_layout *PL = hp_planner_layout(p);
    uint64_t seed = 7;
    int refused = 0, accepted = 0;
    double P0[8];
    assert_int_equal(hp_planner_nominal_pressures(p, P0), HP_OK);
    for (int t = 0; t < 3000; ++t) {
        double P[8];
        for (int k = 0; k < 8; ++k) {
            seed = seed * 6364136223846793005u + 1442695040888963407u;
            double u = (double)(seed >> 11) / 9007199254740992.0;
            /* Around the nominal pressures: most stay inside the stretch limits. */
            P[k] = P0[k] + (u - 0.5) * (PL->bladders[k].p_max - PL->bladders[k].p_min);
        }
        hp_result before, r;
        const double nan6[6] = {NAN, NAN, NAN, NAN, NAN, NAN};
        assert_int_equal(hp_plan(p, nan6, &before), HP_OK);
        hp_error e = hp_planner_set_previous(p, P);
        if (e != HP_OK) {
            assert_int_equal(e, HP_ERR_INVALID);
            /* A pressure outside the stretch limits is refused too: not counted. */
            refused += strstr(hp_planner_error(p), "forward contact kinematics") != NULL;
            expect_state(p, &before); /* nothing changed */
            continue;
        }
        ++accepted;
        assert_int_equal(hp_plan(p, nan6, &r), HP_OK);
        double ro[8], xi[6], resid;
        for (int k = 0; k < 8; ++k) {
            double ri;
            assert_int_equal(hp_iab_fk(&PL->bladders[k].iab, P[k], &ri), HP_OK);
            assert_int_equal(hp_iab_ro(&PL->bladders[k].iab, ri, &ro[k]), HP_OK);
        }
        /* Tolerance 1e-6 mm/deg: the planner's reached claim (hp_planner.h); both fits
         * converge to ~1e-12. */
        assert_int_equal(hp_contact_fk(PL, HP_LEVEL_PLANE, ro, NULL, xi, &resid, NULL), HP_OK);
        for (int i = 0; i < 6; ++i)
            assert_true(fabs(xi[i] - r.achieved[i]) * (i < 3 ? HP_MM_PER_M : HP_DEG_PER_RAD) <=
                        1e-6);
    }
    print_message("set_previous: %d accepted, %d refused\n", accepted, refused);
    assert_true(refused >= 1 && accepted >= 100);
    hp_planner_destroy(p);
}

/* A layout that cannot observe every component (five bladders; eight in a plane) is planned
 * (the others are uncommanded), so its own nominal pressures are a valid start: the horizon
 * starts every plan from them with hp_planner_set_previous. Refused before (HP_ERR_INVALID,
 * "did not converge"): the fit was asked for all six components, which five distances
 * cannot give, and `headplan horizon` exited 65 on such a scene that batch plans. */
static void test_set_previous_rank_deficient(void **st)
{
    (void)st;
    double flat[8][3];
    il_flat_rays(flat);
    for (int c = 0; c < 2; ++c) {
        hp_layout L;
        assert_int_equal(il_layout(&L, HP_HEAD_ELLIPSOID, il_default_axes, il_origin, il_origin,
                                   c ? 8 : 5, c ? (const double(*)[3])flat : il_default_rays, 1.0),
                         HP_OK);
        for (int lv = 0; lv < 2; ++lv) {
            hp_settings s;
            hp_settings_default(&s);
            s.level = lv ? HP_LEVEL_SURFACE : HP_LEVEL_PLANE;
            s.max_time = 60.0;
            hp_planner *p = NULL;
            hp_diag d = {{0}};
            assert_int_equal(hp_planner_create(&L, &s, &p, &d), HP_OK);
            double P0[HP_MAX_BLADDERS];
            hp_result nominal, r;
            const double nan6[6] = {NAN, NAN, NAN, NAN, NAN, NAN};
            assert_int_equal(hp_plan(p, nan6, &nominal), HP_OK);
            assert_int_equal(hp_planner_nominal_pressures(p, P0), HP_OK);
            hp_error e = hp_planner_set_previous(p, P0);
            if (e != HP_OK) print_error("layout %d level %d: %s\n", c, lv, hp_planner_error(p));
            assert_int_equal(e, HP_OK);
            assert_int_equal(hp_plan(p, nan6, &r), HP_OK);
            /* Its own nominal pressures hold the nominal answer's pose (1e-9 mm/deg). */
            for (int i = 0; i < 6; ++i)
                assert_true(fabs(r.achieved[i] - nominal.achieved[i]) *
                                (i < 3 ? HP_MM_PER_M : HP_DEG_PER_RAD) <=
                            1e-9);
            hp_planner_destroy(p);
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_refusals),
        cmocka_unit_test(test_uncommanded_component),
        cmocka_unit_test(test_answers_pass_the_checks),
        cmocka_unit_test(test_every_result_is_accepted),
        cmocka_unit_test(test_linear),
        cmocka_unit_test(test_surface),
        cmocka_unit_test(test_load),
        cmocka_unit_test(test_set_previous_states_a_fitted_pose),
        cmocka_unit_test(test_set_previous_rank_deficient),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
