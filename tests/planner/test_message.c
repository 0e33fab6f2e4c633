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

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_message_follows_status),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
