/* hp_planner_message: the one call that gives the last plan's message whatever its status
 * (the failure's text, the answer's note, "" after REACHED), so a caller that shows "the
 * message" does not have to know which of the two channels a status writes. */
#include "support/test_util.h"
#include "support/layout_fixture.h"

static void test_message_follows_status(void **st)
{
    (void)st;
    hp_layout L;
    assert_int_equal(lf_layout(&L), HP_OK);
    hp_planner *p = NULL;
    assert_int_equal(hp_planner_create(&L, NULL, &p, NULL), HP_OK);
    hp_result r;
    double xi[6];

    /* REACHED: no message. */
    double small[6] = {0.5, 0.2, -0.3, 0.2, 0.1, -0.2};
    lf_pose(small, xi);
    assert_int_equal(hp_plan(p, xi, &r), HP_OK);
    assert_int_equal(r.status, HP_STATUS_REACHED);
    assert_string_equal(hp_planner_message(p), "");

    /* CLOSEST: hp_planner_error is "" (an answer, not a failure), the message is the note
     * naming the binding limit. */
    double far[6] = {30, 0, 0, 0, 0, 0};
    lf_pose(far, xi);
    assert_int_equal(hp_plan(p, xi, &r), HP_OK);
    assert_int_equal(r.status, HP_STATUS_CLOSEST);
    assert_string_equal(hp_planner_error(p), "");
    const char *m = hp_planner_message(p);
    assert_true(m[0] != '\0');
    assert_string_equal(m, hp_planner_note(p));
    assert_non_null(strstr(m, "pressure_"));

    /* A failure: the message is the error's text. */
    double nan6[6] = {NAN, 0, 0, 0, 0, 0};
    assert_int_equal(hp_plan(p, nan6, &r), HP_OK);
    assert_int_equal(r.status, HP_STATUS_INVALID_INPUT);
    assert_true(hp_planner_error(p)[0] != '\0');
    assert_string_equal(hp_planner_message(p), hp_planner_error(p));

    /* And back to REACHED: nothing left over from the failure or the note. */
    lf_pose(small, xi);
    assert_int_equal(hp_plan(p, xi, &r), HP_OK);
    assert_int_equal(r.status, HP_STATUS_REACHED);
    assert_string_equal(hp_planner_message(p), "");
    hp_planner_destroy(p);
    assert_string_equal(hp_planner_message(NULL), "planner is NULL");
}

/* A CLOSEST answer of a backend that does not restart (COBYLA, Ipopt and SLSQP with
 * restarts 0) is the local optimum its one start leads to, and its note says so after the
 * binding limits; Ipopt and SLSQP with their default restarts and the realtime backend
 * (whose closest answers the best-local sweep checks against a multi-start reference) do not
 * add it. The target is
 * 30 mm along x, beyond every bladder's reach at the plane level. */
static void test_closest_note_says_local(void **st)
{
    (void)st;
    hp_layout L;
    assert_int_equal(lf_layout(&L), HP_OK);
    static const struct {
        hp_backend b;
        int restarts; /* -1: the default */
        int local;
    } CASES[] = {
        {HP_BACKEND_IPOPT, 0, 1},         {HP_BACKEND_IPOPT, -1, 0},
        {HP_BACKEND_NLOPT_COBYLA, -1, 1}, {HP_BACKEND_NLOPT_SLSQP, 0, 1},
        {HP_BACKEND_NLOPT_SLSQP, -1, 0},  {HP_BACKEND_REALTIME, -1, 0},
    };
    double far[6] = {30, 0, 0, 0, 0, 0}, xi[6];
    lf_pose(far, xi);
    for (size_t i = 0; i < sizeof CASES / sizeof CASES[0]; ++i) {
        hp_settings s;
        hp_settings_default(&s);
        s.backend = CASES[i].b;
        s.level = HP_LEVEL_PLANE;
        s.max_time = 60.0; /* CLOSEST, never time-limit on a starved machine */
        if (CASES[i].restarts >= 0) s.restarts = CASES[i].restarts;
        hp_planner *p = NULL;
        assert_int_equal(hp_planner_create(&L, &s, &p, NULL), HP_OK);
        hp_result r;
        assert_int_equal(hp_plan(p, xi, &r), HP_OK);
        assert_int_equal(r.status, HP_STATUS_CLOSEST);
        const char *note = hp_planner_note(p);
        char want[128];
        snprintf(want, sizeof want, "; a local optimum: the %s backend made no restarts",
                 hp_backend_name(CASES[i].b));
        print_message("%s restarts %d: %s\n", hp_backend_name(CASES[i].b), s.restarts, note);
        assert_true(strncmp(note, "closest: binding ", 17) == 0);
        if (CASES[i].local) assert_non_null(strstr(note, want));
        else assert_null(strstr(note, "local optimum"));
        assert_string_equal(hp_planner_message(p), note);
        hp_planner_destroy(p);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_message_follows_status),
        cmocka_unit_test(test_closest_note_says_local),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
