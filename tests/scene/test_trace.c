/* Trace reader: CSV and JSON Lines, the rows directive, the pose forms, streams, and every
 * bad-row class with the line (and column) it names. References are the hand-written inputs
 * themselves: the reader must return exactly the numbers written (decimal -> double is
 * correctly rounded by strtod, and the mm/deg -> SI conversion and the exact inverse are
 * checked against the same library conversions done here, which test_pose_forms checks
 * against hand derivations). */
#define _POSIX_C_SOURCE 200809L
#include "support/test_util.h"
#include "headplan/hp_pose.h"
#include "headplan/hp_trace.h"

#include <stdio.h>
#include <string.h>
#include <unistd.h>

#define HDR "t_s,x_mm,y_mm,z_mm,pitch_deg,roll_deg,yaw_deg\n"
#define DEV "# headplan-trace: rows=deviation\n"
#define COR "# headplan-trace: rows=correction\n"

static const hp_trace_rows CORRECTION = HP_TRACE_CORRECTION;
static const hp_trace_rows DEVIATION = HP_TRACE_DEVIATION;

static hp_trace_reader *open_rows(const char *text, hp_trace_format fmt, const hp_trace_rows *rows)
{
    hp_trace_reader *r = NULL;
    hp_diag d = {{0}};
    hp_error e = hp_trace_open_mem(text, strlen(text), "t", fmt, rows, &r, &d);
    if (e != HP_OK) print_error("open failed: %s\n", d.text);
    assert_int_equal(e, HP_OK);
    return r;
}

static hp_trace_reader *open_text(const char *text, hp_trace_format fmt)
{
    return open_rows(text, fmt, NULL);
}

/* Opening fails with code and a message containing needle. */
static void expect_open_fails(const char *text, hp_trace_format fmt, const hp_trace_rows *rows,
                              hp_error code, const char *needle)
{
    hp_trace_reader *r = NULL;
    hp_diag d = {{0}};
    hp_error e = hp_trace_open_mem(text, strlen(text), "t", fmt, rows, &r, &d);
    if (e != code || !strstr(d.text, needle))
        print_error("got %d '%s', want %d with '%s'\n", e, d.text, code, needle);
    assert_int_equal(e, code);
    assert_null(r);
    assert_non_null(strstr(d.text, needle));
}

static void expect_si(hp_trace_reader *r, long line, double t, const double si[6])
{
    hp_trace_row row;
    hp_diag d = {{0}};
    hp_error e = hp_trace_next(r, &row, &d);
    if (e != HP_OK) print_error("row failed: %s\n", d.text);
    assert_int_equal(e, HP_OK);
    assert_int_equal(row.line, line);
    assert_true(row.t == t);
    for (int i = 0; i < 6; ++i) assert_true(row.correction[i] == si[i]);
}

static void expect_row(hp_trace_reader *r, long line, double t, const double mm_deg[6])
{
    double si[6];
    hp_pose_from_clinical(mm_deg, si);
    expect_si(r, line, t, si);
}

static void expect_bad(hp_trace_reader *r, const char *needle)
{
    hp_trace_row row;
    hp_diag d = {{0}};
    hp_error e = hp_trace_next(r, &row, &d);
    if (e != HP_ERR_PARSE || !strstr(d.text, needle))
        print_error("got %d '%s', want a bad row with '%s'\n", e, d.text, needle);
    assert_int_equal(e, HP_ERR_PARSE);
    assert_non_null(strstr(d.text, needle));
}

static void expect_end(hp_trace_reader *r)
{
    hp_trace_row row;
    assert_int_equal(hp_trace_next(r, &row, NULL), HP_END);
}

static void csv_corrections(void **state)
{
    (void)state;
    hp_trace_reader *r = open_text(COR "t_s,x_mm,y_mm,z_mm,pitch_deg,roll_deg,yaw_deg\n"
                                       "0,1,2,3,0.5,-0.25,0\n"
                                       "\n"
                                       "# a comment\n"
                                       "0.1,1e-3,-2.5,0,0,0,90\n",
                                   HP_TRACE_CSV);
    assert_int_equal(hp_trace_rows_of(r), HP_TRACE_CORRECTION);
    expect_row(r, 3, 0.0, (const double[6]){1, 2, 3, 0.5, -0.25, 0});
    expect_row(r, 6, 0.1, (const double[6]){1e-3, -2.5, 0, 0, 0, 90});
    expect_end(r);
    hp_trace_close(r);
}

/* A deviation row's correction is its exact inverse, not its negation: for 5 mm / 3° yaw
 * the two differ by 2·5·sin(1.5°) = 0.26 mm in translation. */
static void csv_deviation_inverted(void **state)
{
    (void)state;
    hp_trace_reader *r = open_text(DEV HDR "0,5,0,0,0,0,3\n", HP_TRACE_CSV);
    assert_int_equal(hp_trace_rows_of(r), HP_TRACE_DEVIATION);
    double dev[6], cor[6];
    hp_pose_from_clinical((const double[6]){5, 0, 0, 0, 0, 3}, dev);
    hp_pose_inverse(dev, cor);
    double gap = hypot(cor[0] + dev[0], cor[1] + dev[1]);
    assert_true(gap > 1e-4); /* the old negation would be 0.26 mm off */
    expect_si(r, 3, 0.0, cor);
    hp_trace_close(r);
}

static void csv_bad_rows_continue(void **state)
{
    (void)state;
    hp_trace_reader *r = open_rows("t_s,x_mm,y_mm,z_mm,pitch_deg,roll_deg,yaw_deg\n"
                                   "0,1,2,3,4,5\n"
                                   "0,1,2,3,4,5,6,7\n"
                                   "0,1.5abc,2,3,4,5,6\n"
                                   "0,nan,2,3,4,5,6\n"
                                   "0,1e999,2,3,4,5,6\n"
                                   "0,,2,3,4,5,6\n"
                                   "1,0,0,0,0,0,0\n"
                                   "2,0,0,0,0,0,0",
                                   HP_TRACE_CSV, &CORRECTION);
    expect_bad(r, "t:2: 6 fields, expected 7");
    expect_bad(r, "t:3: more than 7 fields");
    expect_bad(r, "t:4:3: x_mm: not a number");
    expect_bad(r, "t:5:3: x_mm: not a number");
    expect_bad(r, "t:6:3: x_mm: overflows a double");
    expect_bad(r, "t:7:3: x_mm: empty");
    expect_row(r, 8, 1.0, (const double[6]){0, 0, 0, 0, 0, 0});
    expect_bad(r, "t:9:14: truncated: the last line has no end of line");
    expect_end(r);
    hp_trace_close(r);
}

/* A last line without its end of line is named FILE:LINE:COL like every other bad line,
 * the column where its end of line would begin (a '\r' kept counts, as in the calibration
 * reader): the whole message, so that a missing column cannot pass as a prefix. */
#define TRUNC "truncated: the last line has no end of line"
static void truncated_line_column(void **state)
{
    (void)state;
    static const struct {
        const char *text, *want;
    } cases[] = {
        {COR HDR "1,0,0,0,0,0,0\n0.1,0,0", "t:4:8: " TRUNC},
        {COR HDR "0.1,0,0,0,0,0,0\r", "t:3:17: " TRUNC},
        {COR HDR "# end", "t:3:6: " TRUNC},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        hp_trace_reader *r = open_text(cases[i].text, HP_TRACE_CSV);
        hp_trace_row row;
        hp_diag d = {{0}};
        while (hp_trace_next(r, &row, &d) == HP_OK) {}
        assert_string_equal(d.text, cases[i].want);
        hp_trace_close(r);
    }
}

static void csv_bad_header(void **state)
{
    (void)state;
    const char *cases[][2] = {
        {"", "empty trace"},
        {"t,x,y,z\n", "t:1:1: header must be"},
        /* Anything that looks like a directive must be the directive, spelled exactly. */
        {"# rows: deviation\n" HDR, "t:1:3: directive must read exactly"},
        {"# Rows: deviation\n" HDR, "t:1:3: directive must read exactly"},
        {"#rows=deviation\n" HDR, "t:1:2: directive must read exactly"},
        {"# headplan-trace: rows=sideways\n" HDR, "t:1:24: directive must read exactly"},
        {"# HEADPLAN-trace: rows=deviation\n" HDR, "t:1:3: directive must read exactly"},
        {"# headplan-trace: rows=deviation \n" HDR, "t:1:24: directive must read exactly"},
        {"\n" DEV HDR, "t:2:1: a directive must be the first line"},
        {"# a comment\n# rows: deviation\n" HDR, "t:2:1: a directive must be the first line"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        hp_trace_reader *r = NULL;
        hp_diag d = {{0}};
        hp_error e = hp_trace_open_mem(cases[i][0], strlen(cases[i][0]), "t", HP_TRACE_CSV,
                                       &CORRECTION, &r, &d);
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
        "{\"headplan_trace\": 1, \"rows\": \"deviation\"}\n"
        "{\"t_s\":0,\"x_mm\":1,\"y_mm\":0,\"z_mm\":0,\"pitch_deg\":0,\"roll_deg\":0,\"yaw_deg\":0}"
        "\n"
        "{\"t_s\":0,\"x_mm\":1}\n"
        "{\"t_s\":0,\"x_mm\":1,\"y_mm\":0,\"z_mm\":0,\"pitch_deg\":0,\"roll_deg\":0,\"yaw_deg\":2,"
        "\"w\":1}\n"
        "{\"t_s\":0,\"x_mm\":\"1\",\"y_mm\":0,\"z_mm\":0,\"pitch_deg\":0,\"roll_deg\":0,"
        "\"yaw_deg\":2}\n"
        "[1,2]\n"
        "{\"t_s\":0,\"t_s\":1}\n"
        "{\"t_s\":1,\"x_mm\":0,\"y_mm\":0,\"z_mm\":0,\"pitch_deg\":0,\"roll_deg\":0,\"yaw_deg\":0}"
        "\n",
        HP_TRACE_JSONL);
    assert_int_equal(hp_trace_rows_of(r), HP_TRACE_DEVIATION);
    expect_row(r, 2, 0.0, (const double[6]){-1, 0, 0, 0, 0, 0});
    expect_bad(r, "t:3: missing key 'y_mm'");
    expect_bad(r, "t:4: unknown key 'w'");
    expect_bad(r, "t:5: x_mm: not a number");
    expect_bad(r, "t:6:1: expected a JSON object");
    expect_bad(r, "t:7:");
    expect_row(r, 8, 1.0, (const double[6]){0, 0, 0, 0, 0, 0});
    expect_end(r);
    hp_trace_close(r);
}

static void jsonl_first_line_is_data(void **state)
{
    (void)state;
    hp_trace_reader *r = open_rows("{\"t_s\":0,\"x_mm\":1,\"y_mm\":0,\"z_mm\":0,\"pitch_deg\":0,"
                                   "\"roll_deg\":0,\"yaw_deg\":0}\n",
                                   HP_TRACE_JSONL, &CORRECTION);
    assert_int_equal(hp_trace_rows_of(r), HP_TRACE_CORRECTION);
    expect_row(r, 1, 0.0, (const double[6]){1, 0, 0, 0, 0, 0});
    expect_end(r);
    hp_trace_close(r);
}

/* The kind is never guessed: stated by the file or the caller (agreeing if both), else an
 * error; a disagreement names both. */
static void rows_kind_rules(void **state)
{
    (void)state;
    const char *dev = DEV HDR "0,1,0,0,0,0,0\n";
    const char *none = HDR "0,1,0,0,0,0,0\n";
    expect_open_fails(dev, HP_TRACE_CSV, &CORRECTION, HP_ERR_INVALID,
                      "t: the trace states rows=deviation but the caller says correction");
    expect_open_fails(none, HP_TRACE_CSV, NULL, HP_ERR_INVALID,
                      "t: does not state what its rows are");
    expect_open_fails("{\"t_s\":0,\"x_mm\":1,\"y_mm\":0,\"z_mm\":0,\"pitch_deg\":0,"
                      "\"roll_deg\":0,\"yaw_deg\":0}\n",
                      HP_TRACE_JSONL, NULL, HP_ERR_INVALID, "does not state");
    /* The old JSON Lines form {"rows": ...} is refused, not taken for data or a header. */
    expect_open_fails("{\"rows\": \"deviation\"}\n", HP_TRACE_JSONL, NULL, HP_ERR_PARSE,
                      "t:1:1: header record must be exactly");
    expect_open_fails("{\"headplan_trace\": 2, \"rows\": \"deviation\"}\n", HP_TRACE_JSONL, NULL,
                      HP_ERR_PARSE, "header record must be exactly");
    hp_trace_reader *r = open_rows(dev, HP_TRACE_CSV, &DEVIATION); /* agreeing: fine */
    assert_int_equal(hp_trace_rows_of(r), HP_TRACE_DEVIATION);
    assert_int_equal(hp_trace_states_rows(r), 1);
    hp_trace_close(r);
    r = open_rows(none, HP_TRACE_CSV, &CORRECTION);
    assert_int_equal(hp_trace_states_rows(r), 0);
    expect_row(r, 2, 0.0, (const double[6]){1, 0, 0, 0, 0, 0});
    hp_trace_close(r);
    /* A directive after the header, or a header record after the first line: bad rows. */
    r = open_text(COR HDR "0,1,0,0,0,0,0\n# rows: deviation\n"
                          "# Headplan-trace: rows=deviation\n1,0,0,0,0,0,0\n",
                  HP_TRACE_CSV);
    expect_row(r, 3, 0.0, (const double[6]){1, 0, 0, 0, 0, 0});
    expect_bad(r, "t:4:1: a directive must be the first line");
    expect_bad(r, "t:5:1: a directive must be the first line");
    expect_row(r, 6, 1.0, (const double[6]){0, 0, 0, 0, 0, 0});
    expect_end(r);
    hp_trace_close(r);
    r = open_rows("{\"t_s\":0,\"x_mm\":1,\"y_mm\":0,\"z_mm\":0,\"pitch_deg\":0,"
                  "\"roll_deg\":0,\"yaw_deg\":0}\n{\"headplan_trace\":1,\"rows\":\"deviation\"}\n",
                  HP_TRACE_JSONL, &CORRECTION);
    expect_row(r, 1, 0.0, (const double[6]){1, 0, 0, 0, 0, 0});
    expect_bad(r, "t:2:1: a header record must be the first line");
    hp_trace_close(r);
}

/* Quaternion and 4x4 forms give the same correction as the angles they encode. */
static void pose_forms(void **state)
{
    (void)state;
    const double th = 10.0 * 3.14159265358979323846 / 180.0;
    char text[1024];
    snprintf(text, sizeof text,
             COR "t_s,x_mm,y_mm,z_mm,qw,qx,qy,qz\n0,1,2,3,%.17g,0,0,%.17g\n0,0,0,0,1,0,0,0.5\n",
             cos(th / 2), sin(th / 2));
    hp_trace_reader *r = open_text(text, HP_TRACE_CSV);
    assert_int_equal(hp_trace_form_of(r), HP_TRACE_QUATERNION);
    hp_trace_row row;
    assert_int_equal(hp_trace_next(r, &row, NULL), HP_OK);
    hp_assert_close(row.correction[0], 1e-3, 1e-15, 0);
    hp_assert_close(row.correction[HP_YAW], th, 1e-15, 0);
    hp_assert_close(row.correction[HP_PITCH], 0, 0, 1e-15);
    expect_bad(r, "t:4: quaternion: norm");
    hp_trace_close(r);
    /* A 4x4 of yaw 90° and a 2 mm lift; a reflection is a bad row. */
    r = open_text(DEV
                  "t_s,m00,m01,m02,m03_mm,m10,m11,m12,m13_mm,m20,m21,m22,m23_mm,m30,m31,m32,m33\n"
                  "0,0,-1,0,0,1,0,0,0,0,0,1,2,0,0,0,1\n"
                  "0,-1,0,0,0,0,1,0,0,0,0,1,0,0,0,0,1\n",
                  HP_TRACE_CSV);
    assert_int_equal(hp_trace_form_of(r), HP_TRACE_MATRIX);
    assert_int_equal(hp_trace_next(r, &row, NULL), HP_OK);
    /* Deviation: yaw +90° and z +2 mm; correction: yaw −90° and z −2 mm (R keeps z). */
    hp_assert_close(row.correction[HP_YAW], -3.14159265358979323846 / 2, 1e-15, 0);
    hp_assert_close(row.correction[HP_Z], -2e-3, 1e-15, 0);
    expect_bad(r, "t:4: matrix: a reflection");
    hp_trace_close(r);
    /* JSON Lines with quaternion keys; a row of another form is a bad row. */
    r = open_text(
        "{\"headplan_trace\":1,\"rows\":\"correction\"}\n"
        "{\"t_s\":0,\"x_mm\":0,\"y_mm\":0,\"z_mm\":0,\"qw\":1,\"qx\":0,\"qy\":0,\"qz\":0}\n"
        "{\"t_s\":0,\"x_mm\":1,\"y_mm\":0,\"z_mm\":0,\"pitch_deg\":0,\"roll_deg\":0,\"yaw_deg\":0}"
        "\n",
        HP_TRACE_JSONL);
    expect_row(r, 2, 0.0, (const double[6]){0, 0, 0, 0, 0, 0});
    assert_int_equal(hp_trace_form_of(r), HP_TRACE_QUATERNION);
    expect_bad(r, "t:3: unknown key");
    hp_trace_close(r);
}

/* NUL bytes and invalid UTF-8 name their line and column; a BOM is skipped. */
static void bytes_and_bom(void **state)
{
    (void)state;
    const char text[] = "\xEF\xBB\xBF" COR HDR "0,1\0,0,0,0,0,0\n0,\xff,0,0,0,0,0\n"
                        "0,0,0,0,0,0,0\n";
    hp_trace_reader *r = NULL;
    hp_diag d = {{0}};
    assert_int_equal(hp_trace_open_mem(text, sizeof text - 1, "t", HP_TRACE_CSV, NULL, &r, &d),
                     HP_OK);
    expect_bad(r, "t:3:4: NUL byte");
    expect_bad(r, "t:4:3: invalid UTF-8");
    expect_row(r, 5, 0.0, (const double[6]){0, 0, 0, 0, 0, 0});
    expect_end(r);
    hp_trace_close(r);
}

/* A pipe (no seeking): the JSON Lines header record is not lost and the kind comes from it;
 * the format is found from the first line, since "<pipe>" has no extension. */
static void pipe_reads_sequentially(void **state)
{
    (void)state;
    const char *text = "{\"headplan_trace\":1,\"rows\":\"deviation\"}\n"
                       "{\"t_s\":0,\"x_mm\":1,\"y_mm\":0,\"z_mm\":0,\"pitch_deg\":0,"
                       "\"roll_deg\":0,\"yaw_deg\":0}\n";
    int fd[2];
    assert_int_equal(pipe(fd), 0);
    assert_int_equal(write(fd[1], text, strlen(text)), (long)strlen(text));
    close(fd[1]);
    FILE *f = fdopen(fd[0], "rb");
    assert_non_null(f);
    hp_trace_reader *r = NULL;
    hp_diag d = {{0}};
    hp_error e = hp_trace_open_stream(f, "<pipe>", NULL, "--rows", &r, &d);
    if (e) print_error("%s\n", d.text);
    assert_int_equal(e, HP_OK);
    assert_int_equal(hp_trace_rows_of(r), HP_TRACE_DEVIATION);
    expect_row(r, 2, 0.0, (const double[6]){-1, 0, 0, 0, 0, 0});
    expect_end(r);
    hp_trace_close(r);
    fclose(f);
}

/* A line past the limit stops the reader at once, even a stream without any newline. */
static void long_line_stops(void **state)
{
    (void)state;
    FILE *f = fopen("/dev/zero", "rb");
    assert_non_null(f);
    hp_trace_reader *r = NULL;
    hp_diag d = {{0}};
    assert_int_equal(hp_trace_open_stream(f, "zero.csv", &CORRECTION, NULL, &r, &d), HP_ERR_STATE);
    assert_non_null(strstr(d.text, "zero.csv:1: line longer than 4096 bytes"));
    fclose(f);
    static char big[HP_TRACE_LINE_MAX + 200];
    strcpy(big, COR HDR "0,0,0,0,0,0,0\n");
    size_t n = strlen(big);
    memset(big + n, '1', HP_TRACE_LINE_MAX + 1);
    r = open_text(big, HP_TRACE_CSV);
    expect_row(r, 3, 0.0, (const double[6]){0, 0, 0, 0, 0, 0});
    hp_trace_row row;
    assert_int_equal(hp_trace_next(r, &row, &d), HP_ERR_STATE);
    assert_non_null(strstr(d.text, "t:4: line longer than"));
    assert_int_equal(hp_trace_next(r, &row, &d), HP_ERR_STATE);
    hp_trace_close(r);
}

static void override_and_names(void **state)
{
    (void)state;
    hp_trace_reader *r = NULL;
    hp_trace_close(NULL);

    hp_trace_rows rows;
    hp_trace_format fmt;
    assert_int_equal(hp_trace_rows_parse("deviation", &rows), HP_OK);
    assert_string_equal(hp_trace_rows_name(rows), "deviation");
    assert_int_equal(hp_trace_rows_parse("Deviation", &rows), HP_ERR_INVALID);
    assert_int_equal(hp_trace_format_parse("jsonl", &fmt), HP_OK);
    assert_string_equal(hp_trace_format_name(fmt), "jsonl");
    assert_int_equal(hp_trace_format_parse("tsv", &fmt), HP_ERR_INVALID);
    assert_string_equal(hp_trace_form_name(HP_TRACE_QUATERNION), "quaternion");
    assert_string_equal(hp_trace_form_name(HP_TRACE_MATRIX), "matrix");
    assert_string_equal(hp_error_name(HP_END), "end");
    hp_diag d = {{0}};
    assert_int_equal(hp_trace_open("/nonexistent/x.csv", NULL, &r, &d), HP_ERR_IO);
    assert_non_null(strstr(d.text, "/nonexistent/x.csv: cannot open"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(csv_corrections),
        cmocka_unit_test(csv_deviation_inverted),
        cmocka_unit_test(csv_bad_rows_continue),
        cmocka_unit_test(truncated_line_column),
        cmocka_unit_test(csv_bad_header),
        cmocka_unit_test(jsonl_rows),
        cmocka_unit_test(jsonl_first_line_is_data),
        cmocka_unit_test(rows_kind_rules),
        cmocka_unit_test(pose_forms),
        cmocka_unit_test(bytes_and_bom),
        cmocka_unit_test(pipe_reads_sequentially),
        cmocka_unit_test(long_line_stops),
        cmocka_unit_test(override_and_names),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
