/* The public planner API: settings defaults and validator messages, enum names, the
 * lifecycle on bad input, the safe output on failure, reset / set_previous, and the backend
 * table. */
#include "support/test_util.h"
#include "support/layout_fixture.h"

#include <stdlib.h>

/* Every field of the settings struct: the defaults function must set each one. */
#define SENTINEL 0xA5
#define FIELD_KEPT_SENTINEL(s, f) field_is_sentinel(&(s).f, sizeof((s).f))
static int field_is_sentinel(const void *p, size_t n)
{
    const unsigned char *c = p;
    for (size_t i = 0; i < n; ++i)
        if (c[i] != SENTINEL) return 0;
    return 1;
}

static void test_settings_defaults(void **st)
{
    (void)st;
    hp_settings s;
    memset(&s, SENTINEL, sizeof s);
    hp_settings_default(&s);
    assert_false(FIELD_KEPT_SENTINEL(s, backend));
    assert_false(FIELD_KEPT_SENTINEL(s, level));
    assert_false(FIELD_KEPT_SENTINEL(s, level_tolerance));
    assert_false(FIELD_KEPT_SENTINEL(s, auto_trans));
    assert_false(FIELD_KEPT_SENTINEL(s, auto_rot));
    assert_false(FIELD_KEPT_SENTINEL(s, tolerance));
    assert_false(FIELD_KEPT_SENTINEL(s, max_iter));
    assert_false(FIELD_KEPT_SENTINEL(s, max_time));
    assert_false(FIELD_KEPT_SENTINEL(s, weight_mm_per_deg));
    assert_false(FIELD_KEPT_SENTINEL(s, mu));
    assert_false(FIELD_KEPT_SENTINEL(s, use_rate_limits));
    assert_false(FIELD_KEPT_SENTINEL(s, warm_start));
    assert_false(FIELD_KEPT_SENTINEL(s, load.mass));
    assert_false(FIELD_KEPT_SENTINEL(s, load.com));
    assert_false(FIELD_KEPT_SENTINEL(s, load.gravity));
    assert_false(FIELD_KEPT_SENTINEL(s, load_geometry));
    assert_false(FIELD_KEPT_SENTINEL(s, load_tiebreak));
    assert_false(FIELD_KEPT_SENTINEL(s, restarts));
    assert_false(FIELD_KEPT_SENTINEL(s, auto_pose));
    /* auto_pose is the last field (the struct ends there, up to alignment), so a field
     * appended without a line above fails this test. (Backend-only switches are options of
     * the backend, hp_planner_set_option, not fields.) */
    size_t end = offsetof(hp_settings, auto_pose) + sizeof s.auto_pose;
    assert_int_equal(sizeof s, (end + _Alignof(hp_settings) - 1) / _Alignof(hp_settings) *
                                   _Alignof(hp_settings));
    assert_int_equal(s.backend, HP_DEFAULT_BACKEND);
    assert_int_equal(s.level, HP_DEFAULT_LEVEL);
    assert_true(s.tolerance == HP_DEFAULT_TOLERANCE);
    assert_int_equal(s.max_iter, HP_DEFAULT_MAX_ITER);
    assert_true(s.load.mass == 0.0); /* no load */
    assert_int_equal(s.load_geometry, HP_DEFAULT_LOAD_GEOMETRY);
    assert_int_equal(s.load_tiebreak, HP_DEFAULT_LOAD_TIEBREAK);
    assert_int_equal(s.restarts, HP_DEFAULT_RESTARTS);
    assert_int_equal(hp_settings_validate(&s, NULL), HP_OK);
    hp_settings_default(NULL); /* no crash */
}

/* The load level's settings: the load level needs a load; a stated load is checked by
 * hp_load_spec_validate; the geometry is a contact level; the tie-breaker one of the enum.
 * Each refusal names its field. */
static void test_settings_load(void **st)
{
    (void)st;
    hp_settings s;
    hp_diag d = {{0}};
    hp_settings_default(&s);
    s.level = HP_LEVEL_LOAD;
    assert_int_equal(hp_settings_validate(&s, &d), HP_ERR_INVALID);
    assert_non_null(strstr(d.text, "level: load needs a load"));
    s.load.mass = 3.6;
    s.load.gravity[2] = -HP_GRAVITY;
    assert_int_equal(hp_settings_validate(&s, NULL), HP_OK);
    s.load.mass = NAN;
    assert_int_equal(hp_settings_validate(&s, &d), HP_ERR_INVALID);
    assert_non_null(strstr(d.text, "mass"));
    s.load.mass = 3.6;
    s.load.gravity[2] = 0.0;
    assert_int_equal(hp_settings_validate(&s, &d), HP_ERR_INVALID);
    assert_non_null(strstr(d.text, "gravity"));
    s.load.gravity[2] = -HP_GRAVITY;
    s.load_geometry = HP_LEVEL_AUTO;
    assert_int_equal(hp_settings_validate(&s, &d), HP_ERR_INVALID);
    assert_non_null(strstr(d.text, "load_geometry"));
    s.load_geometry = HP_LEVEL_PLANE;
    s.load_tiebreak = HP_TIE_COUNT_;
    assert_int_equal(hp_settings_validate(&s, &d), HP_ERR_INVALID);
    assert_non_null(strstr(d.text, "load_tiebreak"));
    s.load_tiebreak = HP_TIE_PREVIOUS;
    assert_int_equal(hp_settings_validate(&s, NULL), HP_OK);
    s.level = 99;
    assert_int_equal(hp_settings_validate(&s, &d), HP_ERR_INVALID);
    assert_non_null(strstr(d.text, "level"));
}

typedef struct bad_case {
    const char *field;
    void (*spoil)(hp_settings *s);
} bad_case;

static void b_backend(hp_settings *s) { s->backend = (hp_backend)HP_BACKEND_COUNT_; }
static void b_level(hp_settings *s) { s->level = (hp_level)99; }
static void b_ltol(hp_settings *s) { s->level_tolerance = NAN; }
static void b_ltol0(hp_settings *s) { s->level_tolerance = 0.0; }
static void b_atrans(hp_settings *s) { s->auto_trans = -1e-3; }
static void b_arot(hp_settings *s) { s->auto_rot = INFINITY; }
static void b_tol(hp_settings *s) { s->tolerance = NAN; }
static void b_tol0(hp_settings *s) { s->tolerance = 0.0; }
/* A pose tolerance of 1e300 mm called an answer 17.7 mm short of its correction 'reached'. */
static void b_tol_huge(hp_settings *s) { s->tolerance = 1.0000001; }
static void b_iter(hp_settings *s) { s->max_iter = 0; }
static void b_time(hp_settings *s) { s->max_time = NAN; }
static void b_weight(hp_settings *s) { s->weight_mm_per_deg = -1.0; }
static void b_mu(hp_settings *s) { s->mu = NAN; }
static void b_rate(hp_settings *s) { s->use_rate_limits = 2; }
static void b_warm(hp_settings *s) { s->warm_start = -1; }
static void b_restarts(hp_settings *s) { s->restarts = -1; }
static void b_restarts_many(hp_settings *s) { s->restarts = 65; }

static void test_settings_validator(void **st)
{
    (void)st;
    const bad_case cases[] = {
        {"backend", b_backend},
        {"level", b_level},
        {"level_tolerance", b_ltol},
        {"level_tolerance", b_ltol0},
        {"auto_trans", b_atrans},
        {"auto_rot", b_arot},
        {"tolerance", b_tol},
        {"tolerance", b_tol0},
        {"tolerance", b_tol_huge},
        {"max_iter", b_iter},
        {"max_time", b_time},
        {"weight_mm_per_deg", b_weight},
        {"mu", b_mu},
        {"use_rate_limits", b_rate},
        {"warm_start", b_warm},
        {"restarts", b_restarts},
        {"restarts", b_restarts_many},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        hp_settings s;
        hp_settings_default(&s);
        cases[i].spoil(&s);
        hp_diag d = {{0}};
        assert_int_equal(hp_settings_validate(&s, &d), HP_ERR_INVALID);
        if (strncmp(d.text, cases[i].field, strlen(cases[i].field)) != 0)
            print_error("case %zu: message '%s' does not start with '%s'\n", i, d.text,
                        cases[i].field);
        assert_true(strncmp(d.text, cases[i].field, strlen(cases[i].field)) == 0);
        /* create refuses the same settings with the same message */
        hp_layout L;
        assert_int_equal(lf_layout(&L), HP_OK);
        hp_planner *p = (hp_planner *)&d; /* must be reset to NULL */
        hp_diag d2 = {{0}};
        assert_int_equal(hp_planner_create(&L, &s, &p, &d2), HP_ERR_INVALID);
        assert_null(p);
        assert_string_equal(d.text, d2.text);
    }
    assert_int_equal(hp_settings_validate(NULL, NULL), HP_ERR_NULL);
}

static void test_names(void **st)
{
    (void)st;
    for (int b = 0; b < HP_BACKEND_COUNT_; ++b) {
        hp_backend out = HP_BACKEND_COUNT_;
        assert_int_equal(hp_backend_parse(hp_backend_name((hp_backend)b), &out), HP_OK);
        assert_int_equal(out, b);
    }
    hp_backend out = HP_BACKEND_IPOPT;
    assert_int_equal(hp_backend_parse("Realtime", &out), HP_ERR_INVALID);
    assert_int_equal(hp_backend_parse("", &out), HP_ERR_INVALID);
    assert_int_equal(hp_backend_parse(NULL, &out), HP_ERR_NULL);
    assert_int_equal(out, HP_BACKEND_IPOPT);
    assert_string_equal(hp_backend_name((hp_backend)-1), "unknown");
    assert_string_equal(hp_backend_name(HP_BACKEND_COUNT_), "unknown");
    for (int a = 0; a < HP_STATUS_COUNT_; ++a) {
        assert_string_not_equal(hp_status_name((hp_status)a), "unknown");
        for (int b = 0; b < a; ++b)
            assert_string_not_equal(hp_status_name((hp_status)a), hp_status_name((hp_status)b));
    }
    assert_string_equal(hp_status_name(HP_STATUS_COUNT_), "unknown");
    assert_string_equal(hp_status_name(HP_STATUS_CLOSEST), "closest");
    for (int b = 0; b < HP_BIND_COUNT; ++b)
        assert_string_not_equal(hp_binding_name(1u << b), "unknown");
    assert_string_equal(hp_binding_name(HP_BIND_PRESSURE_MAX), "pressure_max");
    assert_string_equal(hp_binding_name(HP_BIND_PRESSURE_MIN | HP_BIND_RATE_UP), "unknown");
    assert_string_equal(hp_binding_name(0), "unknown");
}

static void test_create_bad_input(void **st)
{
    (void)st;
    hp_layout L;
    assert_int_equal(lf_layout(&L), HP_OK);
    hp_planner *p = NULL;
    hp_diag d = {{0}};
    assert_int_equal(hp_planner_create(NULL, NULL, &p, &d), HP_ERR_NULL);
    assert_int_equal(hp_planner_create(&L, NULL, NULL, &d), HP_ERR_NULL);
    hp_layout bad = L;
    bad.bladders[3].iab.Ri = bad.bladders[3].iab.Ro; /* Ri >= Ro */
    assert_int_not_equal(hp_planner_create(&bad, NULL, &p, &d), HP_OK);
    assert_null(p);
    assert_true(strstr(d.text, "base_skull_right") != NULL);
    hp_planner_destroy(NULL);
    assert_string_equal(hp_planner_error(NULL), "planner is NULL");
    assert_int_equal(hp_plan(NULL, NULL, NULL), HP_ERR_NULL);
    /* The planner validates its own copy; the caller's is left alone, byte for byte. */
    hp_layout raw = L;
    assert_int_equal(hp_planner_create(&raw, NULL, &p, &d), HP_OK);
    assert_memory_equal(&raw, &L, sizeof L);
    assert_int_equal(hp_planner_level(p), HP_LEVEL_LINEAR);
    hp_planner_destroy(p);
    /* auto resolves to a real level */
    hp_settings s;
    hp_settings_default(&s);
    s.level = HP_LEVEL_AUTO;
    assert_int_equal(hp_planner_create(&L, &s, &p, &d), HP_OK);
    assert_true(hp_planner_level(p) != HP_LEVEL_AUTO);
    hp_planner_destroy(p);
}

/* hp_planner_level_choice: for auto, the level chosen and the bounds auto compared, each as
 * hp_contact_error_bound gives it for the planner's auto range (%.3g, the text's format);
 * "" for a stated level; NULL and short buffers handled. */
static void test_level_choice(void **st)
{
    (void)st;
    hp_layout L;
    assert_int_equal(lf_layout(&L), HP_OK);
    hp_settings s;
    hp_settings_default(&s);
    s.level = HP_LEVEL_AUTO;
    hp_planner *p = NULL;
    hp_diag d = {{0}};
    assert_int_equal(hp_planner_create(&L, &s, &p, &d), HP_OK);
    char why[400], want[64];
    assert_int_equal(hp_planner_level_choice(p, why, sizeof why), HP_OK);
    snprintf(want, sizeof want, "auto chose %s: ", hp_level_name(hp_planner_level(p)));
    assert_true(strncmp(why, want, strlen(want)) == 0);
    /* the fixture's layout needs more than linear at the default tolerance and range */
    assert_int_not_equal(hp_planner_level(p), HP_LEVEL_LINEAR);
    {
        double b;
        assert_int_equal(hp_contact_error_bound(&L, HP_LEVEL_LINEAR, s.auto_trans, s.auto_rot, &b),
                         HP_OK);
        snprintf(want, sizeof want, "linear (%.3g mm)", b * 1e3);
        assert_non_null(strstr(why, want));
    }
    char small[8];
    assert_int_equal(hp_planner_level_choice(p, small, sizeof small), HP_OK);
    assert_int_equal(strlen(small), 7); /* truncated, terminated */
    hp_planner_destroy(p);
    s.level = HP_LEVEL_PLANE;
    assert_int_equal(hp_planner_create(&L, &s, &p, &d), HP_OK);
    assert_int_equal(hp_planner_level_choice(p, why, sizeof why), HP_OK);
    assert_string_equal(why, "");
    hp_planner_destroy(p);
    strcpy(why, "x");
    assert_int_equal(hp_planner_level_choice(NULL, why, sizeof why), HP_ERR_NULL);
    assert_string_equal(why, "");
    assert_int_equal(hp_planner_level_choice(NULL, NULL, 0), HP_ERR_NULL);
}

static void same_bladders(const hp_result *a, const hp_result *b)
{
    assert_int_equal(a->n, b->n);
    for (int k = 0; k < a->n; ++k) {
        assert_true(a->bladders[k].pressure == b->bladders[k].pressure);
        assert_true(a->bladders[k].ri == b->bladders[k].ri);
        assert_true(a->bladders[k].ro == b->bladders[k].ro);
    }
}

static void test_safe_output(void **st)
{
    (void)st;
    hp_layout L;
    assert_int_equal(lf_layout(&L), HP_OK);
    hp_planner *p = NULL;
    assert_int_equal(hp_planner_create(&L, NULL, &p, NULL), HP_OK);
    /* Before any plan the safe output is the nominal pose: every pressure 0 (the bladders
     * touch at their reference radii), inside the limits. */
    double nan6[6] = {NAN, 0, 0, 0, 0, 0};
    hp_result r, good;
    assert_int_equal(hp_plan(p, nan6, &r), HP_OK);
    assert_int_equal(r.status, HP_STATUS_INVALID_INPUT);
    assert_true(strstr(hp_planner_error(p), "x") != NULL);
    for (int k = 0; k < 8; ++k) assert_true(fabs(r.bladders[k].pressure) < 1e-9);
    double c[6] = {0.5, 0.2, -0.3, 0.2, 0.1, -0.2}, xi[6];
    lf_pose(c, xi);
    assert_int_equal(hp_plan(p, xi, &good), HP_OK);
    assert_int_equal(good.status, HP_STATUS_REACHED);
    assert_string_equal(hp_planner_error(p), "");
    /* After a valid plan: NaN, Inf, out of range and NULL all hold the previous answer. */
    const double bads[4][6] = {{0, 0, 0, 0, 0, NAN},
                               {0, INFINITY, 0, 0, 0, 0},
                               {0, 0, 0, -INFINITY, 0, 0},
                               {0, 0, 2.0, 0, 0, 0}};
    const char *const named[4] = {"yaw", "y", "pitch", "z"};
    for (int t = 0; t < 4; ++t) {
        assert_int_equal(hp_plan(p, bads[t], &r), HP_OK);
        assert_int_equal(r.status, HP_STATUS_INVALID_INPUT);
        assert_true(strstr(hp_planner_error(p), named[t]) != NULL);
        same_bladders(&r, &good);
        for (int i = 0; i < 6; ++i) assert_true(r.achieved[i] == good.achieved[i]);
    }
    assert_int_equal(hp_plan(p, NULL, &r), HP_ERR_NULL);
    assert_int_equal(r.status, HP_STATUS_INVALID_INPUT);
    same_bladders(&r, &good);
    /* reset: the nominal answer again */
    hp_planner_reset(p);
    assert_int_equal(hp_plan(p, nan6, &r), HP_OK);
    for (int k = 0; k < 8; ++k) assert_true(fabs(r.bladders[k].pressure) < 1e-9);
    /* set_previous: refused outside the limits, then becomes the safe output */
    double pr[8];
    for (int k = 0; k < 8; ++k) pr[k] = 1000.0 + 100.0 * k;
    pr[2] = 2e4;
    assert_int_equal(hp_planner_set_previous(p, pr), HP_ERR_INVALID);
    assert_true(strstr(hp_planner_error(p), "base_skull_left") != NULL);
    pr[2] = NAN;
    assert_int_equal(hp_planner_set_previous(p, pr), HP_ERR_INVALID);
    pr[2] = 1200.0;
    assert_int_equal(hp_planner_set_previous(p, pr), HP_OK);
    assert_int_equal(hp_plan(p, nan6, &r), HP_OK);
    for (int k = 0; k < 8; ++k) assert_true(r.bladders[k].pressure == pr[k]);
    hp_planner_destroy(p);
}

/* The direct chain answers for every backend: a reachable correction never reaches a
 * solver (0 iterations, raw code 0), whichever backend is configured. */
static void test_every_backend_direct_chain(void **st)
{
    (void)st;
    hp_layout L;
    assert_int_equal(lf_layout(&L), HP_OK);
    for (int b = 0; b < HP_BACKEND_COUNT_; ++b) {
        hp_settings s;
        hp_settings_default(&s);
        s.backend = (hp_backend)b;
        hp_planner *p = NULL;
        hp_diag d = {{0}};
        hp_error e = hp_planner_create(&L, &s, &p, &d);
        if (e != HP_OK) print_error("%s: %s\n", hp_backend_name(s.backend), d.text);
        assert_int_equal(e, HP_OK);
        double c[6] = {0.4, -0.3, 0.2, 0.1, 0.2, -0.1}, xi[6];
        lf_pose(c, xi);
        hp_result r;
        assert_int_equal(hp_plan(p, xi, &r), HP_OK);
        assert_int_equal(r.status, HP_STATUS_REACHED);
        assert_int_equal(r.iterations, 0);
        assert_int_equal(r.backend, b);
        assert_true(r.solve_time >= 0);
        hp_planner_destroy(p);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_settings_defaults),
        cmocka_unit_test(test_settings_validator),
        cmocka_unit_test(test_names),
        cmocka_unit_test(test_create_bad_input),
        cmocka_unit_test(test_level_choice),
        cmocka_unit_test(test_settings_load),
        cmocka_unit_test(test_safe_output),
        cmocka_unit_test(test_every_backend_direct_chain),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
