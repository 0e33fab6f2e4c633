/* The bad-scene catalogue (tests/scenes_bad/, expectations in tests/scene/bad_cases.txt):
 * every malformed file is refused with its exact message — file, line, column, key path —
 * and leaves the output scene all zero. Plus what a file cannot express: the size limit,
 * NULL arguments, missing files, and robustness against truncated and mutated scenes. */
#include "support/test_util.h"

#include "headplan/hp_scene.h"

#include <dirent.h>
#include <stdlib.h>
#include <string.h>

#define BAD HP_SOURCE_DIR "/tests/scenes_bad/"
#define TABLE HP_SOURCE_DIR "/tests/scene/bad_cases.txt"

static int all_zero(const hp_scene *s)
{
    const unsigned char *p = (const unsigned char *)s;
    for (size_t i = 0; i < sizeof *s; ++i)
        if (p[i]) return 0;
    return 1;
}

static hp_scene scene; /* large: keep it off the stack */

/* Trims spaces at both ends in place. */
static char *trim(char *s)
{
    while (*s == ' ') ++s;
    size_t n = strlen(s);
    while (n && (s[n - 1] == ' ' || s[n - 1] == '\n' || s[n - 1] == '\r')) s[--n] = '\0';
    return s;
}

static void test_catalogue(void **state)
{
    (void)state;
    FILE *f = fopen(TABLE, "r");
    assert_non_null(f);
    char line[1024];
    int cases = 0, failures = 0;
    static char listed[200][128];
    while (fgets(line, sizeof line, f)) {
        if (line[0] == '#' || line[0] == '\n') continue;
        char *bar = strstr(line, " | ");
        assert_non_null(bar);
        *bar = '\0';
        char *file = trim(line), *want = trim(bar + 3);
        assert_true(cases < 200 && strlen(file) < 128);
        strcpy(listed[cases++], file);
        char path[512];
        snprintf(path, sizeof path, "%s%s", BAD, file);
        memset(&scene, 0xA5, sizeof scene); /* the parser must clear it */
        hp_diag d = {{0}};
        hp_error e = hp_scene_load(path, &scene, &d);
        if (e == HP_OK || !strstr(d.text, want) || !all_zero(&scene)) {
            print_error("%s: error %d, message\n  got:  %s\n  want: %s\n  zeroed: %d\n", file,
                        (int)e, d.text, want, all_zero(&scene));
            ++failures;
        }
        /* every message is one line starting with the path, then ':LINE:COL: ' */
        assert_null(strchr(d.text, '\n'));
        assert_true(strncmp(d.text, path, strlen(path)) == 0);
    }
    fclose(f);
    assert_int_equal(failures, 0);
    assert_true(cases >= 30);

    /* every file of the catalogue has its expectation */
    DIR *dir = opendir(BAD);
    assert_non_null(dir);
    struct dirent *ent;
    while ((ent = readdir(dir))) {
        if (ent->d_name[0] == '.') continue;
        int found = 0;
        for (int i = 0; i < cases; ++i) found |= strcmp(listed[i], ent->d_name) == 0;
        if (!found) print_error("%s has no line in bad_cases.txt\n", ent->d_name);
        assert_true(found);
    }
    closedir(dir);
}

static void test_size_limit_and_arguments(void **state)
{
    (void)state;
    hp_diag d = {{0}};
    /* one byte over the limit: refused before parsing, whatever the content */
    size_t big = HP_SCENE_MAX_BYTES + 1;
    char *text = malloc(big);
    assert_non_null(text);
    memset(text, '#', big);
    assert_int_equal(hp_scene_parse(text, big, "big.yaml", &scene, &d), HP_ERR_PARSE);
    assert_non_null(strstr(d.text, "big.yaml: larger than the 1 MiB limit"));
    /* the same through a file */
    char path[512];
    snprintf(path, sizeof path, "%s/scene_too_large.yaml", HP_BINARY_DIR);
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(text, 1, big, f), big);
    fclose(f);
    free(text);
    assert_int_equal(hp_scene_load(path, &scene, &d), HP_ERR_PARSE);
    assert_non_null(strstr(d.text, "larger than the 1 MiB limit"));
    assert_true(all_zero(&scene));
    remove(path);

    assert_int_equal(hp_scene_load(BAD "no_such_file.yaml", &scene, &d), HP_ERR_IO);
    assert_non_null(strstr(d.text, "no_such_file.yaml: cannot open"));
    assert_int_equal(hp_scene_load(NULL, &scene, &d), HP_ERR_NULL);
    assert_int_equal(hp_scene_load(BAD "empty.yaml", NULL, &d), HP_ERR_NULL);
    assert_int_equal(hp_scene_parse(NULL, 0, "x", &scene, NULL), HP_ERR_NULL);
    assert_int_equal(hp_scene_parse("", 0, NULL, &scene, &d), HP_ERR_PARSE);
    assert_non_null(strstr(d.text, "<scene>:1:1: headplan_scene: empty file"));
    /* an embedded NUL byte ends nothing early: the text is refused, not truncated */
    static const char nul[] = "headplan_scene: 1\nname: a\0b\n";
    assert_int_not_equal(hp_scene_parse(nul, sizeof nul - 1, "nul.yaml", &scene, &d), HP_OK);
}

/* Parsing from memory gives the same scene as loading the file; the text need not be
 * NUL-terminated (the copy below has no terminator inside len). */
static void test_parse_equals_load(void **state)
{
    (void)state;
    static hp_scene a, b;
    hp_diag d = {{0}};
    const char *path = HP_SOURCE_DIR "/scenarios/default.yaml";
    size_t len;
    char *text = hp_test_read_all(path, &len);
    char *exact = malloc(len);
    assert_non_null(exact);
    memcpy(exact, text, len);
    assert_int_equal(hp_scene_load(path, &a, &d), HP_OK);
    assert_int_equal(hp_scene_parse(exact, len, path, &b, &d), HP_OK);
    assert_memory_equal(&a, &b, sizeof a);
    free(exact);
    free(text);
}

/* Every prefix of a valid scene and a few thousand seeded byte mutations: each parse either
 * succeeds or fails with a one-line message and a zeroed scene; never a crash (this test
 * runs under AddressSanitizer in the sanitizer build). */
static void test_truncation_and_mutation(void **state)
{
    (void)state;
    size_t len;
    char *text = hp_test_read_all(HP_SOURCE_DIR "/scenarios/default.yaml", &len);
    hp_diag d;
    int refused = 0;
    for (size_t n = 0; n < len; ++n) {
        d.text[0] = '\0';
        hp_error e = hp_scene_parse(text, n, "cut.yaml", &scene, &d);
        if (e != HP_OK) {
            ++refused;
            assert_true(all_zero(&scene));
            assert_true(strncmp(d.text, "cut.yaml", 8) == 0);
        }
    }
    assert_true(refused > 0);
    static const char alphabet[] = "-:[]{},&*!|>'\"#%@`.0123456789eE \n\tabc";
    unsigned long x = 12345; /* LCG: a fixed sequence */
    char *m = malloc(len);
    assert_non_null(m);
    for (int trial = 0; trial < 3000; ++trial) {
        memcpy(m, text, len);
        for (int k = 0; k < 1 + trial % 3; ++k) {
            x = (1103515245UL * x + 12345UL) & 0x7fffffffUL;
            size_t pos = x % len;
            x = (1103515245UL * x + 12345UL) & 0x7fffffffUL;
            m[pos] = alphabet[x % (sizeof alphabet - 1)];
        }
        hp_error e = hp_scene_parse(m, len, "mut.yaml", &scene, &d);
        if (e != HP_OK) {
            assert_true(all_zero(&scene));
            assert_null(strchr(d.text, '\n'));
        }
    }
    free(m);
    free(text);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_catalogue),
        cmocka_unit_test(test_size_limit_and_arguments),
        cmocka_unit_test(test_parse_equals_load),
        cmocka_unit_test(test_truncation_and_mutation),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
