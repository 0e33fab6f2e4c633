/* The level names have one home (hp_level_name's table, and "load" for the scene's load
 * level): `headplan solve --help` lists exactly those names, and the messages for an
 * unknown level (solve's --level, a scene's model.level) list the same ones. */
#define _POSIX_C_SOURCE 200809L /* popen */
#include "support/test_util.h"

#include "headplan/headplan.h"

#include <stdio.h>
#include <string.h>

/* Every name the table knows, in order: the contact levels, then "load". */
static int table(const char *names[8])
{
    int n = 0;
    for (int l = HP_LEVEL_LINEAR; l <= HP_LEVEL_AUTO; ++l) names[n++] = hp_level_name((hp_level)l);
    names[n++] = "load";
    return n;
}

/* The words of list (separated by ", " or " or ") into words[], returns their count. */
static int split(char *list, char *words[16])
{
    int n = 0;
    for (char *t = strtok(list, ", "); t && n < 16; t = strtok(NULL, ", "))
        if (strcmp(t, "or") != 0) words[n++] = t;
    return n;
}

static void expect_table(char *list, const char *where)
{
    const char *names[8];
    char *words[16];
    int n = table(names), m = split(list, words);
    if (m != n) print_error("%s: %d names, the table has %d\n", where, m, n);
    assert_int_equal(m, n);
    for (int i = 0; i < n; ++i) {
        if (strcmp(words[i], names[i]) != 0)
            print_error("%s: name %d is '%s', the table's '%s'\n", where, i, words[i], names[i]);
        assert_string_equal(words[i], names[i]);
    }
}

/* The first line of cmd's output (stdout and stderr) holding key, copied into line. */
static void line_of(const char *cmd, const char *key, char *line, size_t len)
{
    FILE *p = popen(cmd, "r");
    assert_non_null(p);
    int found = 0;
    while (!found && fgets(line, (int)len, p)) found = strstr(line, key) != NULL;
    pclose(p);
    if (!found) print_error("no '%s' in the output of %s\n", key, cmd);
    assert_true(found);
}

static void test_help_and_messages_use_the_table(void **st)
{
    (void)st;
    char cmd[1024], line[1024];
    /* solve --help: "  --level NAME   contact model: linear, ..., auto or load (the ..." */
    snprintf(cmd, sizeof cmd, "'%s/headplan' solve --help 2>&1", HP_BINARY_DIR);
    line_of(cmd, "--level NAME   contact model: ", line, sizeof line);
    char *from = strstr(line, "contact model: ");
    assert_non_null(from);
    from += strlen("contact model: ");
    char *to = strstr(from, " (");
    if (!to) to = from + strcspn(from, "\n");
    *to = '\0';
    expect_table(from, "solve --help");
    /* solve --level exact: "--level: unknown level 'exact' (NAMES)" */
    snprintf(cmd, sizeof cmd, "'%s/headplan' solve '%s/scenarios/default.yaml' --level exact 2>&1",
             HP_BINARY_DIR, HP_SOURCE_DIR);
    line_of(cmd, "unknown level", line, sizeof line);
    from = strstr(line, "'exact' (");
    assert_non_null(from);
    from += strlen("'exact' (");
    from[strcspn(from, ")")] = '\0';
    expect_table(from, "solve --level exact");
    /* A scene's model.level: the library's message. */
    static hp_scene sc;
    hp_diag d = {{0}};
    const char *text = "headplan_scene: 1\nname: n\nhead: {shape: sphere, radius_mm: 90}\n"
                       "bladders:\n  - {name: a, touch_dir: [0, 0, -1], Ri_mm: 27, Ro_mm: 30,\n"
                       "     material: {convention: paper, C1_pa: 1.1e4, C2_pa: 2.2e4},\n"
                       "     pressure_min_kpa: -5, pressure_max_kpa: 10, stretch_min: 0.8,\n"
                       "     stretch_max: 1.3}\nmodel: {level: exact}\n";
    assert_int_not_equal(hp_scene_parse(text, strlen(text), "s.yaml", &sc, &d), HP_OK);
    from = strstr(d.text, "(known: ");
    if (!from) print_error("%s\n", d.text);
    assert_non_null(from);
    from += strlen("(known: ");
    from[strcspn(from, ")")] = '\0';
    expect_table(from, "model.level");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_help_and_messages_use_the_table),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
