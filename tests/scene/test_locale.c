/* Scenes, traces and calibration data read the same numbers whatever LC_NUMERIC the host
 * program set (a Python or GUI host calling setlocale(LC_ALL, "") in Germany): under a comma
 * locale strtod stopped at the '.' of "77.5" and every scene was refused ("'77.5' is not a
 * number"), and a trace's exponent numbers (the strtod path) were bad rows. */
#define _POSIX_C_SOURCE 200809L
#include "support/test_util.h"
#include "support/comma_locale.h"

#include "headplan/hp_scene.h"
#include "headplan/hp_trace.h"
#include "scene/strict_number.h"

#include <locale.h>
#include <stdlib.h>
#include <string.h>

static hp_scene in_c, in_comma; /* large: off the stack */

static void read_trace(const char *text, hp_trace_row *row)
{
    hp_trace_reader *r = NULL;
    hp_diag d = {{0}};
    hp_trace_rows rows = HP_TRACE_CORRECTION;
    assert_int_equal(hp_trace_open_mem(text, strlen(text), "t.csv", HP_TRACE_CSV, &rows, &r, &d),
                     HP_OK);
    hp_error e = hp_trace_next(r, row, &d);
    if (e != HP_OK) print_error("%s\n", d.text);
    assert_int_equal(e, HP_OK);
    hp_trace_close(r);
}

static void test_comma_locale(void **state)
{
    (void)state;
    static const char trace[] = "t_s,x_mm,y_mm,z_mm,pitch_deg,roll_deg,yaw_deg\n"
                                "1.5e-1,1.25e-3,-2.5E+0,0.30000000000000004,1e-30,0.1,-0.2\n";
    hp_diag d = {{0}};
    setlocale(LC_NUMERIC, "C");
    assert_int_equal(hp_scene_load(HP_SOURCE_DIR "/scenarios/default.yaml", &in_c, &d), HP_OK);
    hp_trace_row want, got;
    read_trace(trace, &want);
    double w1, w2, g1, g2;
    assert_null(hpi_strict_double("77.5", 4, &w1));
    assert_null(hpi_strict_double("1.0000000000000002e-300", 23, &w2));

    if (!comma_locale()) {
        print_message("no comma-decimal locale could be set or built: skipped\n");
        skip();
    }
    hp_error e = hp_scene_load(HP_SOURCE_DIR "/scenarios/default.yaml", &in_comma, &d);
    if (e != HP_OK) print_error("%s\n", d.text);
    assert_int_equal(e, HP_OK);
    /* the same scene, byte for byte (both were zeroed before parsing) */
    assert_memory_equal(&in_c, &in_comma, sizeof in_c);
    read_trace(trace, &got);
    assert_memory_equal(&want, &got, sizeof want);
    assert_null(hpi_strict_double("77.5", 4, &g1));
    assert_null(hpi_strict_double("1.0000000000000002e-300", 23, &g2));
    assert_memory_equal(&w1, &g1, sizeof w1);
    assert_memory_equal(&w2, &g2, sizeof w2);
    /* the caller's locale is left as it was */
    assert_true(is_comma());
    setlocale(LC_NUMERIC, "C");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_comma_locale),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
