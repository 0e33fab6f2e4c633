/* API misuse: NULL everywhere, invalid layouts and settings (every field, NaN included),
 * double destroys, bad previous pressures. Every case must return its error code and leave a
 * message naming the field (in the hp_diag, or on the planner for calls that take none), and
 * never crash; a rejected call changes nothing. docs/safety.md has the table. */
#include "rel_common.h"

/* Fails unless text contains want (case-sensitive). */
static void assert_names(const char *text, const char *want, const char *what)
{
    if (!text || !strstr(text, want)) {
        print_error("%s: message '%s' does not name '%s'\n", what, text ? text : "(null)", want);
        fail();
    }
}

static void null_arguments(void **st)
{
    (void)st;
    hp_layout L;
    assert_int_equal(lf_layout(&L), HP_OK);
    hp_diag d = {{0}};
    hp_planner *p = (hp_planner *)&d; /* must be overwritten with NULL */
    assert_int_equal(hp_planner_create(NULL, NULL, &p, &d), HP_ERR_NULL);
    assert_null(p);
    assert_names(d.text, "layout", "create(NULL layout)");
    assert_int_equal(hp_planner_create(&L, NULL, NULL, &d), HP_ERR_NULL);
    assert_names(d.text, "out", "create(NULL out)");
    assert_int_equal(hp_planner_create(&L, NULL, NULL, NULL), HP_ERR_NULL); /* NULL diag */

    const double z[6] = {0};
    hp_result r;
    assert_int_equal(hp_plan(NULL, z, &r), HP_ERR_NULL);
    assert_int_equal(hp_plan(NULL, NULL, NULL), HP_ERR_NULL);
    assert_names(hp_planner_error(NULL), "NULL", "error(NULL)");
    assert_int_equal(hp_planner_level(NULL), HP_LEVEL_AUTO);
    assert_null(hp_planner_layout(NULL));
    hp_planner_reset(NULL);
    hp_planner_destroy(NULL);
    assert_int_equal(hp_planner_set_previous(NULL, z), HP_ERR_NULL);
    assert_int_equal(hp_settings_validate(NULL, &d), HP_ERR_NULL);
    assert_names(d.text, "settings", "validate(NULL)");
    hp_settings_default(NULL);
    hp_backend b = HP_BACKEND_IPOPT;
    /* The header promises HP_ERR_INVALID for NULL; names.c returns HP_ERR_NULL (reported):
     * either way a refusal that leaves out untouched. */
    assert_int_not_equal(hp_backend_parse(NULL, &b), HP_OK);
    assert_int_equal(hp_backend_parse("bogus", &b), HP_ERR_INVALID);
    assert_int_equal(b, HP_BACKEND_IPOPT);
    assert_string_equal(hp_backend_name((hp_backend)99), "unknown");
    assert_string_equal(hp_status_name((hp_status)-1), "unknown");
    assert_string_equal(hp_binding_name(0), "unknown");
    assert_string_equal(hp_binding_name(3), "unknown");

    /* On a real planner: NULL desired gives the safe output labelled invalid-input; NULL
     * result and NULL pressures are refused with a message. */
    assert_int_equal(hp_planner_create(&L, NULL, &p, &d), HP_OK);
    rel_ctx c;
    rel_ctx_init(&c, p);
    rel_ctx_capture_safe(&c, p);
    assert_int_equal(hp_plan(p, NULL, &r), HP_ERR_NULL);
    assert_int_equal(r.status, HP_STATUS_INVALID_INPUT);
    assert_names(hp_planner_error(p), "desired", "plan(NULL desired)");
    REL_ASSERT(&c, HP_OK, NULL, &r, REL_INV_ALL & ~0u, "NULL desired");
    assert_int_equal(hp_plan(p, z, NULL), HP_ERR_NULL);
    assert_names(hp_planner_error(p), "result", "plan(NULL result)");
    assert_int_equal(hp_planner_set_previous(p, NULL), HP_ERR_NULL);
    assert_names(hp_planner_error(p), "pressures", "set_previous(NULL)");
    hp_planner_destroy(p);
}

/* ---- invalid layouts ---- */

typedef void (*layout_mut)(hp_layout *L);
static void m_n0(hp_layout *L) { L->n = 0; }
static void m_nneg(hp_layout *L) { L->n = -3; }
static void m_nbig(hp_layout *L) { L->n = HP_MAX_BLADDERS + 1; }
static void m_dup(hp_layout *L) { memcpy(L->bladders[3].name, L->bladders[1].name, HP_NAME_MAX); }
static void m_noname(hp_layout *L) { L->bladders[2].name[0] = '\0'; }
static void m_nan_center(hp_layout *L) { L->bladders[4].center[1] = NAN; }
static void m_inf_center(hp_layout *L) { L->bladders[5].center[0] = INFINITY; }
/* The fixture layout was validated; an edit after that must be seen by the next call. */
static void m_edited_after_check(hp_layout *L) { L->bladders[4].center[2] = NAN; }
static void m_center_inside(hp_layout *L)
{
    for (int i = 0; i < 3; ++i) L->bladders[0].center[i] = 0;
}
static void m_nan_pmin(hp_layout *L) { L->bladders[6].p_min = NAN; }
static void m_inverted_p(hp_layout *L) { L->bladders[6].p_min = 2e4; }
static void m_ri_ge_ro(hp_layout *L) { L->bladders[7].iab.Ri = 0.031; }
static void m_nan_c1(hp_layout *L) { L->bladders[7].iab.C1 = NAN; }
static void m_nan_smax(hp_layout *L) { L->bladders[1].stretch_max = NAN; }
static void m_rate0(hp_layout *L) { L->bladders[1].rate_max = 0; }
static void m_rate_nan(hp_layout *L) { L->bladders[1].rate_max = NAN; }
static void m_nan_axis(hp_layout *L) { L->head.semi_axes[1] = NAN; }
static void m_nan_pivot(hp_layout *L) { L->pivot[2] = NAN; }

static const struct {
    const char *what;
    layout_mut mut;
    const char *names; /* the message must contain this */
} layout_cases[] = {
    {"n = 0", m_n0, "n"},
    {"n < 0", m_nneg, "n"},
    {"n > HP_MAX_BLADDERS", m_nbig, "n"},
    {"duplicate names", m_dup, "base_neck_right"},
    {"empty name", m_noname, "name"},
    {"NaN centre", m_nan_center, "side_fore_left"},
    {"infinite centre", m_inf_center, "side_fore_right"},
    {"edited after validation", m_edited_after_check, "side_fore_left"},
    {"centre inside the head", m_center_inside, "base_neck_left"},
    {"NaN p_min", m_nan_pmin, "side_chin_left"},
    {"p_min > p_max", m_inverted_p, "side_chin_left"},
    {"Ri >= Ro", m_ri_ge_ro, "side_chin_right"},
    {"NaN C1", m_nan_c1, "side_chin_right"},
    {"NaN stretch_max", m_nan_smax, "stretch_max"},
    {"rate_max 0", m_rate0, "rate_max"},
    {"rate_max NaN", m_rate_nan, "rate_max"},
    {"NaN semi-axis", m_nan_axis, "semi"},
    {"NaN pivot", m_nan_pivot, "pivot"},
};

static void invalid_layouts(void **st)
{
    (void)st;
    for (size_t i = 0; i < sizeof layout_cases / sizeof layout_cases[0]; ++i) {
        hp_layout L;
        assert_int_equal(lf_layout(&L), HP_OK);
        layout_cases[i].mut(&L);
        for (int bi = 0; bi < 4; ++bi) {
            hp_settings s;
            hp_settings_default(&s);
            s.backend = rel_backends[bi];
            hp_diag d = {{0}};
            hp_planner *p = (hp_planner *)&d;
            hp_error e = hp_planner_create(&L, &s, &p, &d);
            if (bi == 0)
                print_message("layout %-24s -> %-16s '%s'\n", layout_cases[i].what,
                              hp_error_name(e), d.text);
            assert_int_not_equal(e, HP_OK);
            assert_null(p);
            assert_names(d.text, layout_cases[i].names, layout_cases[i].what);
        }
    }
}

/* ---- invalid settings ---- */

typedef void (*settings_mut)(hp_settings *s);
static void s_backend_hi(hp_settings *s) { s->backend = (hp_backend)99; }
static void s_backend_neg(hp_settings *s) { s->backend = (hp_backend)-1; }
static void s_level(hp_settings *s) { s->level = (hp_level)7; }
static void s_lt0(hp_settings *s) { s->level_tolerance = 0; }
static void s_ltnan(hp_settings *s) { s->level_tolerance = NAN; }
static void s_atneg(hp_settings *s) { s->auto_trans = -1e-3; }
static void s_atnan(hp_settings *s) { s->auto_trans = NAN; }
static void s_arinf(hp_settings *s) { s->auto_rot = INFINITY; }
static void s_arnan(hp_settings *s) { s->auto_rot = NAN; }
static void s_tol0(hp_settings *s) { s->tolerance = 0; }
static void s_tolnan(hp_settings *s) { s->tolerance = NAN; }
static void s_tolinf(hp_settings *s) { s->tolerance = INFINITY; }
static void s_it0(hp_settings *s) { s->max_iter = 0; }
static void s_itneg(hp_settings *s) { s->max_iter = -5; }
static void s_time0(hp_settings *s) { s->max_time = 0; }
static void s_timenan(hp_settings *s) { s->max_time = NAN; }
static void s_timeinf(hp_settings *s) { s->max_time = INFINITY; }
static void s_w0(hp_settings *s) { s->weight_mm_per_deg = 0; }
static void s_wnan(hp_settings *s) { s->weight_mm_per_deg = NAN; }
static void s_muneg(hp_settings *s) { s->mu = -1e-9; }
static void s_munan(hp_settings *s) { s->mu = NAN; }
static void s_rate2(hp_settings *s) { s->use_rate_limits = 2; }
static void s_warmneg(hp_settings *s) { s->warm_start = -1; }
static void s_w_tiny(hp_settings *s) { s->weight_mm_per_deg = 1e-200; }
static void s_time_huge(hp_settings *s) { s->max_time = 1e9; }

static const struct {
    const char *what;
    settings_mut mut;
    const char *names;
} settings_cases[] = {
    {"backend 99", s_backend_hi, "backend"},
    {"backend -1", s_backend_neg, "backend"},
    {"level 7", s_level, "level"},
    {"level_tolerance 0", s_lt0, "level_tolerance"},
    {"level_tolerance NaN", s_ltnan, "level_tolerance"},
    {"auto_trans < 0", s_atneg, "auto_trans"},
    {"auto_trans NaN", s_atnan, "auto_trans"},
    {"auto_rot inf", s_arinf, "auto_rot"},
    {"auto_rot NaN", s_arnan, "auto_rot"},
    {"tolerance 0", s_tol0, "tolerance"},
    {"tolerance NaN", s_tolnan, "tolerance"},
    {"tolerance inf", s_tolinf, "tolerance"},
    {"max_iter 0", s_it0, "max_iter"},
    {"max_iter < 0", s_itneg, "max_iter"},
    {"max_time 0", s_time0, "max_time"},
    {"max_time NaN", s_timenan, "max_time"},
    {"max_time inf", s_timeinf, "max_time"},
    {"weight 0", s_w0, "weight_mm_per_deg"},
    {"weight NaN", s_wnan, "weight_mm_per_deg"},
    {"mu < 0", s_muneg, "mu"},
    {"mu NaN", s_munan, "mu"},
    {"use_rate_limits 2", s_rate2, "use_rate_limits"},
    {"warm_start -1", s_warmneg, "warm_start"},
    {"weight 1e-200 (its inverse square overflows)", s_w_tiny, "weight_mm_per_deg"},
    {"max_time 1e9", s_time_huge, "max_time"},
};

static void invalid_settings(void **st)
{
    (void)st;
    hp_layout L;
    assert_int_equal(lf_layout(&L), HP_OK);
    for (size_t i = 0; i < sizeof settings_cases / sizeof settings_cases[0]; ++i) {
        hp_settings s;
        hp_settings_default(&s);
        settings_cases[i].mut(&s);
        hp_diag d = {{0}};
        assert_int_equal(hp_settings_validate(&s, &d), HP_ERR_INVALID);
        assert_names(d.text, settings_cases[i].names, settings_cases[i].what);
        hp_planner *p = (hp_planner *)&d;
        hp_diag d2 = {{0}};
        assert_int_equal(hp_planner_create(&L, &s, &p, &d2), HP_ERR_INVALID);
        assert_null(p);
        assert_string_equal(d.text, d2.text);
        print_message("settings %-20s -> invalid-argument '%s'\n", settings_cases[i].what, d.text);
    }
}

static void destroy_twice_separate(void **st)
{
    (void)st;
    hp_layout L;
    assert_int_equal(lf_layout(&L), HP_OK);
    for (int bi = 0; bi < 4; ++bi) {
        hp_planner *a = rel_planner(&L, rel_backends[bi], HP_LEVEL_SURFACE, INFINITY, 0);
        hp_planner *b = rel_planner(&L, rel_backends[bi], HP_LEVEL_SURFACE, INFINITY, 0);
        assert_non_null(a);
        assert_non_null(b);
        assert_true(a != b);
        hp_planner_destroy(a);
        hp_planner_destroy(b);
        hp_planner_destroy(NULL);
        hp_planner_destroy(NULL);
    }
}

static void bad_previous_pressures(void **st)
{
    (void)st;
    hp_layout L;
    assert_int_equal(lf_layout(&L), HP_OK);
    for (int bi = 0; bi < 4; ++bi) {
        hp_planner *p = rel_planner(&L, rel_backends[bi], HP_LEVEL_PLANE, 400.0, 0);
        assert_non_null(p);
        rel_ctx c;
        rel_ctx_init(&c, p);
        rel_ctx_capture_safe(&c, p);
        hp_result safe0 = c.safe;
        const double bad[] = {NAN, INFINITY, -INFINITY, -5001.0, 10001.0, 1e300, -1e300};
        for (size_t v = 0; v < sizeof bad / sizeof bad[0]; ++v)
            for (int k = 0; k < L.n; k += 3) {
                double P[HP_MAX_BLADDERS] = {0};
                P[k] = bad[v];
                assert_int_equal(hp_planner_set_previous(p, P), HP_ERR_INVALID);
                assert_names(hp_planner_error(p), "set_previous", "set_previous");
                assert_names(hp_planner_error(p), L.bladders[k].name, "set_previous");
            }
        /* Nothing changed: the safe output is still the nominal answer. */
        rel_ctx_capture_safe(&c, p);
        for (int k = 0; k < L.n; ++k)
            assert_memory_equal(&c.safe.bladders[k].pressure, &safe0.bladders[k].pressure,
                                sizeof(double));
        /* Extreme but valid pressures (a far plan's answer: bladders on their pressure and
         * stretch bounds) are accepted and become the safe output. */
        hp_planner *q = rel_planner(&L, HP_BACKEND_REALTIME, HP_LEVEL_PLANE, INFINITY, 0);
        const double far[6] = {0.03, -0.03, 0.03, 0.3, -0.3, 0.3};
        hp_result fr;
        assert_int_equal(hp_plan(q, far, &fr), HP_OK);
        hp_planner_destroy(q);
        double P[HP_MAX_BLADDERS];
        for (int k = 0; k < L.n; ++k) P[k] = fr.bladders[k].pressure;
        assert_int_equal(hp_planner_set_previous(p, P), HP_OK);
        rel_ctx_capture_safe(&c, p);
        for (int k = 0; k < L.n; ++k) assert_true(c.safe.bladders[k].pressure == P[k]);
        hp_planner_destroy(p);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(null_arguments),         cmocka_unit_test(invalid_layouts),
        cmocka_unit_test(invalid_settings),       cmocka_unit_test(destroy_twice_separate),
        cmocka_unit_test(bad_previous_pressures),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
