/* The column table (hp_trace_columns.h) against what it promises, checked here with the
 * result's own fields and the documented units (no call of the table reproduces itself):
 * names expand to the documented patterns and are unique for a real layout, every value
 * equals the field it names in its unit, a refused row gives NaN / 0 / status -1, and the
 * name builder refuses what does not fit. */
#include "support/test_util.h"
#include "tests/horizon/horizon_fixture.h"

#include <math.h>

#define DEG (180.0 / 3.14159265358979323846) /* degrees per radian */

/* One planned row of the default scene with a correction that leaves some error. */
static void planned(hf_case **c, hp_result *r)
{
    *c = hf_load("default.yaml", "drift_10hz.csv", 3);
    assert_non_null(*c);
    hp_planner *p = NULL;
    assert_int_equal(hp_planner_create(&(*c)->sc.layout, &(*c)->s, &p, NULL), HP_OK);
    assert_int_equal(hp_plan(p, (*c)->rows[2].correction, r), HP_OK);
    hp_planner_destroy(p);
}

static void test_names(void **state)
{
    (void)state;
    hf_case *c = hf_load("default.yaml", "drift_10hz.csv", 1);
    assert_non_null(c);
    const hp_layout *L = &c->sc.layout;
    size_t nt;
    const hp_column *t = hp_columns(&nt);
    assert_true(nt > 0 && nt <= HP_COLUMNS_MAX);
    char buf[HP_COLUMN_NAME_MAX];
    /* Spelled out here: the patterns are the documented file format. */
    assert_int_equal(hp_column_name(hp_column_find("desired_{axis}_{unit}"), 3, L, buf, sizeof buf),
                     HP_OK);
    assert_string_equal(buf, "desired_pitch_deg");
    assert_int_equal(hp_column_name(hp_column_find("commanded_{axis}"), 2, L, buf, sizeof buf),
                     HP_OK);
    assert_string_equal(buf, "commanded_z");
    assert_int_equal(hp_column_name(hp_column_find("{bladder}_pressure_pa"), 1, L, buf, sizeof buf),
                     HP_OK);
    char want[HP_COLUMN_NAME_MAX];
    snprintf(want, sizeof want, "%s_pressure_pa", L->bladders[1].name);
    assert_string_equal(buf, want);
    /* Every expanded name is unique (a flags column is one cell: its name alone). */
    static char names[HP_COLUMNS_MAX * HP_COLUMN_WIDTH_MAX][HP_COLUMN_NAME_MAX];
    int n = 0;
    for (size_t j = 0; j < nt; ++j) {
        int w = t[j].format == HP_COLUMN_FLAGS ? 1 : hp_column_width(&t[j], L->n);
        assert_true(w >= 1 && w <= HP_COLUMN_WIDTH_MAX);
        for (int k = 0; k < w; ++k, ++n) {
            assert_int_equal(hp_column_name(&t[j], k, L, names[n], sizeof names[n]), HP_OK);
            for (int i = 0; i < n; ++i) assert_string_not_equal(names[i], names[n]);
        }
        assert_ptr_equal(hp_column_find(t[j].name), &t[j]);
        /* A NumPy column names its dtype; a measured one is in the rows (--no-times). */
        assert_true(!t[j].numpy == !t[j].numpy_dtype);
        assert_true(!t[j].measured || t[j].in_rows);
    }
    /* Refusals: an axis or bladder out of range; a name that does not fit (truncated). */
    const hp_column *p = hp_column_find("{bladder}_pressure_pa");
    assert_int_equal(hp_column_name(p, L->n, L, buf, sizeof buf), HP_ERR_INVALID);
    assert_int_equal(hp_column_name(hp_column_find("error_{axis}_{unit}"), 6, L, buf, sizeof buf),
                     HP_ERR_INVALID);
    assert_int_equal(hp_column_name(p, 0, NULL, buf, sizeof buf), HP_ERR_NULL);
    assert_int_equal(hp_column_name(p, 0, L, buf, 5), HP_ERR_INVALID);
    assert_int_equal(strlen(buf), 4);
    assert_null(hp_column_find("no_such_column"));
    /* Every name fits HP_COLUMN_NAME_MAX for the longest bladder name a layout may hold. */
    hp_layout *big = &c->sc.layout;
    memset(big->bladders[0].name, 'b', HP_NAME_MAX - 1);
    big->bladders[0].name[HP_NAME_MAX - 1] = '\0';
    for (size_t j = 0; j < nt; ++j)
        for (int k = 0; k < (t[j].shape == HP_COLUMN_ONE ? 1 : 6); ++k)
            assert_int_equal(hp_column_name(&t[j], t[j].shape == HP_COLUMN_BLADDERS ? 0 : k, big,
                                            buf, sizeof buf),
                             HP_OK);
    free(c);
}

static double one(const char *name, int k, const hp_trace_row *row, const hp_result *r)
{
    double v[HP_COLUMN_WIDTH_MAX];
    const hp_column *c = hp_column_find(name);
    assert_non_null(c);
    assert_true(k < hp_column_values(c, r ? r->n : 8, row, r, v));
    return v[k];
}

static void test_values(void **state)
{
    (void)state;
    hf_case *c;
    hp_result r;
    planned(&c, &r);
    const hp_trace_row *row = &c->rows[2];
    /* Exact: each is the field times its unit's factor (1e3 mm per m, 180/pi deg per rad). */
    assert_true(one("line", 0, row, &r) == (double)row->line);
    assert_true(one("t_s", 0, row, &r) == row->t);
    for (int i = 0; i < 6; ++i) {
        double f = i < 3 ? 1e3 : DEG;
        hp_assert_close(one("desired_{axis}_{unit}", i, row, &r), r.desired[i] * f, 1e-15, 0);
        hp_assert_close(one("achieved_{axis}_{unit}", i, row, &r), r.achieved[i] * f, 1e-15, 0);
        /* The difference of two rounded products: within a few ulps of the products. */
        double e = (r.achieved[i] - r.desired[i]) * f;
        hp_assert_close(one("error_{axis}_{unit}", i, row, &r), e, 0,
                        1e-14 * (fabs(r.achieved[i] * f) + 1));
        assert_true(one("commanded_{axis}", i, row, &r) == (r.commanded[i] ? 1.0 : 0.0));
    }
    for (int k = 0; k < r.n; ++k) {
        assert_true(one("{bladder}_pressure_pa", k, row, &r) == r.bladders[k].pressure);
        assert_true(one("{bladder}_ri_mm", k, row, &r) == r.bladders[k].ri * 1e3);
        assert_true(one("{bladder}_ro_mm", k, row, &r) == r.bladders[k].ro * 1e3);
        assert_true(one("{bladder}_stretch", k, row, &r) == r.bladders[k].stretch);
        assert_true(one("binding", k, row, &r) == (double)r.bladders[k].binding);
    }
    assert_true(one("pose_error", 0, row, &r) == r.pose_error);
    assert_true(one("iterations", 0, row, &r) == (double)r.iterations);
    assert_true(one("status_code", 0, row, &r) == (double)r.status);
    assert_string_equal(hp_column_text(hp_column_find("status"), one("status", 0, row, &r)),
                        hp_status_name(r.status));
    /* Whole nanoseconds, in us. */
    r.solve_time = 12.3456789e-6;
    assert_true(one("solve_time_us", 0, row, &r) == 12.346);
    /* The worst commanded error per unit, from the result's own poses. */
    double mm = 0, deg = 0;
    for (int i = 0; i < 6; ++i) {
        if (!r.commanded[i]) continue;
        double e = fabs((r.achieved[i] - r.desired[i]) * (i < 3 ? 1e3 : DEG));
        if (i < 3) mm = fmax(mm, e);
        else deg = fmax(deg, e);
    }
    hp_assert_close(one("pose_error_mm", 0, row, &r), mm, 0, 1e-14 * (mm + 1));
    hp_assert_close(one("pose_error_deg", 0, row, &r), deg, 0, 1e-14 * (deg + 1));
    /* A refused row: NaN numbers, 0 integers and flags, status -1 ("bad-row"), its line. */
    assert_true(isnan(one("{bladder}_pressure_pa", 3, row, NULL)));
    assert_true(isnan(one("achieved_{axis}_{unit}", 0, row, NULL)));
    assert_true(one("binding", 0, row, NULL) == 0.0);
    assert_true(one("iterations", 0, row, NULL) == 0.0);
    assert_true(one("status_code", 0, row, NULL) == -1.0);
    assert_string_equal(hp_column_text(hp_column_find("status"), -1.0), "bad-row");
    assert_true(one("line", 0, row, NULL) == (double)row->line);
    assert_true(isnan(one("error", 0, row, &r)));
    assert_null(hp_column_text(hp_column_find("iterations"), 0));
    free(c);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_names),
        cmocka_unit_test(test_values),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
