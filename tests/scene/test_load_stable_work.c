/* The work of HOLD's stable search (planner/load_stable.c, docs/load.md "Stable holds: the
 * bounds on work"), counted, not timed: load_supine's own correction, planned with the
 * scene's settings (realtime backend), runs the search past the pick's own test (its
 * least-squeeze pick is not stable there), and the search solves the pressures of at most
 * STABLE_POINTS points of the set outside its scan (the segment's 10 halvings: the pick's
 * pressures and inner radii come from HOLD's answer, re-solved from its forces before: 11;
 * the scan's point c comes with its pressures from the replay of HOLD's scan, re-solved
 * before that: 12) and at most STABLE_TESTS stability tests (the scan's included), per
 * search. The answer stays REACHED and confirmed by the forward model (test_load_stable
 * checks that independently). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include "headplan/hp_planner.h"
#include "headplan/hp_scene.h"
#include "planner/load_solve.h"
#include "planner/load_stable.h"
#include "support/load_fixture.h"

#include <stdio.h>
#include <stdlib.h>

#define STABLE_POINTS 10
/* A scan's vertices come from the elimination its grid already made (each force affine in
 * the at most two free ones, a vertex two of them fixed: a 2×2 solve; a least-squares
 * factorisation per pair of carrying bladders before, 56 in this plan): at most four per
 * pair of carrying bladders, 4·C(8, 2) a scan, and the supine scene's eight carrying
 * bladders give the scan vertices to visit. */
#define SCAN_VERTICES (4 * 28)
#define STABLE_TESTS 60
#define SEARCH_STEPS_MEAN 2.3

/* The planner of a catalogue scene (scenarios/NAME) with the scene's settings (realtime
 * backend); *sc gets the scene (freed by the caller). */
static hp_planner *scene_planner(const char *name, hp_scene **sc)
{
    char path[512];
    snprintf(path, sizeof path, "%s/scenarios/%s", HP_SOURCE_DIR, name);
    *sc = malloc(sizeof **sc);
    assert_non_null(*sc);
    hp_diag d = {{0}};
    assert_int_equal(hp_scene_load(path, *sc, &d), HP_OK);
    assert_true((*sc)->has_correction);
    hp_settings set;
    assert_int_equal(hp_scene_settings(*sc, &set, NULL), HP_OK);
    set.level = (*sc)->load_geometry;
    set.max_time = 60.0; /* never time-limited: the counts, not the clock, are asserted */
    hp_planner *p = NULL;
    assert_int_equal(load_create(&(*sc)->layout, &(*sc)->load, &set,
                                 (hp_load_tiebreak)(*sc)->load_tiebreak, &p, &d),
                     HP_OK);
    return p;
}

static void test_supine_work(void **state)
{
    (void)state;
    hp_scene *sc;
    hp_planner *p = scene_planner("load_supine.yaml", &sc);
    hp_test_stable_counts c0, c1;
    unsigned long s0, f0, s1, f1, e0, e1;
    hpi_test_stable_counts(&c0);
    hpi_test_scan_counts(&s0, &f0);
    hpi_test_eigen_counts(&e0);
    hp_result r;
    assert_int_equal(hp_plan(p, sc->correction, &r), HP_OK);
    hpi_test_stable_counts(&c1);
    hpi_test_scan_counts(&s1, &f1);
    hpi_test_eigen_counts(&e1);
    assert_int_equal(r.status, HP_STATUS_REACHED);
    unsigned long s = c1.searches - c0.searches, pts = c1.points - c0.points,
                  eig = c1.eigen - c0.eigen, tests = c1.tests - c0.tests;
    print_message("load_supine: %lu stable searches, %lu points, %lu stability tests, %lu "
                  "eigenproblems\n",
                  s, pts, tests, eig);
    assert_true(s >= 1);
    assert_true(pts <= STABLE_POINTS * s);
    /* Every point the search solved is tested, and so is the pick (its own test); the
     * rest are the scan's, asked only of a point that would win (at most its 9 grid
     * points and the improvements among its vertices: 3 in this plan). */
    assert_true(tests >= pts + s);
    assert_true(tests <= STABLE_TESTS * s);
    /* No eigenproblem in the whole plan: a stability test is a Cholesky factorisation of
     * K − margin·I (15 eigenproblems in this plan before), and the forward model's
     * confirmation of a REACHED answer asks whether K is positive definite, not its
     * smallest eigenvalue, which only the refusal's message prints (1 before). */
    assert_int_equal(eig, 0);
    assert_int_equal(e1 - e0, 0);
    /* The segment's points lie between two points whose inner radii are known (the ends of
     * the bisection's bracket), so each of their pressure solves starts from the secant of
     * that bracket and stops after its first step below 1e-8 of the radius: 2.11 a solve on
     * this plan. The pick's radii come from its pressures (no solve); its solves from the
     * carrying range's ends, about five steps each, made 2.36 a solve before; 3.20 when the
     * segment's solves ran to a step of two ulps, 5.13 when every point started from the
     * carrying range's ends. */
    const unsigned long ps = c1.solves - c0.solves, st = c1.steps - c0.steps;
    print_message("load_supine: the search's points: %lu pressure solves, %lu steps (%.2f a "
                  "solve)\n",
                  ps, st, ps ? (double)st / (double)ps : 0.0);
    assert_true(ps >= 1);
    assert_true((double)st <= SEARCH_STEPS_MEAN * (double)ps);
    print_message("load_supine: %lu scans, %lu vertices\n", s1 - s0, f1 - f0);
    /* One scan: HOLD's. The search replays HOLD's recorded scan points (their sums, forces,
     * pressures and radii) instead of scanning the same set again (2 scans before). */
    assert_int_equal(s1 - s0, 1);
    /* Every pair of the eight carrying bladders fixes the two free forces here (no singular
     * pair), so the scan solves for all its 4·C(8, 2) candidate vertices, no more, no less. */
    assert_int_equal(f1 - f0, SCAN_VERTICES * (s1 - s0));
    hp_planner_destroy(p);
    free(sc);
}

/* The pressure-of-force solves (planner/load_solve.c, pressure_of_force_in: safeguarded
 * Newton in the inner radius) of load_supine's plan: Newton converges quadratically from a
 * start inside a bracket of about 20 % of ri, and every solve stops after its first step of
 * at most 1e-8 of the radius (that step applied leaves an error of the order of its square:
 * rounding), so a solve from the carrying range's ends takes about four steps and one from
 * the stable search's narrow brackets about two: 2.89 a solve on this plan (3.37 when the
 * solves from the carrying range's ends ran on to a step of two ulps). A solve whose Newton
 * step lands on an end of its bracket (the root itself, once a residual of rounding size has
 * moved that end there) must stop, not halve the bracket down to two ulps (50 steps: 10.2 a
 * solve on average before that). */
#define PRESSURE_STEPS_MEAN 3.0

static void test_supine_pressure_steps(void **state)
{
    (void)state;
    hp_scene *sc;
    hp_planner *p = scene_planner("load_supine.yaml", &sc);
    unsigned long n0, s0, l0, n1, s1, l1, m0, m1;
    hpi_test_pressure_counts(&n0, &s0, &l0);
    hpi_test_pressure_model_counts(&m0);
    hp_result r;
    assert_int_equal(hp_plan(p, sc->correction, &r), HP_OK);
    hpi_test_pressure_counts(&n1, &s1, &l1);
    hpi_test_pressure_model_counts(&m1);
    assert_int_equal(r.status, HP_STATUS_REACHED);
    const double mean = (double)(s1 - s0) / (double)(n1 - n0);
    print_message("load_supine: %lu pressure solves, %lu steps (%.2f a solve), %lu over %d\n",
                  n1 - n0, s1 - s0, mean, l1 - l0, HP_LOAD_PRESSURE_STEPS_LONG);
    assert_true(n1 - n0 >= 50);
    assert_true(mean <= PRESSURE_STEPS_MEAN);
    assert_int_equal(l1 - l0, 0);
    /* A step's pressure, slope and outer radius come from one pass through the bladder model
     * (the pressure's closed form forms the outer radius anyway), validated once a solve; a
     * solve that stops after its step passes once more for the pressure at the stepped
     * radius: at most steps + solves passes (2·steps + solves before: the pressure and the
     * outer radius each validated and formed on their own). */
    print_message("load_supine: %lu passes through the bladder model\n", m1 - m0);
    assert_true(m1 - m0 <= (s1 - s0) + (n1 - n0));
    hp_planner_destroy(p);
    free(sc);
}

/* HOLD's work at one pose (planner/load_solve.c): the realtime tie-breaker's two starts
 * share one holding set, and the stable search takes that set from HOLD, so a plan whose
 * pick needs the search forms one (two before: HOLD's and the search's), and only the SQP's steps evaluate a bladder's force
 * derivatives (one state a carrying bladder a step: at most n·(iterations + 2) with the two
 * starts' last states; 148 in this plan before, where the scan, the set's ends and the line
 * search asked for them too). */
#define HOLD_FK_PER_CARRY 5.5

static void test_supine_hold_work(void **state)
{
    (void)state;
    hp_scene *sc;
    hp_planner *p = scene_planner("load_supine.yaml", &sc);
    unsigned long s0, d0, s1, d1, k0, k1;
    hpi_test_hold_counts(&s0, &d0);
    hpi_test_fk_counts(&k0);
    hp_result r;
    assert_int_equal(hp_plan(p, sc->correction, &r), HP_OK);
    hpi_test_hold_counts(&s1, &d1);
    hpi_test_fk_counts(&k1);
    assert_int_equal(r.status, HP_STATUS_REACHED);
    const unsigned long n = (unsigned long)sc->layout.n;
    print_message("load_supine: %lu holding sets, %lu derived bladder states, %d iterations, "
                  "%lu forward-kinematics solves\n",
                  s1 - s0, d1 - d0, r.iterations, k1 - k0);
    assert_int_equal(s1 - s0, 1);
    assert_true(d1 - d0 <= n * ((unsigned long)r.iterations + 2));
    /* A bladder's inner radius at a pressure (its forward kinematics, an iterative solve) is
     * solved once per pressure, and not at all where a closed form gives it: the set's
     * carrying ends at the touching pressure (the radius whose outer radius is the contact
     * distance) and at the indentation cap (the one whose outer radius is rho/(1 − indent
     * max)) come from the bladder's volume law; the set's ends serve the scans' grid ends and
     * the SQPs' starts and bounds, and a force the line search or the SQP already evaluated
     * at that pressure is not evaluated again. With both starts' steps (the first start's
     * start forces, each start's SQP state and line search, the interior grid pressures,
     * the stable search's pick): at most HOLD_FK_PER_CARRY a carrying bladder (43 in this plan,
     * 5.4 a bladder; 130 before, 16.25 a bladder; 49 with both of the set's ends solved by
     * the forward kinematics). */
    assert_true((double)(k1 - k0) <= HOLD_FK_PER_CARRY * (double)n);
    hp_planner_destroy(p);
    free(sc);
}

/* CLOSEST's work (planner/load_closest.c), counted: load_tilted's own correction, planned
 * with the scene's settings, is not held at the desired pose, so the plan runs CLOSEST,
 * whose every evaluation of its rows needs each bladder's carrying force range at the pose.
 * The ends of a bladder's carrying range at a pressure bound (its lower bound when that
 * already carries, its upper bound) do not move with the pose: their free outer radii are
 * solved once a CLOSEST solve, not at every evaluation of its rows. Only an end at the
 * indentation cap, whose pressure moves with the contact distance, needs one an evaluation:
 * at most RADII_PER_EVAL a bladder an evaluation on this plan (its 8 solves and 721
 * evaluations ask 64, the bounds' only; 5832 before, 1.01 a bladder an evaluation: every
 * bladder's upper bound solved again at each evaluation). */
#define RADII_PER_EVAL 0.5

static void test_tilted_closest_work(void **state)
{
    (void)state;
    hp_scene *sc;
    hp_planner *p = scene_planner("load_tilted.yaml", &sc);
    unsigned long s0, e0, r0, s1, e1, r1;
    hpi_test_closest_counts(&s0, &e0, &r0);
    hp_result r;
    assert_int_equal(hp_plan(p, sc->correction, &r), HP_OK);
    hpi_test_closest_counts(&s1, &e1, &r1);
    const unsigned long n = (unsigned long)sc->layout.n, sv = s1 - s0, ev = e1 - e0, rad = r1 - r0;
    print_message("load_tilted: status %d, %lu CLOSEST solves, %lu evaluations, %lu free radii "
                  "(%.2f a bladder an evaluation)\n",
                  (int)r.status, sv, ev, rad, ev ? (double)rad / (double)(ev * n) : 0.0);
    assert_int_equal(r.status, HP_STATUS_CLOSEST);
    assert_true(ev >= 1);
    /* The bounds' radii: two a bladder a solve. */
    assert_true((double)rad <= RADII_PER_EVAL * (double)(ev * n) + 2.0 * (double)(sv * n));
    hp_planner_destroy(p);
    free(sc);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_supine_work), cmocka_unit_test(test_supine_pressure_steps),
        cmocka_unit_test(test_supine_hold_work), cmocka_unit_test(test_tilted_closest_work)};
    return cmocka_run_group_tests(tests, NULL, NULL);
}
