/* The answer rows' memo (plan_state.c, hp_answer_memo): the rows (each bladder's inner
 * radius and pressure from its outer radius) of the direct answer a rate-limited plan
 * discards, taken again bit for bit when the same distances and radius bounds come back.
 * - Counted (hpi_test_answer_rows, no timing): a rate-limited planner walking to a held
 *   target at the rate evaluates the direct chain's answer at the target (the pressures it
 *   tests against the rate windows) and, when a pressure comes near a window's end, the
 *   solver's answer each cycle; the first repeats bit for bit from cycle to cycle, so after
 *   the first plan of a hold a plan evaluates at most one answer's rows (the solver's).
 *   Since a direct answer the windows discard for certain is not built
 *   (hpi_plan_direct_left), this trace evaluates no plan's rows twice even with the memo
 *   off (before: 14 plans did); the plan that ends a walk keeps its rows for the plans
 *   holding the target (1 408 rows with the memo, 1 600 without).
 * - Bit for bit: planners with the memo on and off, fed the same targets (a step trace, a
 *   noisy breathing trace) and the same measured pressures (hp_planner_set_measured, ±3 Pa
 *   of seeded noise on the answer's), give the same results to the last bit at the linear
 *   and plane levels, with and without rate limits. */
#include "support/test_util.h"
#include "support/layout_fixture.h"
#include "support/same_result.h"
#include "planner/planner_internal.h"

#define RATE 500.0 /* Pa per plan, as the loop benchmark's rate-limited planner */

static hp_planner *planner(hp_level level, int rate)
{
    hp_settings s;
    hp_settings_default(&s);
    s.max_time = 60.0; /* the outcome, not the clock, is asserted */
    s.level = level;
    s.use_rate_limits = rate;
    hp_planner *p = NULL;
    assert_int_equal(lf_planner_settings(&s, RATE, &p), HP_OK);
    return p;
}

/* Target t of the step trace: held for `hold` plans, then a seeded jump (±3 mm, ±2 deg). */
static void step_target(uint64_t *seed, int t, int hold, double mm_deg[6])
{
    if (t % hold == 0)
        for (int i = 0; i < 6; ++i) mm_deg[i] = lf_uniform(seed) * (i < 3 ? 3.0 : 2.0);
}

/* hp_plan with the memo on or off; the rows it evaluated. */
static unsigned long plan_rows(hp_planner *p, const double d[6], hp_result *r, int memo)
{
    hpi_test_answer_memo(memo);
    unsigned long r0 = hpi_test_answer_rows();
    assert_int_equal(hp_plan(p, d, r), HP_OK);
    unsigned long rows = hpi_test_answer_rows() - r0;
    hpi_test_answer_memo(1);
    return rows;
}

static void test_held_target_rows(void **state)
{
    (void)state;
    const int hold = 40, steps = 5;
    hp_planner *a = planner(HP_LEVEL_LINEAR, 1), *b = planner(HP_LEVEL_LINEAR, 1);
    uint64_t seed = 0x5eed32;
    double mm_deg[6] = {0}, d[6];
    int n = 0, two_off = 0, repeats = 0;
    unsigned long rows_on = 0, rows_off = 0;
    for (int t = 0; t < hold * steps; ++t) {
        step_target(&seed, t, hold, mm_deg);
        lf_pose(mm_deg, d);
        hp_result ra, rb;
        unsigned long on = plan_rows(a, d, &ra, 1), off = plan_rows(b, d, &rb, 0);
        n = ra.n;
        assert_true(hp_test_same_result(&ra, &rb));
        rows_on += on;
        rows_off += off;
        if (t % hold == 0) continue; /* a new target: nothing to repeat */
        ++repeats;
        two_off += off > (unsigned long)n;
        if (on > (unsigned long)n) {
            print_error("plan %d: %lu rows evaluated with the memo (%lu without), want <= %d\n", t,
                        on, off, n);
            fail();
        }
    }
    print_message("step trace, %d plans holding a target: rows evaluated %lu with the memo, "
                  "%lu without; %d plans evaluated two answers without it\n",
                  repeats, rows_on, rows_off, two_off);
    assert_true(rows_on <= rows_off);
    hp_planner_destroy(a);
    hp_planner_destroy(b);
}

/* A jump plan of the step trace (the first toward a new target, several windows away)
 * evaluates one answer's rows, the solver's: the direct chain's radii lie beyond a rate
 * window's end for certain (hpi_setup_rate_surely_left), so its answer, which the rate
 * windows would discard, is not built. Before, a jump plan whose direct chain answered
 * inside the static bounds evaluated two answers' rows, memo on (a new target: nothing to
 * take from it; the linear trace's plan 80 first). Own answers as the next plan's
 * centres, and ±3 Pa readings of them (hp_planner_set_measured), at the linear and plane
 * levels. Every jump plan is held back by the windows (a rate limit binds), so each
 * counted plan went the rate bounds' way. */
static void jump_rows(hp_level level, int measured)
{
    const int hold = 40, steps = 5;
    hp_planner *p = planner(level, 1);
    uint64_t seed = 0x5eed32, noise = 0x301;
    double mm_deg[6] = {0}, d[6];
    int jumps = 0;
    for (int t = 0; t < hold * steps; ++t) {
        step_target(&seed, t, hold, mm_deg);
        lf_pose(mm_deg, d);
        hp_result r;
        unsigned long rows = plan_rows(p, d, &r, 1);
        if (t % hold == 0) {
            unsigned rate = 0;
            for (int k = 0; k < r.n; ++k)
                rate |= r.bladders[k].binding & (HP_BIND_RATE_DOWN | HP_BIND_RATE_UP);
            if (rows != (unsigned long)r.n || !rate) {
                print_error("%s, measured %d, jump plan %d (%s): %lu rows evaluated, want %d; "
                            "rate limit binding: %s\n",
                            hp_level_name(level), measured, t, hp_status_name(r.status), rows, r.n,
                            rate ? "yes" : "no");
                fail();
            }
            ++jumps;
        }
        if (!measured) continue;
        double P[HP_MAX_BLADDERS];
        for (int k = 0; k < r.n; ++k) P[k] = r.bladders[k].pressure + 3.0 * lf_uniform(&noise);
        assert_int_equal(hp_planner_set_measured(p, P, NULL), HP_OK);
    }
    assert_int_equal(jumps, steps);
    hp_planner_destroy(p);
}

static void test_jump_plans_one_answer(void **state)
{
    (void)state;
    const hp_level levels[] = {HP_LEVEL_LINEAR, HP_LEVEL_PLANE};
    for (int l = 0; l < 2; ++l)
        for (int m = 0; m < 2; ++m) jump_rows(levels[l], m);
}

/* What planner b of same_bits changes: the memo off, or the look for a discarded direct
 * answer (hpi_test_plan_look) always or never instead of where its gate says. */
enum { MEMO_OFF, LOOK_ALWAYS, LOOK_NEVER };
static const char *const variant_name[] = {"the memo off", "the look always", "the look never"};

/* hp_plan on b as variant v has it; the rows evaluated. */
static unsigned long plan_variant(hp_planner *b, const double d[6], hp_result *r, int v)
{
    hpi_test_plan_look(v == LOOK_ALWAYS ? 1 : v == LOOK_NEVER ? -1 : 0);
    unsigned long rows = plan_rows(b, d, r, v != MEMO_OFF);
    hpi_test_plan_look(0);
    return rows;
}

/* One trace through a planner as shipped (a) and one as variant v (b): the same results.
 * Returns the rows b evaluated minus a's at the step trace's jump plans (the first toward
 * each new target; 0 for the breathing trace). */
static long same_bits(hp_level level, int rate, int trace, int measured, int v)
{
    hp_planner *a = planner(level, rate), *b = planner(level, rate);
    uint64_t seed = 0x7a11 + (uint64_t)trace, noise = 0x301 + (uint64_t)trace;
    double mm_deg[6] = {0}, d[6];
    long extra = 0;
    for (int t = 0; t < 240; ++t) {
        if (trace == 0) {
            step_target(&seed, t, 60, mm_deg);
        } else { /* breathing with noise */
            double ph = 2.0 * 3.141592653589793 * t / 50.0;
            mm_deg[1] = 0.8 * sin(ph + 0.3);
            mm_deg[2] = 2.0 * sin(ph);
            mm_deg[3] = 0.6 * sin(ph + 0.1);
            for (int i = 0; i < 6; ++i) mm_deg[i] += lf_uniform(&seed) * (i < 3 ? 0.1 : 0.05);
        }
        lf_pose(mm_deg, d);
        hp_result ra, rb;
        long rows_a = (long)plan_rows(a, d, &ra, 1), rows_b = (long)plan_variant(b, d, &rb, v);
        if (trace == 0 && t % 60 == 0) extra += rows_b - rows_a;
        if (!hp_test_same_result(&ra, &rb)) {
            print_error("%s, rate %d, trace %d, measured %d, plan %d: %s changed the answer "
                        "(%s / %s)\n",
                        hp_level_name(level), rate, trace, measured, t, variant_name[v],
                        hp_status_name(ra.status), hp_status_name(rb.status));
            fail();
        }
        if (!measured) continue;
        double P[HP_MAX_BLADDERS];
        for (int k = 0; k < ra.n; ++k) P[k] = ra.bladders[k].pressure + 3.0 * lf_uniform(&noise);
        assert_int_equal(hp_planner_set_measured(a, P, NULL), HP_OK);
        assert_int_equal(hp_planner_set_measured(b, P, NULL), HP_OK);
    }
    hp_planner_destroy(a);
    hp_planner_destroy(b);
    return extra;
}

static void test_memo_same_bits(void **state)
{
    (void)state;
    const hp_level levels[] = {HP_LEVEL_LINEAR, HP_LEVEL_PLANE};
    for (int l = 0; l < 2; ++l)
        for (int rate = 0; rate < 2; ++rate)
            for (int trace = 0; trace < 2; ++trace)
                for (int m = 0; m <= rate; ++m) same_bits(levels[l], rate, trace, m, MEMO_OFF);
}

/* The look for a direct answer the rate windows discard for certain (hpi_plan_direct_left)
 * and its gate (target_far) are a cost choice only: looking always or never gives every
 * answer of the step and breathing traces bit for bit as shipped, at the linear and plane
 * levels, rate-limited, own answers and readings fed back. And the look is not idle: at
 * the step trace's jump plans never looking evaluates more rows than the shipped gate (the
 * direct answers it builds and discards), so a look that stopped skipping fails here.
 * (Over a whole walk the rows even out: the plan that ends it evaluates, and keeps, the
 * direct answer a planner that never looks took from its memo.) */
static void test_look_same_bits(void **state)
{
    (void)state;
    const hp_level levels[] = {HP_LEVEL_LINEAR, HP_LEVEL_PLANE};
    for (int l = 0; l < 2; ++l)
        for (int trace = 0; trace < 2; ++trace)
            for (int m = 0; m < 2; ++m) {
                long never = same_bits(levels[l], 1, trace, m, LOOK_NEVER);
                same_bits(levels[l], 1, trace, m, LOOK_ALWAYS);
                if (trace == 0 && !(never > 0)) {
                    print_error("%s, measured %d, step trace: at the jump plans never looking "
                                "evaluated %ld rows more than the gate, want > 0\n",
                                hp_level_name(levels[l]), m, never);
                    fail();
                }
            }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_held_target_rows),
        cmocka_unit_test(test_memo_same_bits),
        cmocka_unit_test(test_jump_plans_one_answer),
        cmocka_unit_test(test_look_same_bits),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
