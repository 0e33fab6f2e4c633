/* A library message reads the same under a host's comma locale as under C: hp_diag_set wrote
 * its %g in the thread's LC_NUMERIC, so a host that had set de_DE read "got -0,5" where the
 * command line (which runs in C) read "got -0.5" for the same refused bladder. */
#define _POSIX_C_SOURCE 200809L
#include "support/test_util.h"
#include "support/comma_locale.h"

#include "headplan/hp_iab.h"

#include <errno.h>
#include <locale.h>
#include <string.h>

static void test_message_in_c_locale(void **state)
{
    (void)state;
    if (!comma_locale()) {
        print_message("no comma-decimal locale could be set or built: skipped\n");
        skip();
    }
    hp_iab b = {-0.5, 0.03, 1.1e4, 2.2e4};
    hp_diag d = {{0}};
    errno = ERANGE;
    assert_int_equal(hp_iab_validate(&b, &d), HP_ERR_INVALID);
    assert_string_equal(d.text, "Ri: must be > 0 m (got -0.5)");
    /* the thread's locale and errno are the caller's again */
    assert_true(is_comma());
    assert_int_equal(errno, ERANGE);
    hp_diag_set(&d, HP_ERR_INVALID, "%g %.3f", 1.5, 2.25);
    assert_string_equal(d.text, "1.5 2.250");
    setlocale(LC_NUMERIC, "C");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_message_in_c_locale),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
