/* Property tests at scale: seeded random and adversarial targets through every backend and
 * level (the load level: no sphere head, which it refuses, and a tenth of the sample), on
 * five planners each (default layout, sphere head, soft material C2 = 0 with an
 * inflation limit point, a near-degenerate layout, and the default layout with a 1 Pa rate
 * limit that often cannot hold), every result checked against every safety invariant
 * (rel_common.h: pressure and stretch limits, below the limit point, finite valid fields,
 * labelled failures holding the safe output, REACHED re-checked through the FK round trip).
 *
 * Target kinds, cycling with the plan index t:
 *   0 reachable (±0.3 mm/deg)  1 near the limits (±5)  2 far (±40)  3 tiny (±1e-12 m/rad)
 *   4 huge (1e6 in one component)  5 NaN  6 +Inf  7 −Inf (in component t mod 6)
 *   8 exactly on an axis reach limit of hp_layout_analyze (and 1e-12 relative either side)
 *   9 a bad warm start: hp_planner_set_previous with the extreme pressures of a far answer
 *     (a random one of six, or each bladder's from a different one: pressures no pose
 *     holds, so with the 1 Pa rate limit the limits cannot all hold), then a random target; on the soft layout also the limit-point
 *     pressure itself, which must be refused
 *  10 hp_planner_reset, then ±2   11 ±10 with warm start from whatever came before.
 *
 * Sample size: HP_PROPERTY_PLANS (plans per backend × level; default a CI sample sized per
 * backend below) and HP_PROPERTY_BACKENDS (comma list of backend names; default all).
 *   HP_PROPERTY_PLANS=1000000 HP_PROPERTY_BACKENDS=realtime ./reliability_test_property */
#include "rel_common.h"

#define KINDS 5 /* planners per backend × level: REL_KINDS layouts + the rate-limited one */

static long default_plans(hp_backend b)
{
    switch (b) {
    case HP_BACKEND_REALTIME: return HP_TEST_SMALL(3000, 600);
    case HP_BACKEND_IPOPT: return HP_TEST_SMALL(150, 40);
    case HP_BACKEND_NLOPT_SLSQP: return HP_TEST_SMALL(150, 40);
    default: return HP_TEST_SMALL(40, 12);
    }
}

typedef struct prop_planner {
    hp_layout L;
    hp_planner *p;
    rel_ctx c;
    hp_layout_analysis an;
    double extreme[6][HP_MAX_BLADDERS]; /* far answers' pressures: valid, on the bounds */
    int lp_k;                           /* a bladder with a limit point, else −1 */
} prop_planner;

static int setup(prop_planner *pp, hp_backend b, hp_level level, int kind)
{
    int lk = kind < REL_KINDS ? kind : REL_DEFAULT;
    if (rel_layout(&pp->L, lk) != HP_OK) return 0;
    pp->p = rel_planner(&pp->L, b, level, kind == REL_KINDS ? 1.0 : INFINITY, 0);
    if (!pp->p) return 0;
    rel_ctx_init(&pp->c, pp->p);
    pp->c.use_fk_limit = 1;
    /* The reach limits of case 8: at the load level its surface geometry's. */
    if (hp_layout_analyze(&pp->L, level == HP_LEVEL_LOAD ? HP_LEVEL_SURFACE : level, &pp->an) !=
        HP_OK)
        return 0;
    /* Far answers from the realtime backend without rate limits (valid pressures). */
    hp_planner *q = rel_planner(&pp->L, HP_BACKEND_REALTIME, level, INFINITY, 0);
    if (!q) return 0;
    for (int j = 0; j < 6; ++j) {
        double d[6] = {0};
        d[j] = (j < 3 ? 0.04 : 0.5) * (j % 2 ? -1 : 1);
        d[(j + 1) % 6] = j < 2 ? 0.03 : 0.2;
        hp_result r;
        hp_plan(q, d, &r);
        for (int k = 0; k < pp->L.n; ++k) pp->extreme[j][k] = r.bladders[k].pressure;
    }
    hp_planner_destroy(q);
    pp->lp_k = -1;
    for (int k = 0; k < pp->L.n; ++k)
        if (pp->c.lp[k].exists) pp->lp_k = k;
    rel_ctx_capture_safe(&pp->c, pp->p);
    return 1;
}

static void random_pose(uint64_t *seed, double scale, double xi[6])
{
    double c[6];
    for (int i = 0; i < 6; ++i) c[i] = scale * lf_uniform(seed);
    lf_pose(c, xi);
}

/* One plan of kind t % 12 on planner pp; fails the test on any broken invariant. */
static void one_plan(prop_planner *pp, uint64_t *seed, long t, const char *tag)
{
    double xi[6] = {0};
    int cat = (int)(t % 12), comp = (int)((t / 12) % 6);
    switch (cat) {
    case 0: random_pose(seed, 0.3, xi); break;
    case 1: random_pose(seed, 5.0, xi); break;
    case 2: random_pose(seed, 40.0, xi); break;
    case 3:
        for (int i = 0; i < 6; ++i) xi[i] = 1e-12 * lf_uniform(seed);
        break;
    case 4: xi[comp] = (lf_uniform(seed) < 0 ? -1e6 : 1e6); break;
    case 5:
        random_pose(seed, 1.0, xi);
        xi[comp] = NAN;
        break;
    case 6:
        random_pose(seed, 1.0, xi);
        xi[comp] = INFINITY;
        break;
    case 7:
        random_pose(seed, 1.0, xi);
        xi[comp] = -INFINITY;
        break;
    case 8: {
        int dir = (int)((t / 72) % 2);
        double v = pp->an.reach[comp][dir];
        double nudge[3] = {1.0, 1.0 + 1e-12, 1.0 - 1e-12};
        v *= nudge[(t / 144) % 3];
        xi[comp] = comp < 3 ? v * 1e-3 : v * (3.14159265358979323846 / 180.0);
        break;
    }
    case 9: {
        double P[HP_MAX_BLADDERS];
        int mix = (int)(test_rng_next(seed) % 2), j0 = (int)(test_rng_next(seed) % 6);
        for (int k = 0; k < pp->L.n; ++k) /* mixed: each bladder from another far answer */
            P[k] = pp->extreme[mix ? (int)(test_rng_next(seed) % 6) : j0][k];
        if (hp_planner_set_previous(pp->p, P) == HP_OK) rel_ctx_capture_safe(&pp->c, pp->p);
        if (pp->lp_k >= 0) { /* the limit-point pressure itself: above the stable cap */
            double Q[HP_MAX_BLADDERS];
            memcpy(Q, P, sizeof Q);
            Q[pp->lp_k] = pp->c.lp[pp->lp_k].pressure;
            if (!(Q[pp->lp_k] > pp->L.bladders[pp->lp_k].p_max)) {
                assert_int_equal(hp_planner_set_previous(pp->p, Q), HP_ERR_INVALID);
            }
        }
        random_pose(seed, 8.0, xi);
        break;
    }
    case 10:
        hp_planner_reset(pp->p);
        rel_ctx_capture_safe(&pp->c, pp->p);
        random_pose(seed, 2.0, xi);
        break;
    default: random_pose(seed, 10.0, xi); break;
    }
    hp_result r;
    hp_error e = hp_plan(pp->p, xi, &r);
    REL_ASSERT(&pp->c, e, xi, &r, REL_INV_ALL, tag);
    if (cat >= 4 && cat <= 7) assert_int_equal(r.status, HP_STATUS_INVALID_INPUT);
}

static int backend_selected(hp_backend b)
{
    const char *sel = getenv("HP_PROPERTY_BACKENDS");
    if (!sel || !*sel) return 1;
    const char *name = hp_backend_name(b);
    size_t n = strlen(name);
    for (const char *q = sel; (q = strstr(q, name)) != NULL; q += n)
        if ((q == sel || q[-1] == ',') && (q[n] == '\0' || q[n] == ',')) return 1;
    return 0;
}

static void run_backend(hp_backend b)
{
    if (!backend_selected(b)) {
        print_message("%s: skipped (HP_PROPERTY_BACKENDS)\n", hp_backend_name(b));
        return;
    }
    long plans = default_plans(b);
    const char *env = getenv("HP_PROPERTY_PLANS");
    if (env && *env) {
        char *end;
        long v = strtol(env, &end, 10);
        assert_true(*end == '\0' && v > 0);
        plans = v;
    }
    for (int li = 0; li < REL_LEVELS; ++li) {
        const hp_level lv = rel_levels[li];
        if (!rel_plans(b, lv)) { /* refused by name (rel_planner checks the message) */
            hp_layout L0;
            assert_int_equal(rel_layout(&L0, REL_DEFAULT), HP_OK);
            assert_null(rel_planner(&L0, b, lv, INFINITY, 0));
            continue;
        }
        prop_planner pp[KINDS];
        memset(pp, 0, sizeof pp);
        for (int k = 0; k < KINDS; ++k) {
            /* A sphere head is not held at the load level (nothing holds its rotation):
             * hp_planner_create refuses it (tests/planner/test_load_planner.c). */
            if (lv == HP_LEVEL_LOAD && k == REL_SPHERE) continue;
            if (!setup(&pp[k], b, rel_levels[li], k)) {
                print_error("setup %s/%s kind %d failed\n", hp_backend_name(b),
                            hp_level_name(rel_levels[li]), k);
                fail();
            }
        }
        uint64_t seed = 0xC0FFEEull * (uint64_t)(b + 1) + (uint64_t)li;
        char tag[128];
        /* The load level's closest answers search several starts (~1 ms a plan on the
         * realtime backend, 30x its contact levels): a tenth of the sample. */
        const long n_plans = lv == HP_LEVEL_LOAD ? plans / 10 + 1 : plans;
        for (long t = 0; t < n_plans; ++t) {
            int k = (int)(t % KINDS);
            if (!pp[k].p) continue;
            snprintf(tag, sizeof tag, "%s/%s %s plan %ld", hp_backend_name(b),
                     hp_level_name(rel_levels[li]), k < REL_KINDS ? rel_kind_names[k] : "rate-1Pa",
                     t);
            one_plan(&pp[k], &seed, t / KINDS, tag);
        }
        long by[HP_STATUS_COUNT_] = {0}, total = 0;
        double worst = 0;
        for (int k = 0; k < KINDS; ++k) {
            for (int s = 0; s < HP_STATUS_COUNT_; ++s) by[s] += pp[k].c.by_status[s];
            total += pp[k].c.plans;
            worst = fmax(worst, pp[k].c.worst_fk);
            hp_planner_destroy(pp[k].p);
        }
        print_message("%-12s %-7s %8ld plans: reached %ld closest %ld iter %ld time %ld "
                      "infeasible %ld invalid %ld error %ld; worst FK %.2g\n",
                      hp_backend_name(b), hp_level_name(rel_levels[li]), total, by[0], by[1], by[2],
                      by[3], by[4], by[5], by[6], worst);
    }
}

static void property_realtime(void **st)
{
    (void)st;
    run_backend(HP_BACKEND_REALTIME);
}
static void property_ipopt(void **st)
{
    (void)st;
    run_backend(HP_BACKEND_IPOPT);
}
static void property_nlopt_slsqp(void **st)
{
    (void)st;
    run_backend(HP_BACKEND_NLOPT_SLSQP);
}
static void property_nlopt_cobyla(void **st)
{
    (void)st;
    run_backend(HP_BACKEND_NLOPT_COBYLA);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(property_realtime),
        cmocka_unit_test(property_ipopt),
        cmocka_unit_test(property_nlopt_slsqp),
        cmocka_unit_test(property_nlopt_cobyla),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
