/* Every public enum with a name has one name table (common/names.h), and everything that
 * names its values reads it: each word of each table goes through the enum's name and parse
 * calls and back to the same value, a value outside the table is "unknown", text outside it
 * is refused, the tables have one word per value the headers count, and `headplan solve`
 * lists exactly the backend table in its --help and in its message for an unknown backend,
 * and a scene's unknown backend, shape, convention or rows kind is answered with its table. */
#define _POSIX_C_SOURCE 200809L /* popen */
#include "support/test_util.h"

#include "headplan/headplan.h"
#include "common/names.h"
#include "horizon/names.h"
#include "iab/names.h"
#include "kinematics/names.h"
#include "planner/names.h"
#include "scene/names.h"

#include <stdio.h>
#include <string.h>

/* One enum: its table, and its name and parse calls through int. */
typedef struct {
    const char *what;
    const char *const *words;
    const char *(*name)(int);
    hp_error (*parse)(const char *, int *); /* NULL: the enum has no parse call */
} enum_case;

#define NAME_OF(fn, type)                                                                          \
    static const char *fn##_i(int v) { return fn((type)v); }
#define PARSE_OF(fn, type)                                                                         \
    static hp_error fn##_i(const char *s, int *v)                                                  \
    {                                                                                              \
        type t;                                                                                    \
        hp_error e = fn(s, &t);                                                                    \
        if (e == HP_OK) *v = (int)t;                                                               \
        return e;                                                                                  \
    }
NAME_OF(hp_backend_name, hp_backend)
PARSE_OF(hp_backend_parse, hp_backend)
NAME_OF(hp_status_name, hp_status)
NAME_OF(hp_level_name, hp_level)
PARSE_OF(hp_level_parse, hp_level)
NAME_OF(hp_head_shape_name, hp_head_shape)
PARSE_OF(hp_head_shape_parse, hp_head_shape)
NAME_OF(hp_material_convention_name, hp_material_convention)
PARSE_OF(hp_material_convention_parse, hp_material_convention)
NAME_OF(hp_prediction_name, hp_prediction)
PARSE_OF(hp_prediction_parse, hp_prediction)
NAME_OF(hp_trace_rows_name, hp_trace_rows)
PARSE_OF(hp_trace_rows_parse, hp_trace_rows)
NAME_OF(hp_trace_format_name, hp_trace_format)
PARSE_OF(hp_trace_format_parse, hp_trace_format)
NAME_OF(hp_trace_form_name, hp_trace_form)
NAME_OF(hp_scene_kind_name, hp_scene_kind)
NAME_OF(hp_error_name, hp_error)
NAME_OF(hp_load_law_name, hp_load_law)
PARSE_OF(hp_load_law_parse, hp_load_law)
static const char *binding_i(int v) { return hp_binding_name(1u << v); }

static const enum_case CASES[] = {
    {"backend", hpi_backend_words, hp_backend_name_i, hp_backend_parse_i},
    {"status", hpi_status_words, hp_status_name_i, NULL},
    {"binding", hpi_binding_words, binding_i, NULL},
    {"level", hpi_level_words, hp_level_name_i, hp_level_parse_i},
    {"head shape", hpi_head_shape_words, hp_head_shape_name_i, hp_head_shape_parse_i},
    {"convention", hpi_material_convention_words, hp_material_convention_name_i,
     hp_material_convention_parse_i},
    {"prediction", hpi_prediction_words, hp_prediction_name_i, hp_prediction_parse_i},
    {"trace rows", hpi_trace_rows_words, hp_trace_rows_name_i, hp_trace_rows_parse_i},
    {"trace format", hpi_trace_format_words, hp_trace_format_name_i, hp_trace_format_parse_i},
    {"trace form", hpi_trace_form_words, hp_trace_form_name_i, NULL},
    {"scene kind", hpi_scene_kind_words, hp_scene_kind_name_i, NULL},
    {"error", hpi_error_words, hp_error_name_i, NULL},
    {"load law", hpi_load_law_words, hp_load_law_name_i, hp_load_law_parse_i},
};

static void test_round_trip(void **st)
{
    (void)st;
    for (size_t c = 0; c < sizeof CASES / sizeof *CASES; ++c) {
        const enum_case *k = CASES + c;
        int n = hpi_names_count(k->words);
        assert_true(n >= 2);
        for (int v = 0; v < n; ++v) {
            if (strcmp(k->name(v), k->words[v]) != 0)
                print_error("%s %d: name '%s', table '%s'\n", k->what, v, k->name(v), k->words[v]);
            assert_string_equal(k->name(v), k->words[v]);
            for (int u = 0; u < v; ++u) assert_string_not_equal(k->words[u], k->words[v]);
            if (k->parse) {
                int back = -1;
                assert_int_equal(k->parse(k->words[v], &back), HP_OK);
                assert_int_equal(back, v);
            }
        }
        if (k->name != binding_i) {
            assert_string_equal(k->name(n), "unknown");
            assert_string_equal(k->name(-1), "unknown");
        }
        if (k->parse) {
            int keep = 77;
            assert_int_equal(k->parse("", &keep), HP_ERR_INVALID);
            assert_int_equal(k->parse("unknown", &keep), HP_ERR_INVALID);
            assert_int_equal(k->parse(NULL, &keep), HP_ERR_NULL);
            assert_int_equal(keep, 77);
        }
    }
    /* A parse call with nowhere to put its answer refuses, whatever the text. */
    assert_int_equal(hp_backend_parse("realtime", NULL), HP_ERR_NULL);
    assert_int_equal(hp_level_parse("plane", NULL), HP_ERR_NULL);
    assert_int_equal(hp_head_shape_parse("sphere", NULL), HP_ERR_NULL);
    assert_int_equal(hp_material_convention_parse("fe", NULL), HP_ERR_NULL);
    assert_int_equal(hp_prediction_parse("hold", NULL), HP_ERR_NULL);
    assert_int_equal(hp_trace_rows_parse("deviation", NULL), HP_ERR_NULL);
    assert_int_equal(hp_trace_format_parse("csv", NULL), HP_ERR_NULL);
    assert_int_equal(hp_load_law_parse("fem", NULL), HP_ERR_NULL);
    /* One word per value the public headers count. */
    assert_int_equal(hpi_names_count(hpi_backend_words), HP_BACKEND_COUNT_);
    assert_int_equal(hpi_names_count(hpi_error_words), HP_ERR_COUNT_);
    assert_int_equal(hpi_names_count(hpi_status_words), HP_STATUS_COUNT_);
    assert_int_equal(hpi_names_count(hpi_binding_words), HP_BIND_COUNT);
    assert_int_equal(hpi_names_count(hpi_level_words), HP_LEVEL_LOAD + 1);
    assert_int_equal(hpi_names_count(hpi_load_tiebreak_words), HP_TIE_COUNT_);
    assert_int_equal(hpi_names_count(hpi_load_law_words), HP_LOAD_LAW_COUNT_);
}

/* The table's words joined as "a, b, c". */
static const char *joined(const char *const *words, char *buf, size_t len)
{
    return hpi_names_join(words, NULL, buf, len);
}

/* The output of cmd (stdout and stderr) into out. */
static void run(const char *cmd, char *out, size_t len)
{
    FILE *p = popen(cmd, "r");
    assert_non_null(p);
    size_t n = fread(out, 1, len - 1, p);
    out[n] = '\0';
    pclose(p);
}

static void test_cli_lists_the_backend_table(void **st)
{
    (void)st;
    char cmd[1024], out[8192], list[256], want[300];
    snprintf(cmd, sizeof cmd, "'%s/headplan' solve '%s/scenarios/default.yaml' --backend x 2>&1",
             HP_BINARY_DIR, HP_SOURCE_DIR);
    run(cmd, out, sizeof out);
    snprintf(want, sizeof want, "unknown backend 'x' (%s)\n",
             joined(hpi_backend_words, list, sizeof list));
    if (!strstr(out, want)) print_error("got: %swant: %s", out, want);
    assert_non_null(strstr(out, want));
    /* --help names every backend, and no word that is none ("--backend NAME ... " up to the
     * next option). */
    snprintf(cmd, sizeof cmd, "'%s/headplan' solve --help 2>&1", HP_BINARY_DIR);
    run(cmd, out, sizeof out);
    char *from = strstr(out, "\n  --backend NAME");
    assert_non_null(from);
    char *to = strstr(from + 1, "\n  --");
    assert_non_null(to);
    *to = '\0';
    for (int i = 0; hpi_backend_words[i]; ++i) {
        if (!strstr(from, hpi_backend_words[i]))
            print_error("solve --help does not name backend %s\n", hpi_backend_words[i]);
        assert_non_null(strstr(from, hpi_backend_words[i]));
    }
}

/* A scene whose KEY is "x": the reader's message lists exactly the table. */
static void scene_word(const char *before, const char *after, const char *const *words)
{
    static hp_scene sc;
    char text[2048], list[256], want[300];
    snprintf(text, sizeof text, "%sx%s", before, after);
    hp_diag d = {{0}};
    assert_int_not_equal(hp_scene_parse(text, strlen(text), "s.yaml", &sc, &d), HP_OK);
    snprintf(want, sizeof want, "'x' (known: %s)", joined(words, list, sizeof list));
    if (!strstr(d.text, want)) print_error("got: %s\nwant: %s\n", d.text, want);
    assert_non_null(strstr(d.text, want));
}

static void test_scene_reader_uses_the_tables(void **st)
{
    (void)st;
    const char *head = "headplan_scene: 1\nname: n\nhead: {shape: ";
    const char *rest = ", radius_mm: 90}\nbladders:\n  - {name: a, touch_dir: [0, 0, -1], "
                       "Ri_mm: 27, Ro_mm: 30,\n     material: {convention: ";
    const char *tail = ", C1_pa: 1.1e4, C2_pa: 2.2e4},\n     pressure_min_kpa: -5, "
                       "pressure_max_kpa: 10, stretch_min: 0.8,\n     stretch_max: 1.3}\n";
    char a[1024], b[1024];
    snprintf(b, sizeof b, "%spaper%s", rest, tail);
    scene_word(head, b, hpi_head_shape_words);
    snprintf(a, sizeof a, "%ssphere%s", head, rest);
    scene_word(a, tail, hpi_material_convention_words);
    snprintf(a, sizeof a, "%ssphere%spaper%ssolver: {backend: ", head, rest, tail);
    scene_word(a, "}\n", hpi_backend_words);
    snprintf(a, sizeof a, "%ssphere%spaper%strace: {file: t.csv, rows: ", head, rest, tail);
    scene_word(a, "}\n", hpi_trace_rows_words);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_round_trip),
        cmocka_unit_test(test_cli_lists_the_backend_table),
        cmocka_unit_test(test_scene_reader_uses_the_tables),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
