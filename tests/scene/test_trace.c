/* Trace reader: CSV and JSON Lines, deviation vs correction, and every bad-row class with the
 * line it names. References are the hand-written inputs themselves: the reader must return
 * exactly the numbers written (decimal -> double is correctly rounded by strtod, and the
 * mm/deg -> SI conversion is checked against the same conversion done here). */
#include "test_util.h"
#include "headplan/hp_kinematics.h"
#include "headplan/hp_trace.h"

#include <string.h>

static hp_trace_reader *open_text(const char *text, hp_trace_format fmt)
{
    hp_trace_reader *r = NULL;
    hp_diag d = {{0}};
    hp_error e = hp_trace_open_mem(text, strlen(text), "t", fmt, NULL, &r, &d);
    if (e != HP_OK) print_error("open failed: %s\n", d.text);
    assert_int_equal(e, HP_OK);
    return r;
}

static void expect_row(hp_trace_reader *r, long line, double t, const double mm_deg[6])
{
    hp_trace_row row;
    hp_diag d = {{0}};
    hp_error e = hp_trace_next(r, &row, &d);
    if (e != HP_OK) print_error("row failed: %s\n", d.text);
    assert_int_equal(e, HP_OK);
    assert_int_equal(row.line, line);
    assert_true(row.t == t);
    double si[6];
    hp_pose_from_clinical(mm_deg, si);
    for (int i = 0; i < 6; ++i) assert_true(row.correction[i] == si[i]);
}

static void expect_bad(hp_trace_reader *r, const char *needle)
{
    hp_trace_row row;
    hp_diag d = {{0}};
    hp_error e = hp_trace_next(r, &row, &d);
    assert_int_equal(e, HP_ERR_PARSE);
    if (!strstr(d.text, needle)) print_error("message '%s' lacks '%s'\n", d.text, needle);
    assert_non_null(strstr(d.text, needle));
}

static void expect_end(hp_trace_reader *r)
{
    hp_trace_row row;
    assert_int_equal(hp_trace_next(r, &row, NULL), HP_ERR_STATE);
}

static void csv_corrections(void **state)
{
    (void)state;
    hp_trace_reader *r = open_text("t_s,x_mm,y_mm,z_mm,pitch_deg,roll_deg,yaw_deg\n"
                                   "0,1,2,3,0.5,-0.25,0\n"
                                   "\n"
                                   "# a comment\n"
                                   "0.1,1e-3,-2.5,0,0,0,90\n",
                                   HP_TRACE_CSV);
    assert_int_equal(hp_trace_rows_of(r), HP_TRACE_CORRECTION);
    expect_row(r, 2, 0.0, (const double[6]){1, 2, 3, 0.5, -0.25, 0});
    expect_row(r, 5, 0.1, (const double[6]){1e-3, -2.5, 0, 0, 0, 90});
    expect_end(r);
    hp_trace_close(r);
}

static void csv_deviation_negated(void **state)
{
    (void)state;
    hp_trace_reader *r = open_text("# rows: deviation\n"
                                   "t_s,x_mm,y_mm,z_mm,pitch_deg,roll_deg,yaw_deg\n"
                                   "0,1,-2,0,0.5,0,0\n",
                                   HP_TRACE_CSV);
    assert_int_equal(hp_trace_rows_of(r), HP_TRACE_DEVIATION);
    expect_row(r, 3, 0.0, (const double[6]){-1, 2, 0, -0.5, 0, 0});
    hp_trace_close(r);
}

static void csv_bad_rows_continue(void **state)
{
    (void)state;
    hp_trace_reader *r = open_text("t_s,x_mm,y_mm,z_mm,pitch_deg,roll_deg,yaw_deg\n"
                                   "0,1,2,3,4,5\n"
                                   "0,1,2,3,4,5,6,7\n"
                                   "0,1.5abc,2,3,4,5,6\n"
                                   "0,nan,2,3,4,5,6\n"
                                   "0,1e999,2,3,4,5,6\n"
                                   "0,,2,3,4,5,6\n"
                                   "1,0,0,0,0,0,0\n"
                                   "2,0,0,0,0,0,0",
                                   HP_TRACE_CSV);
    expect_bad(r, "t:2: 6 fields, expected 7");
    expect_bad(r, "t:3: more than 7 fields");
    expect_bad(r, "t:4: x_mm: not a number");
    expect_bad(r, "t:5: x_mm: not a number");
    expect_bad(r, "t:6: x_mm: overflows a double");
    expect_bad(r, "t:7: x_mm: empty");
    expect_row(r, 8, 1.0, (const double[6]){0, 0, 0, 0, 0, 0});
    expect_bad(r, "t:9: truncated");
    expect_end(r);
    hp_trace_close(r);
}

static void csv_bad_header(void **state)
{
    (void)state;
    const char *cases[][2] = {
        {"", "empty trace"},
        {"t,x,y,z\n", "t:1: header must be"},
        {"# rows: sideways\nt_s,x_mm,y_mm,z_mm,pitch_deg,roll_deg,yaw_deg\n", "t:1: rows:"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        hp_trace_reader *r = NULL;
        hp_diag d = {{0}};
        hp_error e = hp_trace_open_mem(cases[i][0], strlen(cases[i][0]), "t", HP_TRACE_CSV,
                                       NULL, &r, &d);
        assert_int_equal(e, HP_ERR_PARSE);
        assert_null(r);
        if (!strstr(d.text, cases[i][1])) print_error("'%s' lacks '%s'\n", d.text, cases[i][1]);
        assert_non_null(strstr(d.text, cases[i][1]));
    }
}

static void jsonl_rows(void **state)
{
    (void)state;
    hp_trace_reader *r = open_text(
        "{\"rows\": \"deviation\"}\n"
        "{\"t_s\":0,\"x_mm\":1,\"y_mm\":0,\"z_mm\":0,\"pitch_deg\":0,\"roll_deg\":0,\"yaw_deg\":2}\n"
        "{\"t_s\":0,\"x_mm\":1}\n"
        "{\"t_s\":0,\"x_mm\":1,\"y_mm\":0,\"z_mm\":0,\"pitch_deg\":0,\"roll_deg\":0,\"yaw_deg\":2,"
        "\"w\":1}\n"
        "{\"t_s\":0,\"x_mm\":\"1\",\"y_mm\":0,\"z_mm\":0,\"pitch_deg\":0,\"roll_deg\":0,"
        "\"yaw_deg\":2}\n"
        "[1,2]\n"
        "{\"t_s\":0,\"t_s\":1}\n"
        "{\"t_s\":1,\"x_mm\":0,\"y_mm\":0,\"z_mm\":0,\"pitch_deg\":0,\"roll_deg\":0,\"yaw_deg\":0}\n",
        HP_TRACE_JSONL);
    assert_int_equal(hp_trace_rows_of(r), HP_TRACE_DEVIATION);
    expect_row(r, 2, 0.0, (const double[6]){-1, 0, 0, 0, 0, -2});
    expect_bad(r, "t:3: missing key 'y_mm'");
    expect_bad(r, "t:4: unknown key 'w'");
    expect_bad(r, "t:5: x_mm: not a number");
    expect_bad(r, "t:6: expected a JSON object");
    expect_bad(r, "t:7:");
    expect_row(r, 8, 1.0, (const double[6]){0, 0, 0, 0, 0, 0});
    expect_end(r);
    hp_trace_close(r);
}

static void jsonl_first_line_is_data(void **state)
{
    (void)state;
    hp_trace_reader *r = open_text(
        "{\"t_s\":0,\"x_mm\":1,\"y_mm\":0,\"z_mm\":0,\"pitch_deg\":0,\"roll_deg\":0,\"yaw_deg\":0}\n",
        HP_TRACE_JSONL);
    assert_int_equal(hp_trace_rows_of(r), HP_TRACE_CORRECTION);
    expect_row(r, 1, 0.0, (const double[6]){1, 0, 0, 0, 0, 0});
    expect_end(r);
    hp_trace_close(r);
}

static void override_and_names(void **state)
{
    (void)state;
    const char *text = "# rows: deviation\nt_s,x_mm,y_mm,z_mm,pitch_deg,roll_deg,yaw_deg\n"
                       "0,1,0,0,0,0,0\n";
    hp_trace_rows corr = HP_TRACE_CORRECTION;
    hp_trace_reader *r = NULL;
    assert_int_equal(hp_trace_open_mem(text, strlen(text), "t", HP_TRACE_CSV, &corr, &r, NULL),
                     HP_OK);
    assert_int_equal(hp_trace_rows_of(r), HP_TRACE_CORRECTION);
    expect_row(r, 3, 0.0, (const double[6]){1, 0, 0, 0, 0, 0});
    hp_trace_close(r);
    hp_trace_close(NULL);

    hp_trace_rows rows;
    hp_trace_format fmt;
    assert_int_equal(hp_trace_rows_parse("deviation", &rows), HP_OK);
    assert_string_equal(hp_trace_rows_name(rows), "deviation");
    assert_int_equal(hp_trace_rows_parse("Deviation", &rows), HP_ERR_INVALID);
    assert_int_equal(hp_trace_format_parse("jsonl", &fmt), HP_OK);
    assert_string_equal(hp_trace_format_name(fmt), "jsonl");
    assert_int_equal(hp_trace_format_parse("tsv", &fmt), HP_ERR_INVALID);
    hp_diag d = {{0}};
    assert_int_equal(hp_trace_open("/nonexistent/x.csv", NULL, &r, &d), HP_ERR_IO);
    assert_non_null(strstr(d.text, "/nonexistent/x.csv: cannot open"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(csv_corrections),       cmocka_unit_test(csv_deviation_negated),
        cmocka_unit_test(csv_bad_rows_continue), cmocka_unit_test(csv_bad_header),
        cmocka_unit_test(jsonl_rows),            cmocka_unit_test(jsonl_first_line_is_data),
        cmocka_unit_test(override_and_names),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
