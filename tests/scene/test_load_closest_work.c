/* The work of CLOSEST (planner/load_closest.c, docs/load.md), counted, not timed:
 * load_tilted's own correction, planned with the scene's settings (realtime backend), is not
 * held at the desired pose, so the plan runs CLOSEST, whose every evaluation of its rows
 * needs each bladder's carrying force range at the pose. The answer is checked by the
 * planner's own forward-model confirmation (test_load_answers covers it independently). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include "headplan/hp_planner.h"
#include "headplan/hp_scene.h"
#include "planner/load_solve.h"
#include "support/load_fixture.h"

#include <stdlib.h>

/* The ends of a bladder's carrying range at a pressure bound (its lower bound when that
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
    hp_scene *sc = malloc(sizeof *sc);
    assert_non_null(sc);
    hp_diag d = {{0}};
    assert_int_equal(hp_scene_load(HP_SOURCE_DIR "/scenarios/load_tilted.yaml", sc, &d), HP_OK);
    assert_true(sc->has_correction);
    hp_settings set;
    assert_int_equal(hp_scene_settings(sc, &set, NULL), HP_OK);
    set.level = sc->load_geometry;
    set.max_time = 60.0; /* never time-limited: the counts, not the clock, are asserted */
    hp_planner *p = NULL;
    assert_int_equal(
        load_create(&sc->layout, &sc->load, &set, (hp_load_tiebreak)sc->load_tiebreak, &p, &d),
        HP_OK);
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
    const struct CMUnitTest tests[] = {cmocka_unit_test(test_tilted_closest_work)};
    return cmocka_run_group_tests(tests, NULL, NULL);
}
