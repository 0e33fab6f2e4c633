/* Every backend (realtime, ipopt, nlopt-slsqp, nlopt-cobyla) on every contact level (linear,
 * plane, surface) through the public API only (hp_planner_create / hp_plan), on the default
 * layout of tests/planner/layout_fixture.h:
 *   - seeded reachable corrections: REACHED, and the round trip pressures -> hp_iab_fk ->
 *     hp_iab_ro -> hp_contact_fk (same level) gives the desired pose to 1e-9 mm / 1e-9 deg;
 *   - seeded unreachable corrections: CLOSEST on every backend, every pressure and stretch
 *     inside its limits, the achieved pose equal to Ipopt's (the reference: exact first and
 *     second derivatives) within each backend's stated tolerance, the same binding bladders,
 *     and the returned pressures' own round trip giving the reported achieved pose.
 *
 * Why reachable targets are exact on every backend, COBYLA included: hp_plan tries the
 * direct chain first (pose -> contact distances -> radii -> pressures, docs/planner.md step
 * 2); with eight bladders the pose fixes every radius, so a correction is reachable exactly
 * when that chain is inside every limit, and then no solver runs. COBYLA's derivative-free
 * tolerance (1e-7, docs/backends.md) only matters on unreachable targets.
 *
 * Issue: "reachable corrections met to 1e-9 mm / 1e-9 deg after the round trip through FK
 * on every backend; unreachable ones agree across backends on the closest correction (to the
 * backends' tolerances) and never violate a limit". */
#include "support/test_util.h"
#include "support/layout_fixture.h"

#include <stdlib.h>

#define DEG (3.14159265358979323846 / 180.0)
#define N_BACKENDS 4
#define N_REACH HP_TEST_SMALL(60, 16)   /* seeded reachable targets per level */
#define N_UNREACH HP_TEST_SMALL(40, 12) /* seeded unreachable targets per level */

static const hp_backend backends[N_BACKENDS] = {HP_BACKEND_IPOPT, HP_BACKEND_REALTIME,
                                                HP_BACKEND_NLOPT_SLSQP, HP_BACKEND_NLOPT_COBYLA};

/* Settings tolerance per backend (mm and deg). COBYLA's linear models converge linearly: its
 * documented working tolerance is 1e-7 (docs/backends.md); the others run the default 1e-9. */
static double backend_tolerance(hp_backend b)
{
    return b == HP_BACKEND_NLOPT_COBYLA ? 1e-7 : HP_DEFAULT_TOLERANCE;
}

/* How far a backend's closest pose may sit from Ipopt's (mm or deg, max over the six
 * components). Ipopt itself is the reference (0). Justification:
 *   realtime: an exact active-set QP/SQP on the same model, converged to 1e-9 -> 1e-7
 *     (a hundred times its tolerance: the two stop on different criteria near a vertex);
 *   nlopt-slsqp: BFGS limits the closest answer; docs/backends.md measured up to 4.1e-5 on
 *     300 random unreachable targets -> 2e-4;
 *   nlopt-cobyla: measured up to 8.6e-7 at tolerance 1e-7 (docs/backends.md) -> 1e-5. */
static double agree_tolerance(hp_backend b)
{
    switch (b) {
    case HP_BACKEND_REALTIME: return 1e-7;
    case HP_BACKEND_NLOPT_SLSQP: return 2e-4;
    case HP_BACKEND_NLOPT_COBYLA: return 1e-5;
    default: return 0.0;
    }
}

/* At the load level: 20 % of the head's mass along -Z, as the reliability tests carry. */
static void carry_at_load(const hp_layout *L, hp_settings *s)
{
    if (s->level != HP_LEVEL_LOAD) return;
    hp_load_spec_default(&L->head, &s->load);
    s->load.law = HP_LOAD_LAW_CAP; /* the default bladders carry the head under the cap law only */
    s->load.mass *= 0.2;
}

static hp_planner *make(const hp_layout *L, hp_backend b, hp_level level)
{
    hp_settings s;
    hp_settings_default(&s);
    s.backend = b;
    s.level = level;
    carry_at_load(L, &s);
    s.tolerance = backend_tolerance(b);
    /* Accuracy, not speed, is under test: a generous budget so that a loaded machine or
     * valgrind (Ipopt's first solve took over the default 1 s of CPU there) cannot turn a
     * target into TIME_LIMIT. */
    s.max_time = 60.0;
    hp_planner *p = NULL;
    hp_diag d = {{0}};
    hp_error e = hp_planner_create(L, &s, &p, &d);
    if (e != HP_OK) print_error("create %s: %s\n", hp_backend_name(b), d.text);
    assert_int_equal(e, HP_OK);
    assert_int_equal(hp_planner_level(p), level);
    return p;
}

/* Every pressure and stretch inside its limits, every number finite. */
static void check_limits(const hp_layout *L, const hp_result *r, const char *who)
{
    for (int k = 0; k < L->n; ++k) {
        const hp_bladder *B = &L->bladders[k];
        const hp_bladder_result *b = &r->bladders[k];
        int ok = isfinite(b->pressure) && isfinite(b->ri) && isfinite(b->ro) &&
                 b->pressure >= B->p_min && b->pressure <= B->p_max &&
                 b->stretch >= B->stretch_min && b->stretch <= B->stretch_max;
        if (!ok) {
            print_error("%s: bladder %s: pressure %.17g Pa [%g, %g], stretch %.17g [%g, %g]\n", who,
                        B->name, b->pressure, B->p_min, B->p_max, b->stretch, B->stretch_min,
                        B->stretch_max);
            fail();
        }
    }
}

/* Largest |a − b| over the six pose components, in mm and degrees. */
static double pose_diff(const double a[6], const double b[6])
{
    double m = 0.0;
    for (int i = 0; i < 6; ++i) {
        double s = i < 3 ? 1e3 : 1.0 / DEG;
        double d = fabs(a[i] - b[i]) * s;
        if (!(d <= m)) m = d; /* NaN propagates as a failure */
    }
    return m;
}

static void reachable_at(hp_level level)
{
    hp_layout L;
    assert_int_equal(lf_layout(&L), HP_OK);
    hp_planner *p[N_BACKENDS];
    for (int b = 0; b < N_BACKENDS; ++b) p[b] = make(&L, backends[b], level);
    uint64_t seed = 0xC0FFEEu + (uint64_t)level;
    for (int t = 0; t < N_REACH; ++t) {
        /* +-1 mm, +-0.5 deg: inside the default layout's reach in every direction. */
        double c[6], xi[6];
        for (int i = 0; i < 6; ++i) c[i] = (i < 3 ? 1.0 : 0.5) * lf_uniform(&seed);
        lf_pose(c, xi);
        for (int b = 0; b < N_BACKENDS; ++b) {
            hp_result r;
            hp_planner_reset(p[b]);
            assert_int_equal(hp_plan(p[b], xi, &r), HP_OK);
            if (r.status != HP_STATUS_REACHED)
                print_error("%s level %s target %d: %s\n", hp_backend_name(backends[b]),
                            hp_level_name(level), t, hp_status_name(r.status));
            assert_int_equal(r.status, HP_STATUS_REACHED);
            check_limits(&L, &r, hp_backend_name(backends[b]));
            double back[6];
            assert_int_equal(lf_round_trip(&L, level, &r, back), HP_OK);
            /* 1e-9 mm / 1e-9 deg: the requirement, for every backend (see the top
             * comment: the direct chain answers; its rounding is ~1e-12 mm). */
            for (int i = 0; i < 3; ++i) hp_assert_close(back[i] * 1e3, c[i], 0, 1e-9);
            for (int i = 3; i < 6; ++i) hp_assert_close(back[i] / DEG, c[i], 0, 1e-9);
        }
    }
    for (int b = 0; b < N_BACKENDS; ++b) hp_planner_destroy(p[b]);
}

static void unreachable_at(hp_level level)
{
    hp_layout L;
    assert_int_equal(lf_layout(&L), HP_OK);
    hp_planner *p[N_BACKENDS];
    for (int b = 0; b < N_BACKENDS; ++b) p[b] = make(&L, backends[b], level);
    uint64_t seed = 0xBADCAFEu + (uint64_t)level;
    int done = 0;
    double worst[N_BACKENDS] = {0}, worst_rt = 0.0;
    for (int t = 0; done < N_UNREACH; ++t) {
        assert_true(t < 10 * N_UNREACH); /* the draw must give unreachable targets */
        /* +-8 mm, +-4 deg (the benchmark's unreachable set, docs/backends.md): beyond the
         * default layout's reach on most draws; reachable draws are skipped. */
        double c[6], xi[6];
        for (int i = 0; i < 6; ++i) c[i] = (i < 3 ? 8.0 : 4.0) * lf_uniform(&seed);
        lf_pose(c, xi);
        hp_result ref;
        hp_planner_reset(p[0]);
        assert_int_equal(hp_plan(p[0], xi, &ref), HP_OK);
        if (ref.status == HP_STATUS_REACHED) continue;
        ++done;
        for (int b = 0; b < N_BACKENDS; ++b) {
            hp_result r;
            const char *name = hp_backend_name(backends[b]);
            if (b == 0) {
                r = ref;
            } else {
                hp_planner_reset(p[b]);
                assert_int_equal(hp_plan(p[b], xi, &r), HP_OK);
            }
            if (r.status != HP_STATUS_CLOSEST)
                print_error("%s level %s target %d: %s (%s)\n", name, hp_level_name(level), t,
                            hp_status_name(r.status), hp_planner_error(p[b]));
            assert_int_equal(r.status, HP_STATUS_CLOSEST);
            check_limits(&L, &r, name);
            /* The reported pose is what the returned pressures do: pressures -> FK -> pose
             * at the planner's level. Tolerance 2e-8 mm / deg, not 1e-9: the core keeps the
             * backend's pose when clamping moved no radius by more than 1e-9 mm
             * (docs/planner.md, step 3), and the pseudo-inverse of the contact Jacobian
             * amplifies that by up to 1/0.174 (its smallest singular value, mm per mm or
             * deg, headplan analyze): sqrt(8) x 1e-9 x 5.7 = 1.6e-8. Measured: 1.2e-9. */
            double back[6];
            assert_int_equal(lf_round_trip(&L, level, &r, back), HP_OK);
            double rt = pose_diff(back, r.achieved);
            if (rt > worst_rt) worst_rt = rt;
            if (!(rt <= 2e-8)) {
                print_error("%s level %s target %d: round trip %.3g from achieved\n", name,
                            hp_level_name(level), t, rt);
                fail();
            }
            double diff = pose_diff(r.achieved, ref.achieved);
            if (diff > worst[b]) worst[b] = diff;
            if (!(diff <= agree_tolerance(backends[b]))) {
                print_error("%s level %s target %d: closest pose %.3g from Ipopt's (> %.3g)\n",
                            name, hp_level_name(level), t, diff, agree_tolerance(backends[b]));
                fail();
            }
            for (int k = 0; k < L.n; ++k) {
                if ((r.bladders[k].binding != 0) != (ref.bladders[k].binding != 0)) {
                    print_error("%s level %s target %d: bladder %s binding %#x, Ipopt %#x\n", name,
                                hp_level_name(level), t, L.bladders[k].name, r.bladders[k].binding,
                                ref.bladders[k].binding);
                    fail();
                }
            }
        }
    }
    print_message("level %-7s worst round trip from the achieved pose %.3g\n", hp_level_name(level),
                  worst_rt);
    for (int b = 1; b < N_BACKENDS; ++b)
        print_message("level %-7s %-12s worst closest-pose difference from Ipopt %.3g\n",
                      hp_level_name(level), hp_backend_name(backends[b]), worst[b]);
    for (int b = 0; b < N_BACKENDS; ++b) hp_planner_destroy(p[b]);
}

/* A loose tolerance is an answer, not a failure: Ipopt at tolerance 1e-4 (mm, deg) on the
 * unreachable targets answers CLOSEST with a named binding limit on every one, within 1e-3
 * mm/deg of its own 1e-9 answer (ten times the tolerance: the stopping test bounds the
 * optimality error, the pose error follows it through the contact curvature). Its
 * interior point used to stop up to ~1e-5 mm inside the active bounds, where the planner's
 * one binding threshold (1e-6 mm) sees no limit, and 35 of the benchmark's 40 binding
 * targets came back solver-error; the backend now drives complementarity to 1e-10 whatever
 * the tolerance (docs/backends.md). */
static void loose_tolerance_at(hp_level level)
{
    hp_layout L;
    assert_int_equal(lf_layout(&L), HP_OK);
    hp_planner *tight = make(&L, HP_BACKEND_IPOPT, level);
    hp_settings s;
    hp_settings_default(&s);
    s.backend = HP_BACKEND_IPOPT;
    s.level = level;
    s.tolerance = 1e-4;
    s.max_time = 60.0;
    carry_at_load(&L, &s);
    hp_planner *loose = NULL;
    hp_diag d = {{0}};
    assert_int_equal(hp_planner_create(&L, &s, &loose, &d), HP_OK);
    uint64_t seed = 0x1005eu + (uint64_t)level;
    int done = 0;
    double worst = 0.0;
    for (int t = 0; done < N_UNREACH / 2; ++t) {
        assert_true(t < 10 * N_UNREACH);
        double c[6], xi[6];
        for (int i = 0; i < 6; ++i) c[i] = (i < 3 ? 8.0 : 4.0) * lf_uniform(&seed);
        lf_pose(c, xi);
        hp_result ref, r;
        hp_planner_reset(tight);
        assert_int_equal(hp_plan(tight, xi, &ref), HP_OK);
        /* Not REACHED, and not refused: at the load level a target whose closest held pose
         * is only a saddle is refused at every tolerance (docs/load.md, "Stable holds"). */
        if (ref.status != HP_STATUS_CLOSEST) continue;
        ++done;
        hp_planner_reset(loose);
        assert_int_equal(hp_plan(loose, xi, &r), HP_OK);
        if (r.status != HP_STATUS_CLOSEST)
            print_error("ipopt 1e-4 level %s target %d: %s (%s)\n", hp_level_name(level), t,
                        hp_status_name(r.status), hp_planner_error(loose));
        assert_int_equal(r.status, HP_STATUS_CLOSEST);
        check_limits(&L, &r, "ipopt 1e-4");
        int binds = 0;
        for (int k = 0; k < L.n; ++k) binds |= r.bladders[k].binding != 0;
        assert_true(binds);
        double diff = pose_diff(r.achieved, ref.achieved);
        worst = fmax(worst, diff);
        assert_true(diff <= 1e-3);
    }
    print_message("level %-7s ipopt at tolerance 1e-4: worst pose difference from 1e-9 %.3g\n",
                  hp_level_name(level), worst);
    hp_planner_destroy(tight);
    hp_planner_destroy(loose);
}

static void test_loose_tolerance(void **s)
{
    (void)s;
    const hp_level levels[4] = {HP_LEVEL_LINEAR, HP_LEVEL_PLANE, HP_LEVEL_SURFACE, HP_LEVEL_LOAD};
    for (int l = 0; l < 4; ++l) loose_tolerance_at(levels[l]);
}

static void test_reachable_linear(void **s)
{
    (void)s;
    reachable_at(HP_LEVEL_LINEAR);
}
static void test_reachable_plane(void **s)
{
    (void)s;
    reachable_at(HP_LEVEL_PLANE);
}
static void test_reachable_surface(void **s)
{
    (void)s;
    reachable_at(HP_LEVEL_SURFACE);
}
static void test_unreachable_linear(void **s)
{
    (void)s;
    unreachable_at(HP_LEVEL_LINEAR);
}
static void test_unreachable_plane(void **s)
{
    (void)s;
    unreachable_at(HP_LEVEL_PLANE);
}
static void test_unreachable_surface(void **s)
{
    (void)s;
    unreachable_at(HP_LEVEL_SURFACE);
}

/* A clinical pose tolerance (0.05, 0.5 mm/deg) is the acceptance of an answer, not the
 * solver's precision: NLopt is handed at most the default tolerance, so a binding target
 * gets the very answer the default tolerance gives (bit for bit). Before, the pose tolerance
 * was NLopt's contact, step and objective tolerance: SLSQP's radii left their contacts by
 * up to 0.05 mm and held no pose, COBYLA's optimum failed the KKT check, and most binding
 * targets came back SOLVER_ERROR (the safe output) or ITERATION_LIMIT. */
static void nlopt_loose_tolerance(void **state)
{
    (void)state;
    hp_layout L;
    assert_int_equal(lf_layout(&L), HP_OK);
    const hp_backend bes[2] = {HP_BACKEND_NLOPT_SLSQP, HP_BACKEND_NLOPT_COBYLA};
    /* Not the load level: the tolerance mapping under test is the contact NLopt solve's
     * (COBYLA does not plan the load level at all). */
    const hp_level levels[2] = {HP_LEVEL_LINEAR, HP_LEVEL_SURFACE};
    uint64_t seed = 77;
    double targets[12][6];
    for (int t = 0; t < 12; ++t) {
        double cl[6];
        for (int i = 0; i < 6; ++i) cl[i] = 6.0 * lf_uniform(&seed);
        lf_pose(cl, targets[t]);
    }
    for (int bi = 0; bi < 2; ++bi)
        for (int li = 0; li < 2; ++li) {
            hp_settings s;
            hp_settings_default(&s);
            s.backend = bes[bi];
            s.level = levels[li];
            s.max_time = 60.0;
            hp_planner *ref = NULL, *p = NULL;
            assert_int_equal(hp_planner_create(&L, &s, &ref, NULL), HP_OK);
            s.tolerance = li ? 0.5 : 0.05;
            assert_int_equal(hp_planner_create(&L, &s, &p, NULL), HP_OK);
            int closest = 0;
            for (int t = 0; t < 12; ++t) {
                hp_result r, rr;
                assert_int_equal(hp_plan(ref, targets[t], &rr), HP_OK);
                assert_int_equal(hp_plan(p, targets[t], &r), HP_OK);
                if (rr.status != HP_STATUS_CLOSEST || rr.pose_error <= s.tolerance) continue;
                if (r.status != HP_STATUS_CLOSEST)
                    print_error("%s %s target %d: %s: %s\n", hp_backend_name(bes[bi]),
                                hp_level_name(levels[li]), t, hp_status_name(r.status),
                                hp_planner_error(p));
                assert_int_equal(r.status, HP_STATUS_CLOSEST);
                for (int k = 0; k < L.n; ++k)
                    assert_true(r.bladders[k].pressure == rr.bladders[k].pressure);
                ++closest;
            }
            assert_true(closest >= 6);
            hp_planner_destroy(p);
            hp_planner_destroy(ref);
        }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_reachable_linear),  cmocka_unit_test(test_reachable_plane),
        cmocka_unit_test(test_reachable_surface), cmocka_unit_test(test_unreachable_linear),
        cmocka_unit_test(test_unreachable_plane), cmocka_unit_test(test_unreachable_surface),
        cmocka_unit_test(test_loose_tolerance),   cmocka_unit_test(nlopt_loose_tolerance),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
