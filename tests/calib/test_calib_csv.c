/* The calibration data readers: every malformed file is refused with FILE:LINE:COL naming
 * the field (NaN, negative radius, pressure past the limit point or outside the limits,
 * wrong column count, unknown or missing header columns, too few rows), and good files read
 * in SI units. */
#define _POSIX_C_SOURCE 200809L
#include "support/test_util.h"
#include "headplan/headplan.h"

#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static char dir[] = "/tmp/hp_csv_XXXXXX";

static const char *write_file(const char *name, const char *text)
{
    static char path[256];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fputs(text, f);
    fclose(f);
    return path;
}

static void material_case(const char *text, const char *want)
{
    const char *p = write_file("m.csv", text);
    static hp_calib_point pts[16];
    int n = -1;
    hp_calib_radius kind;
    hp_diag d = {{0}};
    hp_error e = hp_calib_read_material(p, pts, 16, &n, &kind, &d);
    char full[300];
    snprintf(full, sizeof full, "%s/m.csv:%s", dir, want);
    if (e == HP_OK || strncmp(d.text, full, strlen(full)) != 0) {
        print_error("file:\n%s\nwant '%s', got %d '%s'\n", text, full, e, d.text);
        fail();
    }
    assert_int_equal(n, 0);
}

static void test_material_good(void **state)
{
    (void)state;
    const char *p = write_file("good.csv", "# comment\n\npressure_kpa, ro_mm ,sigma_mm\r\n"
                                           "-1.5,29.5,0.02\n0,30,0.02\n2,31.25,0.01\n");
    hp_calib_point pts[4];
    int n;
    hp_calib_radius kind;
    assert_int_equal(hp_calib_read_material(p, pts, 4, &n, &kind, NULL), HP_OK);
    assert_int_equal(n, 3);
    assert_int_equal(kind, HP_CALIB_OUTER);
    hp_assert_close(pts[0].pressure, -1500, 0, 0);
    hp_assert_close(pts[2].radius, 0.03125, 1e-15, 0);
    hp_assert_close(pts[2].sigma, 1e-5, 1e-15, 0);
    assert_int_equal(pts[0].line, 4);
}

static void test_material_bad(void **state)
{
    (void)state;
    material_case("", "1:1: empty file");
    material_case("pressure,ri_mm\n", "1:1: header: first column");
    material_case("pressure_pa,r_mm\n", "1:13: header: second column must be ri_mm or ro_mm");
    material_case("pressure_pa,ri_mm,sd\n", "1:19: header: third column must be sigma_mm");
    material_case("pressure_pa,ri_mm\n1000,27.5\n2000,nan\n", "3:6: ri_mm: 'nan': not a number");
    material_case("pressure_pa,ri_mm\n1000,27.5\n2000,-3\n", "3:6: ri_mm: must be > 0 mm");
    material_case("pressure_pa,ri_mm\n1000,27.5\n2000,28,1\n", "3:1: 3 columns, the header has 2");
    material_case("pressure_pa,ri_mm\n1000,27.5\n", "3:1: 1 data rows");
    material_case("pressure_pa,ri_mm,sigma_mm\n1e999,27.5,1\n",
                  "2:1: pressure: '1e999': overflows");
    material_case("pressure_pa,ri_mm,sigma_mm\n1,27.5,0\n", "2:8: sigma_mm: must be > 0 (got 0)");
    material_case("pressure_pa,ri_mm\n 0x10 ,27.5\n", "2:2: pressure: '0x10': not a number");
    /* A file cut short: "36" cut to "3" would be another data point; a last line without
     * its end of line is refused, as the trace reader does, whatever it holds. */
    material_case("pressure_pa,ri_mm\n1000,27.5\n2000,28\n3000,3",
                  "4:7: truncated: the last line has no end of line");
    material_case("pressure_pa,ri_mm\n1000,27.5\n2000,28\n3000,30\n# end",
                  "5:6: truncated: the last line has no end of line");
    material_case("pressure_pa,ri_mm\r\n1000,27.5\r\n2000,28\r\n3000,30\r",
                  "4:9: truncated: the last line has no end of line");
    hp_calib_point pts[2];
    int n;
    hp_calib_radius kind;
    hp_diag d = {{0}};
    assert_int_equal(hp_calib_read_material("/nonexistent/x.csv", pts, 2, &n, &kind, &d),
                     HP_ERR_IO);
    assert_non_null(strstr(d.text, "/nonexistent/x.csv: cannot open"));
}

static char header[1024];

/* Reading text (written to NAME) as layout rows must fail with a message that starts with
 * "DIR/NAME:" + want and contains has. */
static void expect_layout_refusal(const hp_layout *L, const char *name, const char *text,
                                  const char *want, const char *has)
{
    const char *p = write_file(name, text);
    static hp_calib_row out[8];
    int n = -1;
    hp_diag d = {{0}};
    hp_error e = hp_calib_read_layout(p, L, out, 8, &n, &d);
    char full[300];
    snprintf(full, sizeof full, "%s/%s:%s", dir, name, want);
    if (e == HP_OK || strncmp(d.text, full, strlen(full)) != 0 || !strstr(d.text, has)) {
        print_error("want '%s' (with '%s'), got %d '%s'\n", full, has, e, d.text);
        fail();
    }
    assert_int_equal(n, 0);
}

static void layout_case(const hp_layout *L, const char *rows, const char *want)
{
    char text[4096];
    snprintf(text, sizeof text, "%s\n%s", header, rows);
    expect_layout_refusal(L, "l.csv", text, want, "");
}

static void test_layout(void **state)
{
    (void)state;
    hp_scene *sc = calloc(1, sizeof *sc);
    assert_int_equal(hp_scene_load(HP_SOURCE_DIR "/scenarios/default.yaml", sc, NULL), HP_OK);
    const hp_layout *L = &sc->layout;
    /* Columns in another order than the scene's, one in kPa. */
    snprintf(header, sizeof header, "yaw_deg,x_mm,y_mm,z_mm,pitch_deg,roll_deg");
    for (int k = L->n - 1; k >= 0; --k)
        snprintf(header + strlen(header), sizeof header - strlen(header), ",p_%s_%s",
                 L->bladders[k].name, k == 0 ? "kpa" : "pa");
    const char *good = "1,0.5,0,0,0,0,0,0,0,0,0,0,0,1.5\n0,0,0,0,0,0,0,0,0,0,0,0,0,0\n";
    char text[4096];
    snprintf(text, sizeof text, "%s\n%s", header, good);
    const char *p = write_file("good.csv", text);
    static hp_calib_row rows[4];
    int n;
    hp_diag d = {{0}};
    assert_int_equal(hp_calib_read_layout(p, L, rows, 4, &n, &d), HP_OK);
    assert_int_equal(n, 2);
    hp_assert_close(rows[0].pressure[0], 1500, 0, 0); /* kPa column */
    hp_assert_close(rows[0].pose[HP_YAW], 1 * 3.14159265358979323846 / 180, 1e-15, 0);
    hp_assert_close(rows[0].pose[HP_X], 0.5e-3, 1e-15, 0);
    layout_case(L, "0,0,0,0,0,0,0,0,0,0,0,0,0,nan\n0,0,0,0,0,0,0,0,0,0,0,0,0,0\n", "2:");
    layout_case(L, "0,0,0,0,0,0,0,0,0,0,0,0,0\n", "2:1: 13 columns, the header has 14");
    layout_case(L, "0,0,0,0,0,0,0,0,0,0,0,0,0,20\n0,0,0,0,0,0,0,0,0,0,0,0,0,0\n", "2:");
    layout_case(L, "0,0,0,0,0,0,0,0,0,0,0,0,0,0\n", "3:1: 1 data rows");
    layout_case(L, "0,0,0,0,0,0,0,0,0,0,0,0,0,0\n0,0,0,0,0,0,0,0,0,0,0,0,0,3",
                "3:28: truncated: the last line has no end of line");
    /* Header faults. */
    char save[1024];
    memcpy(save, header, sizeof save);
    strcat(header, ",extra_mm");
    layout_case(L, "", "1:");
    snprintf(header, sizeof header, "x_mm,y_mm,z_mm,pitch_deg,roll_deg,yaw_deg");
    layout_case(L, "", "1:1: header: missing column p_base_neck_left_pa");
    memcpy(header, save, sizeof save);
    strcat(header, ",x_mm");
    layout_case(L, "", "1:");
    memcpy(header, save, sizeof save);
    free(sc);
}

/* The refusals above name their column: check two messages in full. */
static void test_layout_messages(void **state)
{
    (void)state;
    hp_scene *sc = calloc(1, sizeof *sc);
    assert_int_equal(hp_scene_load(HP_SOURCE_DIR "/scenarios/default.yaml", sc, NULL), HP_OK);
    const hp_layout *L = &sc->layout;
    snprintf(header, sizeof header, "x_mm,y_mm,z_mm,pitch_deg,roll_deg,yaw_deg");
    for (int k = 0; k < L->n; ++k)
        snprintf(header + strlen(header), sizeof header - strlen(header), ",p_%s_pa",
                 L->bladders[k].name);
    layout_case(L, "0,0,0,0,nan,0,0,0,0,0,0,0,0,0\n", "2:9: roll_deg: 'nan': not a number");
    layout_case(L, "0,0,0,0,0,0,0,0,0,0,0,20000,0,0\n",
                "2:23: p_side_fore_right: 20000 Pa outside the bladder's limits");
    layout_case(L, "0,0,0,0,0,0,-6000,0,0,0,0,0,0,0\n",
                "2:13: p_base_neck_left: -6000 Pa outside the bladder's limits");
    size_t col = strlen(header) + 2; /* 1-based column of the repeated name */
    snprintf(header + strlen(header), sizeof header - strlen(header), ",x_mm");
    char want[64];
    snprintf(want, sizeof want, "1:%zu: header: 'x_mm' appears twice", col);
    layout_case(L, "", want);
    free(sc);
}

static void jsonl_case(const hp_layout *L, const char *text, const char *want, const char *has)
{
    expect_layout_refusal(L, "l.jsonl", text, want, has);
}

/* JSON Lines: the example rows read exactly as their CSV twin; malformed lines refused. */
static void test_layout_jsonl(void **state)
{
    (void)state;
    hp_scene *sc = calloc(1, sizeof *sc);
    assert_int_equal(hp_scene_load(HP_SOURCE_DIR "/scenarios/default.yaml", sc, NULL), HP_OK);
    const hp_layout *L = &sc->layout;
    static hp_calib_row a[32], b[32];
    int na, nb;
    hp_diag d = {{0}};
    assert_int_equal(hp_calib_read_layout(HP_SOURCE_DIR "/examples/calibration/layout_rows.csv", L,
                                          a, 32, &na, &d),
                     HP_OK);
    assert_int_equal(hp_calib_read_layout(HP_SOURCE_DIR "/examples/calibration/layout_rows.jsonl",
                                          L, b, 32, &nb, &d),
                     HP_OK);
    assert_int_equal(na, 24);
    assert_int_equal(nb, 24);
    for (int i = 0; i < na; ++i) {
        for (int k = 0; k < 8; ++k) assert_true(a[i].pressure[k] == b[i].pressure[k]);
        for (int j = 0; j < 6; ++j) assert_true(a[i].pose[j] == b[i].pose[j]);
    }
    const char *keys = "\"p_base_neck_left_pa\": 0, \"p_base_neck_right_pa\": 0, "
                       "\"p_base_skull_left_pa\": 0, \"p_base_skull_right_pa\": 0, "
                       "\"p_side_fore_left_pa\": 0, \"p_side_fore_right_pa\": 0, "
                       "\"p_side_chin_left_pa\": 0, \"p_side_chin_right_pa\": 0, "
                       "\"x_mm\": 0, \"y_mm\": 0, \"z_mm\": 0, \"pitch_deg\": 0, "
                       "\"roll_deg\": 0";
    char t[2048];
    snprintf(t, sizeof t, "{%s, \"yaw_deg\": 0}\n{%s, \"yaw_deg\": 1}\n", keys, keys);
    const char *p = write_file("ok.jsonl", t);
    assert_int_equal(hp_calib_read_layout(p, L, a, 32, &na, &d), HP_OK);
    assert_int_equal(na, 2);
    snprintf(t, sizeof t, "{%s, \"yaw_deg\": \"1\"}\n", keys);
    jsonl_case(L, t, "1:", "yaw_deg: expected a number");
    snprintf(t, sizeof t, "{%s}\n", keys);
    jsonl_case(L, t, "1:1: missing key yaw_deg", "");
    snprintf(t, sizeof t, "{%s, \"yaw_deg\": 0, \"t_s\": 1}\n", keys);
    jsonl_case(L, t, "1:", "unknown key 't_s'");
    snprintf(t, sizeof t, "{%s, \"yaw_deg\": 0, \"yaw_deg\": 1}\n", keys);
    jsonl_case(L, t, "1:", "duplicate");
    jsonl_case(L, "{\"x_mm\": NaN}\n", "1:", "");
    /* Underflow is refused as in CSV (jansson read 1e-400 as 0 and kept subnormals): the
     * column is the number's, 1-based. */
    snprintf(t, sizeof t, "{%s, \"yaw_deg\": 1e-400}\n", keys);
    char want[128];
    snprintf(want, sizeof want, "1:%zu: yaw_deg: too small for a double",
             strlen(t) - strlen("1e-400}\n") + 1);
    jsonl_case(L, t, want, "");
    snprintf(t, sizeof t, "{%s, \"yaw_deg\": -1e-310}\n", keys);
    snprintf(want, sizeof want, "1:%zu: yaw_deg: too small for a double",
             strlen(t) - strlen("-1e-310}\n") + 1);
    jsonl_case(L, t, want, "");
    jsonl_case(L, "[1, 2]\n", "1:1: expected one object per line", "");
    snprintf(t, sizeof t, "{%s, \"yaw_deg\": 0}\n{%s, \"yaw_deg\": 1}", keys, keys);
    snprintf(want, sizeof want, "2:%zu: truncated: the last line has no end of line",
             strlen(strchr(t, '\n') + 1) + 1);
    jsonl_case(L, t, want, "");
    free(sc);
}

/* Copies the file at src to name in the test folder, prefixed by a UTF-8 byte-order mark. */
static const char *with_bom(const char *name, const char *src)
{
    static char text[64 * 1024];
    FILE *f = fopen(src, "rb");
    assert_non_null(f);
    memcpy(text, "\xEF\xBB\xBF", 3);
    size_t n = fread(text + 3, 1, sizeof text - 4, f);
    fclose(f);
    text[3 + n] = '\0';
    return write_file(name, text);
}

/* A byte-order mark (what a spreadsheet may write first) is skipped, as the scene and trace
 * readers skip it: the same points as without it. It was read as part of the first header
 * name ("header: expected pressure_pa,ri_mm ... (1 columns)", "unknown column"). */
static void test_byte_order_mark(void **state)
{
    (void)state;
    hp_scene *sc = calloc(1, sizeof *sc);
    assert_int_equal(hp_scene_load(HP_SOURCE_DIR "/scenarios/default.yaml", sc, NULL), HP_OK);
    static hp_calib_row a[32], b[32];
    static hp_calib_point pa[32], pb[32];
    int na, nb;
    hp_calib_radius ka, kb;
    hp_diag d = {{0}};
    static const char *const layout[2] = {"layout_rows.csv", "layout_rows.jsonl"};
    for (int f = 0; f < 2; ++f) {
        char src[512];
        snprintf(src, sizeof src, "%s/examples/calibration/%s", HP_SOURCE_DIR, layout[f]);
        assert_int_equal(hp_calib_read_layout(src, &sc->layout, a, 32, &na, &d), HP_OK);
        const char *p = with_bom(layout[f], src);
        if (hp_calib_read_layout(p, &sc->layout, b, 32, &nb, &d) != HP_OK) {
            print_error("%s with a BOM: %s\n", layout[f], d.text);
            fail();
        }
        assert_int_equal(na, nb);
        assert_memory_equal(a, b, sizeof a[0] * (size_t)na);
    }
    const char *src = HP_SOURCE_DIR "/examples/calibration/material_ri.csv";
    assert_int_equal(hp_calib_read_material(src, pa, 32, &na, &ka, &d), HP_OK);
    const char *p = with_bom("material.csv", src);
    if (hp_calib_read_material(p, pb, 32, &nb, &kb, &d) != HP_OK) {
        print_error("material with a BOM: %s\n", d.text);
        fail();
    }
    assert_int_equal(na, nb);
    assert_int_equal(ka, kb);
    assert_memory_equal(pa, pb, sizeof pa[0] * (size_t)na);
    /* Columns count from after the mark, as in a trace. */
    material_case("\xEF\xBB\xBFpressure_pa,rx_mm\n", "1:13: header: second column");
    free(sc);
}

static int setup(void **state)
{
    (void)state;
    return mkdtemp(dir) ? 0 : -1;
}

static int teardown(void **state)
{
    (void)state;
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    return system(cmd) == 0 ? 0 : -1;
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_material_good), cmocka_unit_test(test_material_bad),
        cmocka_unit_test(test_layout),        cmocka_unit_test(test_layout_messages),
        cmocka_unit_test(test_layout_jsonl),  cmocka_unit_test(test_byte_order_mark),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
