/* The planner's printf-free number formatting (planner/plan_text.c): a request for more
 * decimals than its 16-byte fraction buffer holds is clamped to 15, not written past it. The
 * reference is the digit string itself: 0 to 15 decimals is "0." and fifteen zeros. */
#include "support/test_util.h"
#include "planner/planner_internal.h"

#include <string.h>

static void decimals_within_buffer(void **state)
{
    (void)state;
    const char *zeros15 = "0.000000000000000";
    int decs[] = {15, 16, 17, 40};
    for (size_t i = 0; i < sizeof decs / sizeof decs[0]; ++i) {
        char buf[HP_DIAG_MAX];
        hpi_text_set(buf, "");
        hpi_text_add_num(buf, 0.0, decs[i]);
        assert_string_equal(buf, zeros15);
    }
}

static void ordinary_decimals(void **state)
{
    (void)state;
    char buf[HP_DIAG_MAX];
    hpi_text_set(buf, "");
    hpi_text_add_num(buf, -1.25, 3);
    assert_string_equal(buf, "-1.250");
    hpi_text_set(buf, "");
    hpi_text_add_num(buf, 7.0, 0);
    assert_string_equal(buf, "7");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(decimals_within_buffer),
        cmocka_unit_test(ordinary_decimals),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
